// The JSON stage of compressed geometry (gltf_compressed.h): what must be
// checked or filled in before tinygltf 2.7 parses the document, because of how
// it reads extension objects and buffers.
#include <climits>

#include "load/gltf_compressed.h"
#include "load/loader.h"

namespace rt {
namespace {

using Json = nlohmann::json;

constexpr const char* kMeshopt = "EXT_meshopt_compression";
constexpr const char* kDraco = "KHR_draco_mesh_compression";

Json* member(Json& object, const char* key) {
    if (!object.is_object()) return nullptr;
    const auto it = object.find(key);
    return it == object.end() ? nullptr : &*it;
}

// `element`.extensions.`name`, checked to be an object whose integers (and
// those of its objects, as Draco's attributes) fit an int; null when absent.
Json* extension(Json& element, const char* name, const std::string& what) {
    Json* extensions = member(element, "extensions");
    Json* object = extensions ? member(*extensions, name) : nullptr;
    if (!object) return nullptr;
    if (!object->is_object()) throw SceneError(what + " is not a JSON object");
    const auto check = [&](const Json& values, const std::string& prefix) {
        for (const auto& [key, value] : values.items()) {
            const bool fits = value.is_number_unsigned()  ? value.get<uint64_t>() <= uint64_t(INT_MAX)
                              : value.is_number_integer() ? value.get<int64_t>() >= INT_MIN
                                                          : true;
            if (!fits) throw SceneError(what + "." + prefix + key + " " + value.dump() + " is out of range");
        }
    };
    check(*object, "");
    if (Json* attributes = member(*object, "attributes"); attributes && attributes->is_object())
        check(*attributes, "attributes.");
    return object;
}

bool is_fallback(Json& buffer) {
    if (!buffer.is_object() || buffer.contains("uri")) return false;
    Json* extensions = member(buffer, "extensions");
    Json* object = extensions ? member(*extensions, kMeshopt) : nullptr;
    Json* fallback = object ? member(*object, "fallback") : nullptr;
    return fallback && fallback->is_boolean() && fallback->get<bool>();
}

// tinygltf 2.7 refuses a buffer without data, which is what a meshopt fallback
// buffer is; a 4-byte placeholder lets it parse, and no view reads it once
// decode_meshopt() has pointed the compressed views at their decoded bytes.
bool add_fallback_placeholders(Json& doc) {
    Json* buffers = member(doc, "buffers");
    if (!buffers || !buffers->is_array()) return false;
    bool changed = false;
    for (Json& buffer : *buffers) {
        if (!is_fallback(buffer)) continue;
        buffer["uri"] = "data:application/octet-stream;base64,AAAAAA==";
        buffer["byteLength"] = size_t(4);  // unsigned, as check_references reads it
        changed = true;
    }
    return changed;
}

void check_meshopt_views(Json& doc, const std::string& name) {
    Json* views = member(doc, "bufferViews");
    if (!views || !views->is_array()) return;
    for (size_t i = 0; i < views->size(); ++i)
        extension((*views)[i], kMeshopt, name + ": bufferViews[" + std::to_string(i) + "]." + kMeshopt);
}

// Checks every Draco extension object; gives the indices accessors it must a placeholder view.
bool prepare_draco_primitives(Json& doc, const std::string& name) {
    Json* meshes = member(doc, "meshes");
    Json* accessors = member(doc, "accessors");
    Json* views = member(doc, "bufferViews");
    if (!meshes || !meshes->is_array()) return false;
    bool changed = false;
    for (size_t m = 0; m < meshes->size(); ++m) {
        Json* primitives = member((*meshes)[m], "primitives");
        if (!primitives || !primitives->is_array()) continue;
        for (size_t p = 0; p < primitives->size(); ++p) {
            Json& primitive = (*primitives)[p];
            const std::string what =
                name + ": meshes[" + std::to_string(m) + "].primitives[" + std::to_string(p) + "]." + kDraco;
            const Json* object = extension(primitive, kDraco, what);
            const Json* indices = member(primitive, "indices");
            if (!object || !indices || !indices->is_number_unsigned() || !accessors || !accessors->is_array() ||
                indices->get<uint64_t>() >= accessors->size() || !views || !views->is_array() || views->empty())
                continue;
            Json& accessor = (*accessors)[indices->get<size_t>()];
            if (!accessor.is_object() || accessor.contains("bufferView")) continue;
            const Json* view = object->contains("bufferView") ? &(*object)["bufferView"] : nullptr;
            const bool valid = view && view->is_number_unsigned() && view->get<uint64_t>() < views->size();
            accessor["bufferView"] = valid ? view->get<size_t>() : size_t(0);
            changed = true;
        }
    }
    return changed;
}

}  // namespace

bool prepare_compressed_json(nlohmann::json& doc, const std::string& scene_name) {
    check_meshopt_views(doc, scene_name);
    const bool draco = prepare_draco_primitives(doc, scene_name);
    return add_fallback_placeholders(doc) || draco;
}

}  // namespace rt
