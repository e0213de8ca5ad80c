// Images from Python: the 8-bit sRGB encoding and the EXR writer the CLI uses,
// so the job service's tiles, image.png and image.exr match rtrender's output.
#include "rtcore_image.h"

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include <nanobind/ndarray.h>
#include <nanobind/stl/map.h>
#include <nanobind/stl/string.h>

#include "aov.h"
#include "image.h"
#include "rtcore_convert.h"

namespace rtcore {
namespace {

using namespace nb::literals;
using Rgb = nb::ndarray<const float, nb::ndim<3>, nb::c_contig, nb::device::cpu>;
using Layer = nb::ndarray<const float, nb::c_contig, nb::device::cpu>;

void check_rgb(const Rgb& rgb, const char* what) {
    if (rgb.shape(2) != 3)
        throw std::invalid_argument(std::string(what) + ": expected an (height, width, 3) array, got " +
                                    std::to_string(rgb.shape(2)) + " channels");
}

nb::ndarray<nb::numpy, uint8_t> encode_srgb8(const Rgb& rgb) {
    check_rgb(rgb, "encode_srgb8");
    const size_t h = rgb.shape(0), w = rgb.shape(1), pixels = h * w;
    std::vector<uint8_t> rgba(pixels * 4);
    {
        nb::gil_scoped_release release;
        const float* in = rgb.data();
        for (size_t p = 0; p < pixels; ++p) {
            for (int c = 0; c < 3; ++c) rgba[4 * p + c] = rt::srgb8(in[3 * p + c]);
            rgba[4 * p + 3] = 255;
        }
    }
    return to_numpy(std::move(rgba), {h, w, 4});
}

void write_exr(const std::string& path, const Rgb& color, const std::map<std::string, Layer>& aux) {
    check_rgb(color, "write_exr");
    const uint32_t h = uint32_t(color.shape(0)), w = uint32_t(color.shape(1));
    const size_t pixels = size_t(w) * h;
    rt::Image image(w, h);
    std::copy(color.data(), color.data() + pixels * 3, image.rgb.begin());

    std::vector<rt::AuxOutput> outputs;
    for (const auto& [name, layer] : aux) outputs.push_back(rt::parse_aux_output(name));
    rt::AuxImage layers(w, h, outputs);
    for (const auto& [name, layer] : aux) {
        const rt::AuxOutput output = rt::parse_aux_output(name);
        const size_t values = pixels * rt::aux_channel_count(output);
        if (layer.size() != values)
            throw std::invalid_argument("write_exr: layer '" + name + "' has " + std::to_string(layer.size()) +
                                        " values, the image needs " + std::to_string(values));
        const float* in = layer.data();
        switch (output) {
            case rt::DEPTH: std::copy(in, in + values, layers.depth.begin()); break;
            case rt::NORMAL: std::copy(in, in + values, layers.normal.begin()); break;
            case rt::ALBEDO: std::copy(in, in + values, layers.albedo.begin()); break;
            case rt::BVH_COST:
                std::transform(in, in + values, layers.bvh_cost.begin(), [](float v) { return uint32_t(v); });
                break;
            default: break;
        }
    }
    nb::gil_scoped_release release;
    rt::write_image(path, image, outputs.empty() ? nullptr : &layers);
}

}  // namespace

void bind_images(nb::module_& m) {
    m.def("encode_srgb8", &encode_srgb8, "rgb"_a,
          "Linear RGB float32 (h, w, 3) as 8-bit sRGB RGBA (h, w, 4), rounded exactly as rtrender's PNG.");
    m.def("write_exr", &write_exr, "path"_a, "color"_a, "aux"_a = std::map<std::string, Layer>{},
          "Writes linear colour and auxiliary layers ({'depth': (h, w), 'normal': (h, w, 3), ...}, float32) "
          "as one EXR with rtrender's channel names.");
}

}  // namespace rtcore
