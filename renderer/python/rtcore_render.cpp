// Rendering from Python: tiles (with their auxiliary outputs and previews),
// whole images and debugger paths.
#include <algorithm>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "image/aov.h"
#include "image/denoise.h"
#include "integrator/default_camera.h"
#include "integrator/render.h"
#include "rtcore_convert.h"
#include "rtcore_scene.h"
#include "util/thread_pool.h"

namespace rtcore {
namespace {

// A list of names ("depth") or rt.AuxOutput values (1); a lone string is
// refused rather than read letter by letter.
std::vector<rt::AuxOutput> read_aux(nb::handle aux) {
    const char* expected = "aux: expected a list of names (depth, normal, albedo, bvh_cost, alpha) or rt.AuxOutput values";
    if (nb::isinstance<nb::str>(aux) || nb::isinstance<nb::bytes>(aux)) throw std::invalid_argument(expected);
    std::vector<rt::AuxOutput> outputs;
    for (nb::handle item : aux) {
        if (nb::isinstance<nb::str>(item))
            outputs.push_back(rt::parse_aux_output(nb::borrow<nb::str>(item).c_str()));
        else if (nb::isinstance<nb::int_>(item) && !nb::isinstance<nb::bool_>(item))
            outputs.push_back(rt::aux_output_from_value(nb::cast<int>(item)));
        else
            throw std::invalid_argument(expected);
    }
    return outputs;
}

// Copies the pixels a preview at scale `stride` computed for this tile (the
// layers of `known`, keyed as render_tile answers them: 'color' and each
// auxiliary layer, ceil(h/stride) x ceil(w/stride) pixels) to their places in
// the tile's buffers.
void place_known(nb::handle known, uint32_t stride, const rt::TileRect& tile, std::vector<float>& rgb,
                 rt::AuxImage& layers) {
    if (stride == 0) throw std::invalid_argument("known_stride: known pixels need the preview's scale (>= 1)");
    if (tile.x % stride != 0 || tile.y % stride != 0)
        throw std::invalid_argument("known_stride: the tile at (" + std::to_string(tile.x) + ", " +
                                    std::to_string(tile.y) + ") does not start on the preview's grid of " +
                                    std::to_string(stride));
    if (!nb::isinstance<nb::dict>(known)) throw std::invalid_argument("known: expected a dict of layers");
    const auto layers_in = nb::borrow<nb::dict>(known);
    const size_t kw = rt::preview_extent(tile.width, stride), kh = rt::preview_extent(tile.height, stride);
    const auto place = [&](const char* name, auto* target, size_t channels) {
        using T = std::remove_pointer_t<decltype(target)>;
        if (!layers_in.contains(name)) throw std::invalid_argument(std::string("known: no '") + name + "' layer");
        nb::ndarray<const T, nb::c_contig, nb::device::cpu> values;
        if (!nb::try_cast(layers_in[name], values) || values.size() != kh * kw * channels)
            throw std::invalid_argument(std::string("known['") + name + "']: expected " + std::to_string(kh) + "x" +
                                        std::to_string(kw) + "x" + std::to_string(channels) + " C-contiguous " +
                                        (std::is_same_v<T, float> ? "float32" : "uint32") + " values");
        for (size_t j = 0; j < kh; ++j)
            for (size_t i = 0; i < kw; ++i)
                std::copy_n(values.data() + (j * kw + i) * channels, channels,
                            target + (j * stride * tile.width + i * stride) * channels);
    };
    place("color", rgb.data(), 3);
    for (rt::AuxOutput output : layers.outputs())
        layers.with_layer(output, [&](auto& values) {
            place(rt::aux_name(output).c_str(), values.data(), rt::aux_channel_count(output));
        });
}

}  // namespace

rt::Renderer PyScene::renderer(nb::handle camera, nb::handle settings) const {
    return rt::Renderer(*accel_, read_message<rt::RenderSettings>(settings, "settings"),
                        read_message<rt::Camera>(camera, "camera"));
}

nb::bytes PyScene::complete(const std::string& type_name, nb::handle data) const {
    const auto request = new_message(type_name);
    read_message(data, *request, "body");
    const auto* descriptor = request->GetDescriptor();
    const auto* camera_field = descriptor->FindFieldByName("camera");
    const auto* settings_field = descriptor->FindFieldByName("settings");
    if (!camera_field || camera_field->message_type() != rt::Camera::descriptor() || !settings_field ||
        settings_field->message_type() != rt::RenderSettings::descriptor())
        throw std::invalid_argument(type_name + " is not a render request: it needs a camera and settings");
    const auto* reflection = request->GetReflection();
    rt::Camera camera = reflection->HasField(*request, camera_field)
                            ? static_cast<const rt::Camera&>(reflection->GetMessage(*request, camera_field))
                            : rt::default_camera(*scene_);
    rt::RenderSettings settings;
    if (reflection->HasField(*request, settings_field))
        settings.CopyFrom(reflection->GetMessage(*request, settings_field));
    // The request's own fields by the schema's limits, then its camera and
    // settings by the renderer, which applies their limits and its own checks:
    // each value is checked once.
    reflection->ClearField(request.get(), camera_field);
    reflection->ClearField(request.get(), settings_field);
    rt::apply_limits(*request, "");
    const rt::Renderer checked(*accel_, std::move(settings), std::move(camera));
    reflection->MutableMessage(request.get(), camera_field)->CopyFrom(checked.camera());
    reflection->MutableMessage(request.get(), settings_field)->CopyFrom(checked.settings());
    return to_bytes(*request);
}

nb::object PyScene::render_tile(nb::handle camera, nb::handle settings, uint32_t x, uint32_t y, uint32_t width,
                                uint32_t height, nb::handle aux, uint32_t scale, nb::handle known,
                                uint32_t known_stride, const std::stop_source* stop) const {
    const rt::Renderer renderer = this->renderer(camera, settings);
    const rt::TileRect tile{x, y, width, height};
    renderer.check_tile(tile, scale);
    const std::vector<rt::AuxOutput> outputs = aux.is_none() ? std::vector<rt::AuxOutput>{} : read_aux(aux);
    const size_t w = rt::preview_extent(width, scale), h = rt::preview_extent(height, scale);
    if (!known.is_none() && scale != 1)
        throw std::invalid_argument("known: a preview (scale " + std::to_string(scale) + ") has no known pixels");
    std::vector<float> rgb;
    rt::AuxImage layers;
    {
        // Even allocating the buffers (first touches of fresh pages) is work
        // the server's event loop must not wait for.
        nb::gil_scoped_release release;
        rgb.resize(w * h * 3);
        layers = rt::AuxImage(uint32_t(w), uint32_t(h), outputs);
    }
    if (!known.is_none()) place_known(known, known_stride, tile, rgb, layers);
    rt::RenderStats stats;
    {
        nb::gil_scoped_release release;
        stats = renderer.render_tile(*rt::render_pool(), tile, rgb.data(), layers.layers(), scale,
                                     known.is_none() ? 0 : known_stride, stop ? stop->get_token() : std::stop_token{});
    }
    auto color = to_numpy(std::move(rgb), {h, w, 3});
    if (aux.is_none()) return nb::cast(color);

    nb::dict result;
    result["color"] = color;
    for (rt::AuxOutput output : layers.outputs())
        layers.with_layer(output, [&](auto& values) {
            const size_t channels = rt::aux_channel_count(output);
            result[rt::aux_name(output).c_str()] = channels == 1 ? nb::cast(to_numpy(std::move(values), {h, w}))
                                                                 : nb::cast(to_numpy(std::move(values), {h, w, channels}));
        });
    result["rays"] = stats.rays.total();
    result["samples"] = stats.samples;
    return result;
}

nb::ndarray<nb::numpy, float> PyScene::render(nb::handle camera, nb::handle settings, unsigned threads,
                                              uint32_t tile_size) const {
    const rt::Renderer renderer = this->renderer(camera, settings);
    rt::Image image;
    {
        nb::gil_scoped_release release;
        rt::RenderStats stats;
        // A whole image is denoised as rtrender denoises it; tiles never are.
        rt::AuxImage guides(renderer.settings().width(), renderer.settings().height(),
                            rt::denoise_guides(renderer.settings()));
        image = renderer.render(threads, tile_size, nullptr, stats, &guides);
        rt::apply_denoise(image, guides, renderer.settings(), threads);
    }
    const size_t w = image.width, h = image.height;
    return to_numpy(std::move(image.rgb), {h, w, 3});
}

nb::bytes PyScene::debug_path(nb::handle camera, nb::handle settings, uint32_t x, uint32_t y) const {
    const rt::Renderer renderer = this->renderer(camera, settings);
    rt::DebugPath path;
    {
        nb::gil_scoped_release release;
        path = renderer.debug_pixel(x, y);
    }
    return to_bytes(path);
}

}  // namespace rtcore
