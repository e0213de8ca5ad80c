// Helpers for the loader tests: scenes are mostly generated in the tests, so that
// each hostile variant is one visible change to a valid file.
#pragma once

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>

#include "load/loader.h"

namespace rt::testing {

using Json = nlohmann::json;
using Bytes = std::vector<unsigned char>;

// A fresh directory under the system's temporary folder, removed afterwards.
class TempDir {
  public:
    TempDir() {
        std::string pattern = (std::filesystem::temp_directory_path() / "rt_loader_XXXXXX").string();
        if (!mkdtemp(pattern.data())) throw std::runtime_error("mkdtemp failed");
        path_ = pattern;
    }
    ~TempDir() {
        std::error_code ignored;
        std::filesystem::remove_all(path_, ignored);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;

    const std::filesystem::path& path() const { return path_; }

    std::filesystem::path write(const std::string& name, const std::string& content) const {
        return write(name, Bytes(content.begin(), content.end()));
    }
    std::filesystem::path write(const std::string& name, const Bytes& content) const {
        const std::filesystem::path file = path_ / name;
        std::filesystem::create_directories(file.parent_path());
        std::ofstream(file, std::ios::binary).write(reinterpret_cast<const char*>(content.data()),
                                                     std::streamsize(content.size()));
        return file;
    }

  private:
    std::filesystem::path path_;
};

inline std::string base64(const Bytes& bytes) {
    static const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (size_t i = 0; i < bytes.size(); i += 3) {
        const uint32_t b0 = bytes[i], b1 = i + 1 < bytes.size() ? bytes[i + 1] : 0,
                       b2 = i + 2 < bytes.size() ? bytes[i + 2] : 0;
        const uint32_t triple = b0 << 16 | b1 << 8 | b2;
        out += digits[triple >> 18 & 63];
        out += digits[triple >> 12 & 63];
        out += i + 1 < bytes.size() ? digits[triple >> 6 & 63] : '=';
        out += i + 2 < bytes.size() ? digits[triple & 63] : '=';
    }
    return out;
}

template <typename T>
void append(Bytes& bytes, const std::vector<T>& values) {
    const size_t at = bytes.size();
    bytes.resize(at + values.size() * sizeof(T));
    if (!values.empty()) std::memcpy(bytes.data() + at, values.data(), values.size() * sizeof(T));
}

// An RGB PNG from 8-bit values, row by row from the top.
inline Bytes png(int width, int height, const std::vector<unsigned char>& rgb) {
    Bytes out;
    stbi_write_png_to_func(
        [](void* context, void* data, int size) {
            auto* bytes = static_cast<Bytes*>(context);
            bytes->insert(bytes->end(), static_cast<unsigned char*>(data), static_cast<unsigned char*>(data) + size);
        },
        &out, width, height, 3, rgb.data(), width * 3);
    return out;
}

// A minimal glTF document: one buffer holding `data` (as a data: URI), and
// helpers to describe views and accessors into it.
// A GLB of `doc` (the JSON chunk, padded with spaces) and `bin` (the BIN chunk, padded with zeros).
inline Bytes glb_container(const Json& doc, Bytes bin) {
    std::string text = doc.dump();
    while (text.size() % 4 != 0) text += ' ';
    while (bin.size() % 4 != 0) bin.push_back(0);
    Bytes glb;
    const auto u32 = [&](uint32_t v) { append(glb, std::vector<uint32_t>{v}); };
    u32(0x46546C67u);  // "glTF"
    u32(2);
    u32(uint32_t(12 + 8 + text.size() + 8 + bin.size()));
    u32(uint32_t(text.size()));
    u32(0x4E4F534Au);  // JSON
    glb.insert(glb.end(), text.begin(), text.end());
    u32(uint32_t(bin.size()));
    u32(0x004E4942u);  // BIN
    glb.insert(glb.end(), bin.begin(), bin.end());
    return glb;
}

struct GltfDoc {
    Json json = Json::parse(R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": []}],
                                "nodes": [], "meshes": [], "buffers": [], "bufferViews": [], "accessors": []})");
    Bytes data;

    // Appends values to the buffer, as a new buffer view with one accessor
    // over all of them; returns the accessor index.
    template <typename T>
    int add_accessor(const std::vector<T>& values, int component_type, const char* type, size_t components) {
        while (data.size() % 4 != 0) data.push_back(0);
        const size_t offset = data.size();
        append(data, values);
        json["bufferViews"].push_back(
            {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", values.size() * sizeof(T)}});
        json["accessors"].push_back({{"bufferView", json["bufferViews"].size() - 1},
                                     {"componentType", component_type},
                                     {"count", values.size() / components},
                                     {"type", type}});
        return int(json["accessors"].size() - 1);
    }
    int add_vec3(const std::vector<float>& v) { return add_accessor(v, 5126, "VEC3", 3); }
    int add_vec2(const std::vector<float>& v) { return add_accessor(v, 5126, "VEC2", 2); }
    int add_indices(const std::vector<uint32_t>& v) { return add_accessor(v, 5125, "SCALAR", 1); }

    // A mesh with one primitive and a root node showing it; returns the node.
    int add_mesh_node(const Json& primitive, const Json& node_fields = Json::object()) {
        json["meshes"].push_back({{"primitives", Json::array({primitive})}});
        Json node = node_fields;
        node["mesh"] = json["meshes"].size() - 1;
        return add_root(node);
    }
    int add_root(const Json& node) {
        json["nodes"].push_back(node);
        const int index = int(json["nodes"].size() - 1);
        json["scenes"][0]["nodes"].push_back(index);
        return index;
    }

    // The document with its buffer embedded as a data: URI.
    std::string text() const {
        Json out = json;
        if (!data.empty())
            out["buffers"] = Json::array(
                {{{"byteLength", data.size()}, {"uri", "data:application/octet-stream;base64," + base64(data)}}});
        return out.dump();
    }

    // The document as a GLB, its buffer in the BIN chunk.
    Bytes glb() const {
        Json out = json;
        out["buffers"] = Json::array({{{"byteLength", data.size()}}});
        return glb_container(out, data);
    }
};

inline Scene load_text(const std::string& text, const std::string& name) {
    return load_scene_from_memory(std::as_bytes(std::span(text.data(), text.size())), name);
}

inline Scene load_bytes(const Bytes& bytes, const std::string& name) {
    return load_scene_from_memory(std::as_bytes(std::span(bytes.data(), bytes.size())), name);
}

// The message of the SceneError `load` throws; fails the test when it throws
// nothing or something else.
inline std::string scene_error(const std::function<void()>& load) {
    try {
        load();
    } catch (const SceneError& e) {
        return e.what();
    } catch (const std::exception& e) {
        ADD_FAILURE() << "expected SceneError, got another exception: " << e.what();
        return "";
    }
    ADD_FAILURE() << "expected SceneError, nothing was thrown";
    return "";
}

inline bool contains(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

inline bool has_warning(const Scene& scene, const std::string& part) {
    for (const std::string& warning : scene.warnings)
        if (contains(warning, part)) return true;
    return false;
}

}  // namespace rt::testing
