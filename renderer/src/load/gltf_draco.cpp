// KHR_draco_mesh_compression: a primitive's extension names a bufferView holding
// a Draco mesh and, per semantic, the unique id of its Draco attribute. The
// accessors the primitive names keep their count, type and component type (the
// decoded data must match them) but have no data of their own; we give them
// views of a buffer holding what Draco decoded, as three.js's GLTFLoader does.
#include <cstring>
#include <map>
#include <utility>

#include <draco/compression/decode.h>

#include "load/gltf_compressed.h"
#include "load/loader.h"

namespace rt {
namespace {

constexpr const char* kExtension = "KHR_draco_mesh_compression";

size_t components(int type) {
    switch (type) {
        case TINYGLTF_TYPE_SCALAR: return 1;
        case TINYGLTF_TYPE_VEC2: return 2;
        case TINYGLTF_TYPE_VEC3: return 3;
        case TINYGLTF_TYPE_VEC4: return 4;
        default: return 0;  // matrices are no vertex attribute
    }
}

size_t component_bytes(int component_type) {
    switch (component_type) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
        case TINYGLTF_COMPONENT_TYPE_SHORT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
        default: return 0;
    }
}

class DracoPrimitive {
  public:
    DracoPrimitive(tinygltf::Model& model, std::string what) : model_(model), what_(std::move(what)) {}

    [[noreturn]] void fail(const std::string& problem) const { throw SceneError(what_ + " " + problem); }

    void decode(tinygltf::Primitive& primitive, const tinygltf::Value& extension, DecodeBudget& budget);

  private:
    std::unique_ptr<draco::Mesh> decode_mesh(const tinygltf::Value& extension);
    tinygltf::Accessor& accessor(int index, const std::string& role);
    void write_attribute(const draco::Mesh& mesh, const std::string& semantic, int attribute_id,
                         tinygltf::Accessor& accessor);
    void write_indices(const draco::Mesh& mesh, tinygltf::Accessor& accessor);
    // Appends `bytes` as a new bufferView of the output buffer; returns its index.
    int add_view(const std::vector<unsigned char>& bytes);

