// Images from Python: denoising, bloom, the 8-bit display encoding and the EXR writer the
// CLI uses, so the job service's tiles, image.png and image.exr match
// rtrender's output.
#include "rtcore_image.h"

#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <nanobind/ndarray.h>
#include <nanobind/stl/map.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/string.h>

#include "image/aov.h"
#include "image/bloom.h"
#include "image/denoise.h"
#include "image/oidn_library.h"
#include "image/display.h"
#include "image/image.h"
#include "rtcore_convert.h"

namespace rtcore {
namespace {

using namespace nb::literals;
using Rgb = nb::ndarray<const float, nb::c_contig, nb::device::cpu>;
using Layer = nb::ndarray<const float, nb::c_contig, nb::device::cpu>;

// The (height, width) of an (height, width, 3) array; ValueError naming the
// function and the shape it got otherwise.
std::pair<size_t, size_t> rgb_size(const Rgb& rgb, const char* what) {
    if (rgb.ndim() != 3 || rgb.shape(2) != 3) {
        std::string shape;
        for (size_t i = 0; i < rgb.ndim(); ++i) shape += (i ? ", " : "") + std::to_string(rgb.shape(i));
        throw std::invalid_argument(std::string(what) + "(): expected an (height, width, 3) array, got shape (" +
                                    shape + ")");
    }
    return {rgb.shape(0), rgb.shape(1)};
}

nb::ndarray<nb::numpy, uint8_t> encode_srgb8(const Rgb& rgb, nb::handle settings) {
    const auto [h, w] = rgb_size(rgb, "encode_srgb8");
    const rt::DisplayTransform display =
        settings.is_none() ? rt::DisplayTransform{}
                           : rt::DisplayTransform::from(read_message<rt::RenderSettings>(settings, "settings"));
    std::vector<uint8_t> rgba(h * w * 4);
    {
        nb::gil_scoped_release release;
        rt::encode_srgb8({rgb.data(), h * w * 3}, display, rgba);
    }
    return to_numpy(std::move(rgba), {h, w, 4});
}

nb::ndarray<nb::numpy, float> apply_bloom(const Rgb& rgb, nb::handle settings) {
    const auto [h, w] = rgb_size(rgb, "apply_bloom");
    const auto bloom = read_message<rt::RenderSettings>(settings, "settings");
    rt::Image image(static_cast<uint32_t>(w), static_cast<uint32_t>(h));
    {
        nb::gil_scoped_release release;
        std::copy(rgb.data(), rgb.data() + h * w * 3, image.rgb.begin());
        rt::apply_bloom(image, bloom);
    }
    return to_numpy(std::move(image.rgb), {h, w, 3});
}

void write_exr(const std::string& path, const Rgb& color, const std::map<std::string, Layer>& aux,
               std::optional<Rgb> noisy) {
    const auto [height, width] = rgb_size(color, "write_exr");
    const uint32_t h = uint32_t(height), w = uint32_t(width);
    const size_t pixels = size_t(w) * h;
    rt::Image image(w, h);
    std::copy(color.data(), color.data() + pixels * 3, image.rgb.begin());

    std::vector<rt::AuxOutput> outputs;
    rt::Image before;
    if (noisy) {
        if (rgb_size(*noisy, "write_exr") != std::pair<size_t, size_t>(height, width))
            throw std::invalid_argument("write_exr: the noisy image is not the colour's size");
        before = rt::Image(w, h);
        std::copy(noisy->data(), noisy->data() + pixels * 3, before.rgb.begin());
    }
    for (const auto& [name, layer] : aux) outputs.push_back(rt::parse_aux_output(name));
    rt::AuxImage layers(w, h, outputs);
    for (const auto& [name, layer] : aux) {
        const rt::AuxOutput output = rt::parse_aux_output(name);
        const size_t values = pixels * rt::aux_channel_count(output);
        if (layer.size() != values)
            throw std::invalid_argument("write_exr: layer '" + name + "' has " + std::to_string(layer.size()) +
                                        " values, the image needs " + std::to_string(values));
        layers.with_layer(output, [&](auto& out) {
            using T = typename std::decay_t<decltype(out)>::value_type;
            std::transform(layer.data(), layer.data() + values, out.begin(), [](float v) { return T(v); });
        });
    }
    nb::gil_scoped_release release;
    rt::write_image(path, image, outputs.empty() ? nullptr : &layers, {}, noisy ? &before : nullptr);
}

nb::ndarray<nb::numpy, float> denoise(const Rgb& color, const Rgb& albedo, const Rgb& normal, unsigned threads) {
    const auto size = rgb_size(color, "denoise");
    if (rgb_size(albedo, "denoise") != size || rgb_size(normal, "denoise") != size)
        throw std::invalid_argument("denoise(): albedo and normal must have the colour's shape");
    const auto [h, w] = size;
    std::vector<float> out(h * w * 3);
    {
        nb::gil_scoped_release release;
        rt::denoise_oidn(uint32_t(w), uint32_t(h), color.data(), albedo.data(), normal.data(), out.data(), threads);
    }
    return to_numpy(std::move(out), {h, w, 3});
}

}  // namespace

void bind_images(nb::module_& m) {
    m.def("encode_srgb8", &encode_srgb8, "rgb"_a, "settings"_a = nb::none(),
          "Linear RGB float32 (h, w, 3) as 8-bit sRGB RGBA (h, w, 4), byte for byte as rtrender's PNG: "
          "scaled by 2^exposure and tone mapped as the settings (rt.RenderSettings, bytes or JSON) say; "
          "None: exposure 0, CLIP.");
    m.def("apply_bloom", &apply_bloom, "rgb"_a, "settings"_a.none(),
          "A new linear RGB float32 (h, w, 3) array: rgb with the settings' bloom (bloom_threshold, "
          "bloom_radius, bloom_strength of rt.RenderSettings, bytes or JSON; width and height are the "
          "array's), as rtrender applies it before writing. The image's sum is unchanged; strength 0 "
          "returns a copy.");
    m.def("write_exr", &write_exr, "path"_a, "color"_a, "aux"_a = std::map<std::string, Layer>{},
          "noisy"_a = nb::none(),
          "Writes linear colour, auxiliary layers ({'depth': (h, w), 'normal': (h, w, 3), ...}, float32) and "
          "the image before denoising (noisy, (h, w, 3), as channels noisy.R, noisy.G, noisy.B) as one EXR with "
          "rtrender's channel names.");
    m.def("denoise", &denoise, "color"_a, "albedo"_a, "normal"_a, "threads"_a = 0,
          "A new linear RGB float32 (h, w, 3) array: color denoised by Open Image Denoise's RT filter (HDR) "
          "with the albedo and normal layers ((h, w, 3) float32, as render_tile answers them) as guides, on "
          "up to `threads` threads (0: all). Pixels that are not finite keep their values. RuntimeError when "
          "OIDN cannot be loaded (rtcore.denoiser_library() says which file was).");
    m.def("denoiser_library", &rt::oidn::loaded_library,
          "The Open Image Denoise library this process loaded, or '' when none could be (or none was asked for "
          "yet).");
}

}  // namespace rtcore
