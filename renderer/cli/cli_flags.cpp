#include "cli_flags.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <sstream>

#include <google/protobuf/descriptor.h>

#include "image/aov.h"
#include "util/proto_limits.h"
#include "rt/options.pb.h"

namespace rtrender {
namespace {

using google::protobuf::FieldDescriptor;

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

// A message setting's own fields, for help and errors.
std::string field_names(const FieldDescriptor* field) {
    std::string names;
    for (int i = 0; i < field->message_type()->field_count(); ++i)
        names += (names.empty() ? "" : ", ") + field->message_type()->field(i)->name();
    return names;
}

void print_help() {
    std::cout <<
        "usage: rtrender SCENE -o OUT.png|OUT.exr [options]\n"
        "\n"
        "Renders SCENE (.gltf, .glb or .obj, with an optional SCENE-stem.rt.json sidecar).\n"
        "PNG is written as sRGB 8-bit (after --exposure and --tone-map), EXR as linear\n"
        "float; both after denoising (--denoise oidn) and bloom (--bloom-strength above 0).\n"
        "\n"
        "options:\n"
        "  -o, --output FILE        image to write (.png or .exr)\n"
        "  --settings FILE.json     rt.RenderSettings in JSON; flags below override it\n"
        "  --camera NAME            one of the scene's cameras (default: its first)\n"
        "  --camera-file FILE.json  rt.Camera in JSON: {position, target, up, fov_y} or, with\n"
        "                           projection ORTHOGRAPHIC, ortho_height instead of fov_y\n"
        "  --orthographic HEIGHT    render the chosen camera with parallel rays, the image\n"
        "                           HEIGHT world units tall (its width by the aspect)\n"
        "  --perspective            render the chosen camera as a pinhole (its fov_y)\n"
        "  --threads N              worker threads (default: all cores)\n"
        "  --tile-size N            tile edge in pixels (default 32); never changes the image\n"
        "  --aux LIST               auxiliary outputs as extra EXR channels, comma-separated:\n"
        "                           depth,normal,albedo,bvh_cost,alpha (rt.AuxOutput)\n"
        "  --noisy FILE             with --denoise, also the image before denoising\n"
        "                           (.png or .exr, after bloom as the output is)\n"
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
        const bool is_message = field->cpp_type() == FieldDescriptor::CPPTYPE_MESSAGE;
        std::string text = "  " + flag_name(field) +
                           (is_enum ? " NAME" : is_message ? " K=V;.." : field->is_repeated() ? " N,N,N" : " N");
        text.resize(std::max<size_t>(text.size() + 1, 27), ' ');
        if (is_enum)
            std::cout << text << enum_choices(field) << " (default " << lower(field->enum_type()->value(0)->name())
                      << ")\n";
        else if (is_message)
            std::cout << text << "rt." << field->message_type()->name() << ": " << field_names(field)
                      << " as NAME=N,N,N separated by ';', or its JSON (absent by default)\n";
        else if (field->is_repeated())
            std::cout << text << limits.count() << " values, " << limits.min() << " to " << limits.max()
                      << " (absent by default)\n";
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
    if (outputs.empty()) throw UsageError("--aux needs at least one of depth,normal,albedo,bvh_cost,alpha");
    return outputs;
}

bool has_extension(const std::string& file, const std::string& extension) {
    return lower(std::filesystem::path(file).extension().string()) == extension;
}

std::vector<std::string> split(const std::string& text, char separator) {
    std::vector<std::string> parts;
    std::istringstream in(text);
    for (std::string part; std::getline(in, part, separator);) parts.push_back(part);
    return parts;
}

// One value of `field` from `text`: a number, an enum name, a comma-separated
// list for a repeated field ("0.1,0.2,0.3"), and for a message either its JSON
// or its fields as NAME=VALUE pairs separated by ';' ("bottom=0,0,0;top=1,1,1").
// Limits are the renderer's to check, as for the settings file.
void set_flag_value(google::protobuf::Message& message, const FieldDescriptor* field, const std::string& flag,
                    const std::string& text) {
    const auto* reflection = message.GetReflection();
    if (field->is_repeated()) {
        if (field->cpp_type() != FieldDescriptor::CPPTYPE_FLOAT) throw UsageError(flag + ": unsupported setting type");
        reflection->ClearField(&message, field);
        for (const std::string& item : split(text, ','))
            reflection->AddFloat(&message, field, parse_number<float>(flag, item));
        return;
    }
    switch (field->cpp_type()) {
        case FieldDescriptor::CPPTYPE_UINT32: {
            const auto v = parse_number<long long>(flag, text);
            if (v < 0 || v > 0xffffffffLL) throw UsageError(flag + ": " + text + " is out of range");
            reflection->SetUInt32(&message, field, uint32_t(v));
            break;
        }
        case FieldDescriptor::CPPTYPE_FLOAT:
            reflection->SetFloat(&message, field, parse_number<float>(flag, text));
            break;
        case FieldDescriptor::CPPTYPE_ENUM: {
            std::string upper = text;
            for (char& c : upper) c = char(std::toupper(static_cast<unsigned char>(c)));
            const auto* value = field->enum_type()->FindValueByName(upper);
            if (!value) throw UsageError(flag + ": '" + text + "' is not one of " + enum_choices(field));
            reflection->SetEnum(&message, field, value);
            break;
        }
        case FieldDescriptor::CPPTYPE_MESSAGE: {
            google::protobuf::Message& inner = *reflection->MutableMessage(&message, field);
            inner.Clear();
            if (!text.empty() && text[0] == '{') {
                rt::read_json_message(text, inner, flag);
                break;
            }
            for (const std::string& pair : split(text, ';')) {
                const auto equals = pair.find('=');
                const auto* part = equals == std::string::npos
                                       ? nullptr
                                       : inner.GetDescriptor()->FindFieldByName(pair.substr(0, equals));
                if (!part)
                    throw UsageError(flag + ": '" + pair + "' is not NAME=VALUE with NAME one of " +
                                     field_names(field));
                set_flag_value(inner, part, flag + " " + part->name(), pair.substr(equals + 1));
            }
            break;
        }
        default:
            throw UsageError(flag + ": unsupported setting type");
    }
}

}  // namespace

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
        } else if (arg == "--orthographic") {
            const std::string text = value();
            options.ortho_height = parse_number<float>(arg, text);
            if (!(options.ortho_height > 0.0f) || !std::isfinite(options.ortho_height))
                throw UsageError("--orthographic: HEIGHT must be a positive finite number, not " + text);
        } else if (arg == "--perspective") {
            options.perspective = true;
        } else if (arg == "--threads") {
            options.threads = parse_number<unsigned>(arg, value());
        } else if (arg == "--tile-size") {
            options.tile_size = parse_number<uint32_t>(arg, value());
            if (options.tile_size == 0) throw UsageError("--tile-size must be at least 1");
        } else if (arg == "--noisy") {
            options.noisy = value();
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
            set_flag_value(options.flags, field, flag_name(field), value());
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
    if (!options.noisy.empty() && !has_extension(options.noisy, ".exr") && !has_extension(options.noisy, ".png"))
        throw UsageError("--noisy: the file must be .png or .exr, not " + options.noisy);
    if (!options.camera_name.empty() && !options.camera_file.empty())
        throw UsageError("--camera and --camera-file exclude each other");
    if (options.perspective && options.ortho_height > 0.0f)
        throw UsageError("--orthographic and --perspective exclude each other");
    return options;
}

}  // namespace rtrender
