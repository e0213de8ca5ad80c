// rtrender: renders a scene file to PNG or EXR.
//
// Every field of the rt.RenderSettings message is a flag (--max-depth for
// max_depth), so a setting added to proto/rt/render.proto is reachable here
// without touching this file.
#include <chrono>
#include <cstdio>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>
#include <unistd.h>

#include <google/protobuf/descriptor.h>
#include <google/protobuf/util/json_util.h>

#include "geometry/accel.h"
#include "image/aov.h"
#include "image/bloom.h"
#include "integrator/default_camera.h"
#include "image/image.h"
#include "load/loader.h"
#include "util/proto_limits.h"
#include "integrator/render.h"
#include "rt/options.pb.h"

namespace {

using google::protobuf::FieldDescriptor;

struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

struct Options {
    std::string scene;
    std::string output;
    std::string settings_file;
    std::string camera_name;
    std::string camera_file;
    unsigned threads = 0;
    uint32_t tile_size = 32;
    bool quiet = false;
    bool debug_pixel = false;
    uint32_t debug_x = 0, debug_y = 0;
    std::vector<rt::AuxOutput> aux;  // auxiliary outputs, as extra EXR channels
    rt::RenderSettings flags;  // settings given as flags; they override the file
};

std::string flag_name(const FieldDescriptor* field) {
    std::string name = field->name();
    for (char& c : name)
        if (c == '_') c = '-';
    return "--" + name;
}

std::string lower(std::string text) {
    for (char& c : text) c = char(std::tolower(static_cast<unsigned char>(c)));
    return text;
}

// An enum setting's values in lower case, the default (the proto3 zero) first.
std::string enum_choices(const FieldDescriptor* field) {
    std::string names;
    for (int i = 0; i < field->enum_type()->value_count(); ++i)
        names += (names.empty() ? "" : ", ") + lower(field->enum_type()->value(i)->name());
    return names;
}

void print_help() {
    std::cout <<
        "usage: rtrender SCENE -o OUT.png|OUT.exr [options]\n"
        "\n"
        "Renders SCENE (.gltf, .glb or .obj, with an optional SCENE-stem.rt.json sidecar).\n"
        "PNG is written as sRGB 8-bit (after --exposure and --tone-map), EXR as linear\n"
        "float; both after bloom (--bloom-strength above 0).\n"
        "\n"
        "options:\n"
        "  -o, --output FILE        image to write (.png or .exr)\n"
        "  --settings FILE.json     rt.RenderSettings in JSON; flags below override it\n"
        "  --camera NAME            one of the scene's cameras (default: its first)\n"
        "  --camera-file FILE.json  rt.Camera in JSON: {position, target, up, fov_y}\n"
        "  --threads N              worker threads (default: all cores)\n"
        "  --tile-size N            tile edge in pixels (default 32); never changes the image\n"
        "  --aux LIST               auxiliary outputs as extra EXR channels, comma-separated:\n"
        "                           depth,normal,albedo,bvh_cost (rt.AuxOutput)\n"
        "  --debug-pixel X,Y        print the rays traced for one pixel (rt.DebugPath JSON)\n"
        "  --quiet                  no progress bar\n"
        "  -h, --help               this text\n"
        "\n"
        "render settings (rt.RenderSettings):\n";
    const auto* descriptor = rt::RenderSettings::descriptor();
    for (int i = 0; i < descriptor->field_count(); ++i) {
        const FieldDescriptor* field = descriptor->field(i);
        const rt::Limits& limits = field->options().GetExtension(rt::limits);
        const bool is_enum = field->cpp_type() == FieldDescriptor::CPPTYPE_ENUM;
        std::string text = "  " + flag_name(field) + (is_enum ? " NAME" : " N");
        text.resize(std::max<size_t>(text.size() + 1, 27), ' ');
        if (is_enum)
            std::cout << text << enum_choices(field) << " (default " << lower(field->enum_type()->value(0)->name())
                      << ")\n";
        else
            std::cout << text << "default " << limits.default_() << ", " << limits.min() << " to " << limits.max()
                      << "\n";
    }
    std::cout << "\nexit status: 0 success, 1 the scene or image failed, 2 bad arguments\n";
}

template <class T>
T parse_number(const std::string& flag, const std::string& text) {
    std::istringstream in(text);
    T value{};
    if (!(in >> value) || !in.eof())
        throw UsageError(flag + ": '" + text + "' is not a number");
    return value;
}

std::vector<rt::AuxOutput> parse_aux_list(const std::string& text) {
    std::vector<rt::AuxOutput> outputs;
    std::istringstream in(text);
    for (std::string name; std::getline(in, name, ',');) {
        try {
            outputs.push_back(rt::parse_aux_output(name));
        } catch (const std::invalid_argument& e) {
            throw UsageError(std::string("--aux: ") + e.what());
        }
    }
    if (outputs.empty()) throw UsageError("--aux needs at least one of depth,normal,albedo,bvh_cost");
    return outputs;
}

bool has_extension(const std::string& file, const std::string& extension) {
    return lower(std::filesystem::path(file).extension().string()) == extension;
}

void set_setting_flag(rt::RenderSettings& settings, const FieldDescriptor* field, const std::string& text) {
    const auto* reflection = settings.GetReflection();
    const std::string flag = flag_name(field);
    switch (field->cpp_type()) {
        case FieldDescriptor::CPPTYPE_UINT32: {
            const auto v = parse_number<long long>(flag, text);
            if (v < 0 || v > 0xffffffffLL) throw UsageError(flag + ": " + text + " is out of range");
            reflection->SetUInt32(&settings, field, uint32_t(v));
            break;
        }
        case FieldDescriptor::CPPTYPE_FLOAT:
            reflection->SetFloat(&settings, field, parse_number<float>(flag, text));
            break;
        case FieldDescriptor::CPPTYPE_ENUM: {
            std::string upper = text;
            for (char& c : upper) c = char(std::toupper(static_cast<unsigned char>(c)));
            const auto* value = field->enum_type()->FindValueByName(upper);
            if (!value) throw UsageError(flag + ": '" + text + "' is not one of " + enum_choices(field));
            reflection->SetEnum(&settings, field, value);
            break;
        }
        default:
            throw UsageError(flag + ": unsupported setting type");
    }
}

Options parse_arguments(int argc, char** argv) {
    Options options;
    const auto* settings_descriptor = rt::RenderSettings::descriptor();
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) throw UsageError(arg + " needs a value");
            return argv[++i];
        };
        if (arg == "-h" || arg == "--help") {
            print_help();
            std::exit(0);
        } else if (arg == "-o" || arg == "--output") {
            options.output = value();
        } else if (arg == "--settings") {
            options.settings_file = value();
        } else if (arg == "--camera") {
            options.camera_name = value();
        } else if (arg == "--camera-file") {
            options.camera_file = value();
        } else if (arg == "--threads") {
            options.threads = parse_number<unsigned>(arg, value());
        } else if (arg == "--tile-size") {
            options.tile_size = parse_number<uint32_t>(arg, value());
            if (options.tile_size == 0) throw UsageError("--tile-size must be at least 1");
        } else if (arg == "--aux") {
            options.aux = parse_aux_list(value());
        } else if (arg == "--quiet") {
            options.quiet = true;
        } else if (arg == "--debug-pixel") {
            const std::string v = value();
            const auto comma = v.find(',');
            if (comma == std::string::npos) throw UsageError("--debug-pixel takes X,Y");
            options.debug_pixel = true;
            options.debug_x = parse_number<uint32_t>(arg, v.substr(0, comma));
            options.debug_y = parse_number<uint32_t>(arg, v.substr(comma + 1));
        } else if (arg.rfind("--", 0) == 0) {
            std::string name = arg.substr(2);
            for (char& c : name)
                if (c == '-') c = '_';
            const FieldDescriptor* field = settings_descriptor->FindFieldByName(name);
            if (!field) throw UsageError("unknown option " + arg + " (see --help)");
            set_setting_flag(options.flags, field, value());
        } else if (!arg.empty() && arg[0] == '-') {
            throw UsageError("unknown option " + arg + " (see --help)");
        } else if (options.scene.empty()) {
            options.scene = arg;
        } else {
            throw UsageError("more than one scene given: " + options.scene + " and " + arg);
        }
    }
    if (options.scene.empty()) throw UsageError("no scene given (see --help)");
    if (options.output.empty() && !options.debug_pixel) throw UsageError("no output given: -o OUT.png or OUT.exr");
    if (!options.aux.empty() && !options.output.empty() && !has_extension(options.output, ".exr"))
        throw UsageError("--aux writes extra channels of an EXR: the output must be .exr, not " + options.output);
    if (!options.camera_name.empty() && !options.camera_file.empty())
        throw UsageError("--camera and --camera-file exclude each other");
    return options;
}

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
    settings.MergeFrom(options.flags);

    const rt::Scene scene = rt::load_scene(options.scene);
    for (const auto& warning : scene.warnings) std::fprintf(stderr, "rtrender: warning: %s\n", warning.c_str());
    const rt::Accelerator accel(scene, options.threads);
    const rt::Renderer renderer(accel, settings, choose_camera(options, scene));

    if (options.debug_pixel) {
        const rt::DebugPath path = renderer.debug_pixel(options.debug_x, options.debug_y);
        std::string json;
        google::protobuf::util::JsonPrintOptions print;
        print.add_whitespace = true;
        (void)google::protobuf::util::MessageToJsonString(path, &json, print);
        std::cout << json;
        if (options.output.empty()) return 0;
    }

    ProgressBar bar(!options.quiet);
    rt::RenderStats counts;
    rt::AuxImage aux(renderer.settings().width(), renderer.settings().height(), options.aux);
    const auto start = std::chrono::steady_clock::now();
    rt::Image image = renderer.render(options.threads, options.tile_size,
                                      [&](size_t done, size_t total) { bar.update(done, total); }, counts, &aux);
    const double render_ms = milliseconds_since(start);
    const auto bloom_start = std::chrono::steady_clock::now();
    rt::apply_bloom(image, renderer.settings());
    const double bloom_ms = milliseconds_since(bloom_start);
    const auto write_start = std::chrono::steady_clock::now();
    rt::write_image(options.output, image, &aux, rt::DisplayTransform::from(renderer.settings()));
    const double write_ms = milliseconds_since(write_start);

    const auto& stats = accel.stats();
    std::printf("rtrender: %zu triangles, %zu spheres, BVH %zu nodes depth %u, build %.1f ms, "
                "render %.1f ms, %.2f Mrays/s (%llu rays), %.1f samples/pixel -> %s\n",
                stats.triangles, scene.spheres.size(), stats.nodes, stats.depth, stats.build_ms, render_ms,
                double(counts.rays.total()) / (render_ms * 1e3),
                static_cast<unsigned long long>(counts.rays.total()),
                double(counts.samples) / (double(image.width) * image.height), options.output.c_str());
    if (renderer.settings().bloom_strength() > 0.0f) std::printf("rtrender: bloom %.1f ms\n", bloom_ms);
    std::printf("rtrender: write %.1f ms\n", write_ms);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        return run(parse_arguments(argc, argv));
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
