// rtrender: renders a scene file to PNG or EXR.
//
// Every field of the rt.RenderSettings message is a flag (--max-depth for
// max_depth; cli_flags.cpp), so a setting added to proto/rt/render.proto is
// reachable here without touching either file.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>
#include <unistd.h>

#include <google/protobuf/descriptor.h>
#include <google/protobuf/util/json_util.h>

#include "cli_flags.h"
#include "geometry/accel.h"
#include "image/aov.h"
#include "image/bloom.h"
#include "image/denoise.h"
#include "image/oidn_library.h"
#include "integrator/default_camera.h"
#include "image/image.h"
#include "load/loader.h"
#include "util/proto_limits.h"
#include "integrator/render.h"

namespace {

using google::protobuf::FieldDescriptor;
using rtrender::Options;
using rtrender::UsageError;

std::string read_text_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error(path + ": cannot be read");
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

rt::Camera choose_camera(const Options& options, const rt::Scene& scene) {
    if (!options.camera_file.empty()) {
        rt::Camera camera;
        rt::parse_json_message(read_text_file(options.camera_file), camera, options.camera_file);
        return camera;
    }
    if (options.camera_name.empty()) return rt::default_camera(scene);
    std::string names;
    for (const auto& camera : scene.cameras) {
        if (camera.name == options.camera_name) return camera.camera;
        names += (names.empty() ? "" : ", ") + camera.name;
    }
    throw UsageError("--camera: the scene has no camera '" + options.camera_name + "' (it has: " +
                     (names.empty() ? "none" : names) + ")");
}

// The chosen camera's pose with the projection the flags ask for, if any.
rt::Camera with_projection(const Options& options, rt::Camera camera) {
    if (options.perspective) camera.set_projection(rt::PERSPECTIVE);
    if (options.ortho_height > 0.0f) {
        camera.set_projection(rt::ORTHOGRAPHIC);
        camera.set_ortho_height(options.ortho_height);
    }
    return camera;
}

class ProgressBar {
  public:
    explicit ProgressBar(bool enabled) : enabled_(enabled), interactive_(isatty(STDERR_FILENO)) {}

    void update(size_t done, size_t total) {
        if (!enabled_) return;
        const int percent = int(100 * done / total);
        if (interactive_) {
            const auto now = Clock::now();
            if (done != total && now - last_ < std::chrono::milliseconds(100)) return;
            last_ = now;
            const int filled = percent * 40 / 100;
            std::fprintf(stderr, "\r[%s%s] %3d%% %zu/%zu tiles", std::string(filled, '#').c_str(),
                         std::string(40 - filled, ' ').c_str(), percent, done, total);
            if (done == total) std::fprintf(stderr, "\n");
        } else if (percent / 10 != printed_ / 10 || done == total) {
            printed_ = percent;
            std::fprintf(stderr, "%3d%% %zu/%zu tiles\n", percent, done, total);
        }
    }

