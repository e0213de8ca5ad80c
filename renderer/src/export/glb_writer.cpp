#include "export/glb_writer.h"

#include <stdexcept>
#include <utility>

namespace rt {
namespace {

using Json = nlohmann::json;

// glTF's enumerations (glTF 2.0 specification, section 5).
constexpr int kFloat = 5126;
constexpr int kUnsignedInt = 5125;
constexpr int kArrayBuffer = 34962;
constexpr int kElementArrayBuffer = 34963;

static_assert(sizeof(vec3) == 12 && sizeof(vec2) == 8 && sizeof(glm::vec4) == 16,
              "attributes are copied as packed floats");

void append_u32(std::string& out, uint32_t v) {
    for (int shift = 0; shift < 32; shift += 8) out.push_back(char((v >> shift) & 0xff));
}

}  // namespace

Json gltf_array3(vec3 v) { return Json::array({v.x, v.y, v.z}); }

GlbWriter::GlbWriter()
    : doc_(Json{{"asset", {{"version", "2.0"}, {"generator", "rt export_glb"}}}, {"scene", 0}}) {}

int GlbWriter::append(const char* array, Json item) {
    Json& items = doc_[array];
    items.push_back(std::move(item));
    return int(items.size() - 1);
}

int GlbWriter::add_view(const void* data, size_t bytes, int target) {
    bin_.append((4 - bin_.size() % 4) % 4, '\0');
    Json view = {{"buffer", 0}, {"byteOffset", bin_.size()}, {"byteLength", bytes}};
    if (target != 0) view["target"] = target;
    bin_.append(static_cast<const char*>(data), bytes);
    return append("bufferViews", std::move(view));
}

int GlbWriter::add_accessor(int view, int component_type, size_t count, const char* type) {
    return append("accessors",
                  {{"bufferView", view}, {"componentType", component_type}, {"count", count}, {"type", type}});
}

int GlbWriter::add_positions(const std::vector<vec3>& positions) {
    const int accessor = add_vec3s(positions);
    vec3 lo(kInfinity), hi(-kInfinity);
    for (const vec3& p : positions) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    // glTF requires the bounds of POSITION; viewers size their boxes by them.
    doc_["accessors"][size_t(accessor)]["min"] = gltf_array3(lo);
    doc_["accessors"][size_t(accessor)]["max"] = gltf_array3(hi);
    return accessor;
}

int GlbWriter::add_vec2s(const std::vector<vec2>& values) {
    return add_accessor(add_view(values.data(), values.size() * sizeof(vec2), kArrayBuffer), kFloat, values.size(),
                        "VEC2");
}

int GlbWriter::add_vec3s(const std::vector<vec3>& values) {
    return add_accessor(add_view(values.data(), values.size() * sizeof(vec3), kArrayBuffer), kFloat, values.size(),
                        "VEC3");
}

int GlbWriter::add_vec4s(const std::vector<glm::vec4>& values) {
    return add_accessor(add_view(values.data(), values.size() * sizeof(glm::vec4), kArrayBuffer), kFloat,
                        values.size(), "VEC4");
}

int GlbWriter::add_indices(const std::vector<uint32_t>& indices) {
    const int view = add_view(indices.data(), indices.size() * sizeof(uint32_t), kElementArrayBuffer);
    return add_accessor(view, kUnsignedInt, indices.size(), "SCALAR");
}

int GlbWriter::add_node(Json node) {
    const int index = append("nodes", std::move(node));
    scene_nodes_.push_back(index);
    return index;
}

// The GLB container (glTF 2.0 specification, section 4.4): a 12-byte header,
// the JSON chunk padded with spaces and the BIN chunk padded with zeros, both
// to 4 bytes.
std::string GlbWriter::container(Json scene) {
    if (!scene_nodes_.empty()) scene["nodes"] = scene_nodes_;  // glTF forbids empty arrays
    doc_["scenes"] = Json::array({std::move(scene)});
    bin_.append((4 - bin_.size() % 4) % 4, '\0');
    if (!bin_.empty()) doc_["buffers"] = Json::array({{{"byteLength", bin_.size()}}});
    // Names from OBJ files may not be UTF-8; JSON must be.
    std::string json = doc_.dump(-1, ' ', false, Json::error_handler_t::replace);
    json.append((4 - json.size() % 4) % 4, ' ');
    const uint64_t length = 12 + 8 + json.size() + (bin_.empty() ? 0 : 8 + bin_.size());
    if (length > UINT32_MAX)
        throw std::length_error("export_glb(): the scene needs " + std::to_string(length) +
                                " bytes, more than a GLB can hold (4 GiB)");
    std::string glb;
    glb.reserve(length);
    append_u32(glb, 0x46546C67u);  // "glTF"
    append_u32(glb, 2);
    append_u32(glb, uint32_t(length));
    append_u32(glb, uint32_t(json.size()));
    append_u32(glb, 0x4E4F534Au);  // "JSON"
    glb += json;
    if (!bin_.empty()) {
        append_u32(glb, uint32_t(bin_.size()));
        append_u32(glb, 0x004E4942u);  // "BIN\0"
        glb += bin_;
    }
    return glb;
}

}  // namespace rt