    tinygltf::Model& model_;
    std::string what_;
    int buffer_ = -1;
};

template <typename T>
void append_values(const draco::PointAttribute& attribute, const draco::Mesh& mesh, size_t n,
                   std::vector<unsigned char>& out, bool& ok) {
    std::vector<T> value(n);
    out.reserve(size_t(mesh.num_points()) * n * sizeof(T));
    for (draco::PointIndex::ValueType p = 0; p < mesh.num_points() && ok; ++p) {
        ok = attribute.ConvertValue<T>(attribute.mapped_index(draco::PointIndex(p)), int8_t(n), value.data());
        const auto* bytes = reinterpret_cast<const unsigned char*>(value.data());
        out.insert(out.end(), bytes, bytes + n * sizeof(T));
    }
}

std::unique_ptr<draco::Mesh> DracoPrimitive::decode_mesh(const tinygltf::Value& extension) {
    if (!extension.IsObject()) fail("is not a JSON object");
    const tinygltf::Value& view_index = extension.Get("bufferView");
    if (!view_index.IsInt() || view_index.Get<int>() < 0 ||
        size_t(view_index.Get<int>()) >= model_.bufferViews.size())
        fail("has no bufferView, or one that does not exist");
    const tinygltf::BufferView& view = model_.bufferViews[size_t(view_index.Get<int>())];
    const std::string view_name = "bufferViews[" + std::to_string(view_index.Get<int>()) + "]";
    if (view.buffer < 0 || size_t(view.buffer) >= model_.buffers.size())
        fail("uses " + view_name + ", which refers to a buffer that does not exist");
    const std::vector<unsigned char>& buffer = model_.buffers[size_t(view.buffer)].data;
    if (view.byteOffset > buffer.size() || view.byteLength > buffer.size() - view.byteOffset)
        fail("uses " + view_name + ", which reaches past the end of buffers[" + std::to_string(view.buffer) + "] (" +
             std::to_string(buffer.size()) + " bytes)");

    draco::DecoderBuffer stream;
    stream.Init(reinterpret_cast<const char*>(buffer.data() + view.byteOffset), view.byteLength);
    const auto type = draco::Decoder::GetEncodedGeometryType(&stream);
    if (!type.ok()) fail("cannot be decoded: Draco: " + type.status().error_msg_string());
    if (type.value() != draco::TRIANGULAR_MESH)
        fail("holds a Draco point cloud, not a triangle mesh: only meshes are supported");
    draco::Decoder decoder;
    auto mesh = decoder.DecodeMeshFromBuffer(&stream);
    if (!mesh.ok()) fail("cannot be decoded: Draco: " + mesh.status().error_msg_string());
    return std::move(mesh).value();
}

tinygltf::Accessor& DracoPrimitive::accessor(int index, const std::string& role) {
    if (index < 0 || size_t(index) >= model_.accessors.size())
        fail(role + " refers to accessor " + std::to_string(index) + ", which does not exist");
    tinygltf::Accessor& accessor = model_.accessors[size_t(index)];
    if (accessor.sparse.isSparse) fail(role + " (accessors[" + std::to_string(index) + "]) is sparse");
    return accessor;
}

int DracoPrimitive::add_view(const std::vector<unsigned char>& bytes) {
    if (buffer_ < 0) {
        model_.buffers.emplace_back();
        buffer_ = int(model_.buffers.size() - 1);
    }
    std::vector<unsigned char>& data = model_.buffers[size_t(buffer_)].data;
    data.resize((data.size() + 3) / 4 * 4);  // every element aligned to its component
    tinygltf::BufferView view;
    view.buffer = buffer_;
    view.byteOffset = data.size();
    view.byteLength = bytes.size();
    data.insert(data.end(), bytes.begin(), bytes.end());
    model_.bufferViews.push_back(std::move(view));
    return int(model_.bufferViews.size() - 1);
}

void DracoPrimitive::write_attribute(const draco::Mesh& mesh, const std::string& semantic, int attribute_id,
                                     tinygltf::Accessor& accessor) {
    const std::string role = "attribute " + semantic;
    const draco::PointAttribute* attribute =
        attribute_id < 0 ? nullptr : mesh.GetAttributeByUniqueId(uint32_t(attribute_id));
    if (!attribute) fail(role + " names Draco attribute " + std::to_string(attribute_id) + ", which the mesh lacks");
    const size_t n = components(accessor.type);
    if (n == 0 || attribute->num_components() != n)
        fail(role + ": the Draco attribute has " + std::to_string(attribute->num_components()) +
             " components, its accessor " + std::to_string(n));
    if (accessor.count != mesh.num_points())
        fail(role + ": its accessor has count " + std::to_string(accessor.count) + ", but Draco decoded " +
             std::to_string(mesh.num_points()) + " points");

    std::vector<unsigned char> bytes;
    bool ok = true;
    switch (accessor.componentType) {
        case TINYGLTF_COMPONENT_TYPE_FLOAT: append_values<float>(*attribute, mesh, n, bytes, ok); break;
        case TINYGLTF_COMPONENT_TYPE_BYTE: append_values<int8_t>(*attribute, mesh, n, bytes, ok); break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: append_values<uint8_t>(*attribute, mesh, n, bytes, ok); break;
        case TINYGLTF_COMPONENT_TYPE_SHORT: append_values<int16_t>(*attribute, mesh, n, bytes, ok); break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: append_values<uint16_t>(*attribute, mesh, n, bytes, ok); break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: append_values<uint32_t>(*attribute, mesh, n, bytes, ok); break;
        default: fail(role + ": its accessor has component type " + std::to_string(accessor.componentType));
    }
    if (!ok) fail(role + ": Draco cannot convert its values to the accessor's component type");
    accessor.bufferView = add_view(bytes);
    accessor.byteOffset = 0;
}

void DracoPrimitive::write_indices(const draco::Mesh& mesh, tinygltf::Accessor& accessor) {
    const size_t corners = size_t(mesh.num_faces()) * 3;
    if (accessor.count != corners)
        fail("indices: its accessor has count " + std::to_string(accessor.count) + ", but Draco decoded " +
             std::to_string(mesh.num_faces()) + " triangles");
    std::vector<unsigned char> bytes(corners * sizeof(uint32_t));
    for (draco::FaceIndex::ValueType f = 0; f < mesh.num_faces(); ++f) {
        const draco::Mesh::Face& face = mesh.face(draco::FaceIndex(f));
        for (size_t k = 0; k < 3; ++k) {
            const uint32_t index = face[k].value();
            std::memcpy(&bytes[(size_t(f) * 3 + k) * sizeof(uint32_t)], &index, sizeof index);
        }
    }
    if (accessor.type != TINYGLTF_TYPE_SCALAR) fail("indices: its accessor is not SCALAR");
    accessor.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
    accessor.bufferView = add_view(bytes);
    accessor.byteOffset = 0;
}

void DracoPrimitive::decode(tinygltf::Primitive& primitive, const tinygltf::Value& extension, DecodeBudget& budget) {
    if (primitive.mode != TINYGLTF_MODE_TRIANGLES)
        fail("is on a primitive of mode " + std::to_string(primitive.mode) + ": only TRIANGLES are supported");
    const tinygltf::Value& attributes = extension.IsObject() ? extension.Get("attributes") : tinygltf::Value();
    if (!attributes.IsObject()) fail("has no attributes object");

    // What the accessors will take, known before Draco allocates anything.
    std::vector<std::pair<std::string, int>> wanted;  // semantic -> Draco attribute id
    size_t bytes = 0, vertices = 0;
    for (const std::string& semantic : attributes.Keys()) {
        const tinygltf::Value& id = attributes.Get(semantic);
        if (!id.IsInt()) fail("attribute " + semantic + " has an id that is not an integer");
        const auto it = primitive.attributes.find(semantic);
        if (it == primitive.attributes.end())
            fail("attribute " + semantic + " is not one of the primitive's attributes");
        const tinygltf::Accessor& a = accessor(it->second, "attribute " + semantic);
        vertices = std::max(vertices, a.count);
        bytes += std::min(a.count, kMaxSceneVertices) * components(a.type) * component_bytes(a.componentType);
        wanted.emplace_back(semantic, id.Get<int>());
    }
    if (primitive.indices < 0) fail("is on a primitive without indices, which Draco always decodes");
    const size_t corners = accessor(primitive.indices, "indices").count;
    if (vertices > kMaxSceneVertices || corners > 3 * kMaxSceneTriangles)
        fail("declares " + std::to_string(vertices) + " vertices and " + std::to_string(corners) +
             " indices, more than a scene may have");
    budget.take(bytes + corners * sizeof(uint32_t), what_);

    const std::unique_ptr<draco::Mesh> mesh = decode_mesh(extension);
    for (const auto& [semantic, id] : wanted)
        write_attribute(*mesh, semantic, id, accessor(primitive.attributes.at(semantic), "attribute " + semantic));
    write_indices(*mesh, accessor(primitive.indices, "indices"));
}

}  // namespace