  private:
    using Clock = std::chrono::steady_clock;
    bool enabled_;
    bool interactive_;
    Clock::time_point last_{};
    int printed_ = -1;
};

double milliseconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

int run(const Options& options) {
    rt::RenderSettings settings;
    if (!options.settings_file.empty())
        rt::parse_json_message(read_text_file(options.settings_file), settings, options.settings_file);
    // A flag replaces the file's list or message; MergeFrom alone would append or merge.
    std::vector<const FieldDescriptor*> given;
    options.flags.GetReflection()->ListFields(options.flags, &given);
    for (const FieldDescriptor* field : given) settings.GetReflection()->ClearField(&settings, field);
    settings.MergeFrom(options.flags);

    const rt::Scene scene = rt::load_scene(options.scene);
    for (const auto& warning : scene.warnings) std::fprintf(stderr, "rtrender: warning: %s\n", warning.c_str());
    const rt::Accelerator accel(scene, options.threads);
    const rt::Renderer renderer(accel, settings, with_projection(options, choose_camera(options, scene)));

    if (options.debug_pixel) {
        const rt::DebugPath path = renderer.debug_pixel(options.debug_x, options.debug_y);
        std::string json;
        google::protobuf::util::JsonPrintOptions print;
        print.add_whitespace = true;
        (void)google::protobuf::util::MessageToJsonString(path, &json, print);
        std::cout << json;
        if (options.output.empty()) return 0;
    }

    const bool denoising = renderer.settings().denoise() != rt::NO_DENOISER;
    if (!options.noisy.empty() && !denoising)
        throw UsageError("--noisy is the image before denoising: give --denoise oidn too");
    ProgressBar bar(!options.quiet);
    rt::RenderStats counts;
    // The denoiser's guides are rendered whether or not they are written.
    std::vector<rt::AuxOutput> layers = options.aux;
    for (rt::AuxOutput guide : rt::denoise_guides(renderer.settings()))
        if (std::find(layers.begin(), layers.end(), guide) == layers.end()) layers.push_back(guide);
    rt::AuxImage aux(renderer.settings().width(), renderer.settings().height(), layers);
    const auto start = std::chrono::steady_clock::now();
    rt::Image image = renderer.render(options.threads, options.tile_size,
                                      [&](size_t done, size_t total) { bar.update(done, total); }, counts, &aux);
    const double render_ms = milliseconds_since(start);
    rt::Image noisy = options.noisy.empty() ? rt::Image() : image;
    const auto denoise_start = std::chrono::steady_clock::now();
    rt::apply_denoise(image, aux, renderer.settings(), options.threads);
    const double denoise_ms = milliseconds_since(denoise_start);
    const auto bloom_start = std::chrono::steady_clock::now();
    rt::apply_bloom(image, renderer.settings());
    const double bloom_ms = milliseconds_since(bloom_start);
    const auto write_start = std::chrono::steady_clock::now();
    const rt::DisplayTransform display = rt::DisplayTransform::from(renderer.settings());
    for (rt::AuxOutput output : layers)  // only the layers asked for are written
        if (std::find(options.aux.begin(), options.aux.end(), output) == options.aux.end())
            aux.with_layer(output, [](auto& values) { values.clear(); });
    rt::write_image(options.output, image, &aux, display);
    if (!options.noisy.empty()) {
        rt::apply_bloom(noisy, renderer.settings());
        rt::write_image(options.noisy, noisy, nullptr, display);
    }
    const double write_ms = milliseconds_since(write_start);

    const auto& stats = accel.stats();
    const std::string placed = stats.instances == 0 ? std::string()
                               : " (" + std::to_string(scene.placed_triangles()) + " placed by " +
                                     std::to_string(stats.instances) + " instances)";
    std::printf("rtrender: %zu triangles%s, %zu spheres, BVH %zu nodes depth %u (%s kernels), build %.1f ms, "
                "render %.1f ms, %.2f Mrays/s (%llu rays), %.1f samples/pixel -> %s\n",
                stats.triangles, placed.c_str(), scene.spheres.size(), stats.nodes, stats.depth, rt::to_string(accel.simd()),
                stats.build_ms, render_ms,
                double(counts.rays.total()) / (render_ms * 1e3),
                static_cast<unsigned long long>(counts.rays.total()),
                double(counts.samples) / (double(image.width) * image.height), options.output.c_str());
    if (denoising) std::printf("rtrender: denoise %.1f ms (%s)\n", denoise_ms, rt::oidn::loaded_library().c_str());
    if (renderer.settings().bloom_strength() > 0.0f) std::printf("rtrender: bloom %.1f ms\n", bloom_ms);
    std::printf("rtrender: write %.1f ms\n", write_ms);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        return run(rtrender::parse_arguments(argc, argv));
    } catch (const UsageError& e) {
        std::fprintf(stderr, "rtrender: %s\n", e.what());
        return 2;
    } catch (const std::invalid_argument& e) {
        std::fprintf(stderr, "rtrender: %s\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "rtrender: error: %s\n", e.what());
        return 1;
    }
}