void decode_draco(tinygltf::Model& model, const std::string& scene_name, DecodeBudget& budget) {
    // An accessor the same compressed data decodes into for several primitives
    // is written once; one that two different streams claim is refused.
    std::map<int, std::string> written;  // accessor -> the extension that filled it
    for (size_t m = 0; m < model.meshes.size(); ++m) {
        for (size_t p = 0; p < model.meshes[m].primitives.size(); ++p) {
            tinygltf::Primitive& primitive = model.meshes[m].primitives[p];
            const auto extension = primitive.extensions.find(kExtension);
            if (extension == primitive.extensions.end()) continue;
            const std::string what = scene_name + ": meshes[" + std::to_string(m) + "].primitives[" +
                                     std::to_string(p) + "]." + kExtension;
            const tinygltf::Value& object = extension->second;
            // Only an integer names a stream: tinygltf's GetNumberAsInt casts any
            // number, and a huge one (1e83) overflows int (decode_mesh refuses it).
            const tinygltf::Value& view = object.IsObject() ? object.Get("bufferView") : object;
            const std::string key = view.IsInt() ? std::to_string(view.Get<int>()) : "";
            std::vector<int> used{primitive.indices};
            const tinygltf::Value& attributes = object.IsObject() ? object.Get("attributes") : object;
            for (const std::string& semantic : attributes.IsObject() ? attributes.Keys() : std::vector<std::string>{}) {
                const auto it = primitive.attributes.find(semantic);
                if (it != primitive.attributes.end()) used.push_back(it->second);
            }
            size_t seen = 0;
            for (int index : used) {
                const auto it = written.find(index);
                if (it == written.end()) continue;
                if (it->second != key)
                    throw SceneError(what + " decodes into accessors[" + std::to_string(index) +
                                     "], which another Draco stream decoded into already");
                ++seen;
            }
            if (seen == used.size()) continue;  // the same stream into the same accessors
            if (seen != 0)
                throw SceneError(what + " shares some of its accessors with another primitive of the same stream");
            DracoPrimitive(model, what).decode(primitive, extension->second, budget);
            for (int index : used) written[index] = key;
            primitive.extensions.erase(extension);
        }
    }
}

}  // namespace rt
