// The parsed glTF model's node forest and meshes, turned into our world-space
// scene, at shutter open and, when nodes move (gltf_poses.h), at shutter close.
// Nothing in the model is trusted: indices are range-checked, accessors go
// through GltfAccessor, numbers must be finite, and nodes must form trees.
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include <glm/gtc/type_ptr.hpp>

#include "load/gltf_accessor.h"
#include "load/gltf_lights.h"
#include "load/gltf_loader.h"
#include "load/gltf_poses.h"
#include "load/loader.h"
#include "util/proto_limits.h"

namespace rt {
namespace {

using glm::dmat3;
using glm::dvec4;

std::string at(const char* array, size_t index) {
    return std::string(array) + "[" + std::to_string(index) + "]";
}

bool all_finite(const dmat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) return false;
    return true;
}

std::string mode_name(int mode) {
    switch (mode) {
        case TINYGLTF_MODE_POINTS: return "POINTS";
        case TINYGLTF_MODE_LINE: return "LINES";
        case TINYGLTF_MODE_LINE_LOOP: return "LINE_LOOP";
        case TINYGLTF_MODE_LINE_STRIP: return "LINE_STRIP";
        default: return std::to_string(mode);
    }
}

class GltfSceneBuilder {
  public:
    GltfSceneBuilder(const tinygltf::Model& model, const std::string& name,
                     std::span<const SceneAdditions::Motion> motions)
        : model_(model),
          name_(name),
          materials_(model, name, loaded_.scene),
          poses_(model, name, motions, loaded_.scene.warnings) {}

    LoadedScene build();

  private:
    [[noreturn]] void fail(const std::string& problem) const { throw SceneError(name_ + ": " + problem); }
    void warn(const std::string& message) { loaded_.scene.warnings.push_back(name_ + ": " + message); }

    struct Reference {
        int node;
        int parent;            // -1 for a root
        std::string referrer;  // where the reference is, for messages
    };
    // A node's transform to world space at shutter open and close.
    struct World {
        dmat4 open{1.0};
        dmat4 close{1.0};
    };
    // A primitive's accessors, their counts checked against POSITION's.
    struct Attributes {
        GltfAccessor positions;
        std::optional<GltfAccessor> normals, texcoords, indices;
    };
    std::vector<Reference> root_nodes() const;
    void add_primitive(const tinygltf::Primitive& primitive, const std::string& what, const World& world);
    // Nothing, with a warning, for a primitive without positions.
    std::optional<Attributes> read_attributes(const tinygltf::Primitive& primitive, const std::string& what);
    std::vector<uint32_t> corner_vertices(const Attributes& attributes, const std::string& what) const;
    // Appends the primitive's vertices in world space; returns the first one's index.
    size_t add_vertices(const Attributes& attributes, const World& world);
    void add_triangles(int mode, const std::vector<uint32_t>& corners, size_t count, size_t base, bool mirrored,
                       uint32_t material);
    void add_camera(const tinygltf::Node& node, const std::string& what, const World& world);
    void add_light(const tinygltf::Node& node, const std::string& what, const dmat4& world);

    const tinygltf::Model& model_;
    const std::string& name_;
    LoadedScene loaded_;
    GltfMaterials materials_;
    GltfPoses poses_;
};

std::vector<GltfSceneBuilder::Reference> GltfSceneBuilder::root_nodes() const {
    std::vector<Reference> roots;
    // tinygltf's -1 stands for no `scene` property; below that, the file gave one.
    if (model_.defaultScene < -1) fail("scene " + std::to_string(model_.defaultScene) + " does not exist");
    if (model_.defaultScene >= 0 || !model_.scenes.empty()) {
        const size_t scene = size_t(std::max(model_.defaultScene, 0));
        if (scene >= model_.scenes.size()) fail("scene " + std::to_string(scene) + " does not exist");
        for (int node : model_.scenes[scene].nodes) roots.push_back({node, -1, at("scenes", scene) + ".nodes"});
        return roots;
    }
    // No scene at all: every node that is nobody's child is a root.
    std::vector<char> is_child(model_.nodes.size(), 0);
    for (const tinygltf::Node& node : model_.nodes)
        for (int child : node.children)
            if (child >= 0 && size_t(child) < is_child.size()) is_child[size_t(child)] = 1;
    for (size_t i = 0; i < is_child.size(); ++i)
        if (!is_child[i]) roots.push_back({int(i), -1, "the root nodes"});
    return roots;
}

LoadedScene GltfSceneBuilder::build() {
    // Depth first with an explicit stack: a hostile file may nest nodes deeper
    // than the call stack allows.
    std::vector<Reference> stack = root_nodes();
    std::reverse(stack.begin(), stack.end());
    std::vector<char> visited(model_.nodes.size(), 0);
    std::vector<World> world(model_.nodes.size());
    while (!stack.empty()) {
        const Reference reference = std::move(stack.back());
        stack.pop_back();
        if (reference.node < 0 || size_t(reference.node) >= model_.nodes.size())
            fail(reference.referrer + " refers to node " + std::to_string(reference.node) + ", which does not exist");
        const size_t index = size_t(reference.node);
        const std::string what = at("nodes", index);
        if (visited[index])
            fail(what + " is reached twice (again from " + reference.referrer +
                 "): nodes must form trees, with one parent each and no cycles");
        visited[index] = 1;

        const tinygltf::Node& node = model_.nodes[index];
        const World parent = reference.parent < 0 ? World{} : world[size_t(reference.parent)];
        const GltfPoses::Local local = poses_.local(index, what);
        world[index] = {parent.open * local.open, parent.close * local.close};
        if (!all_finite(world[index].open) || !all_finite(world[index].close))
            fail(what + ": its world transform is not finite");

        if (node.mesh != -1) {
            if (node.mesh < 0 || size_t(node.mesh) >= model_.meshes.size())
                fail(what + ".mesh refers to mesh " + std::to_string(node.mesh) + ", which does not exist");
            const tinygltf::Mesh& mesh = model_.meshes[size_t(node.mesh)];
            for (size_t k = 0; k < mesh.primitives.size(); ++k)
                add_primitive(mesh.primitives[k], at("meshes", size_t(node.mesh)) + "." + at("primitives", k),
                              world[index]);
        }
        if (node.camera != -1) add_camera(node, what, world[index]);
        // Lights stand still: where they are when the shutter opens.
        add_light(node, what, world[index].open);
        for (auto child = node.children.rbegin(); child != node.children.rend(); ++child)
            stack.push_back({*child, int(index), what + ".children"});
    }
    return std::move(loaded_);
}

void GltfSceneBuilder::add_primitive(const tinygltf::Primitive& primitive, const std::string& what,
                                     const World& world) {
    const int mode = primitive.mode;
    if (mode >= TINYGLTF_MODE_POINTS && mode <= TINYGLTF_MODE_LINE_STRIP) {
        warn(what + " has mode " + mode_name(mode) + ": only triangles are rendered, skipped");
        return;
    }
    if (mode < TINYGLTF_MODE_POINTS || mode > TINYGLTF_MODE_TRIANGLE_FAN)
        fail(what + " has unknown primitive mode " + std::to_string(mode));
    const std::optional<Attributes> attributes = read_attributes(primitive, what);
    if (!attributes) return;

    // Every count here is backed by buffer data of at least that many elements.
    const size_t n = attributes->positions.count();
    const size_t c = attributes->indices ? attributes->indices->count() : n;
    if (mode == TINYGLTF_MODE_TRIANGLES && c % 3 != 0)
        fail(what + " has " + std::to_string(c) + " corners, not a multiple of 3");
    const size_t triangle_count = mode == TINYGLTF_MODE_TRIANGLES ? c / 3 : (c >= 3 ? c - 2 : 0);
    check_geometry_limits(loaded_.scene, n, triangle_count, name_ + ": " + what);
    const std::vector<uint32_t> corners = corner_vertices(*attributes, what);

    // A mirroring transform reverses the winding; we reverse it back so it keeps
    // matching the normals. (One that starts mirroring during the shutter
    // interval leaves it to face_viewer, where the normals win.)
    const bool mirrored = glm::determinant(dmat3(world.open)) < 0.0;
    const size_t base = add_vertices(*attributes, world);

    if (primitive.material < -1)
        fail(what + ".material refers to material " + std::to_string(primitive.material) + ", which does not exist");
    add_triangles(mode, corners, triangle_count, base, mirrored, materials_.material(primitive.material, what));
}

std::optional<GltfSceneBuilder::Attributes> GltfSceneBuilder::read_attributes(const tinygltf::Primitive& primitive,
                                                                              const std::string& what) {
    const auto attribute = [&](const char* semantic) {
        const auto it = primitive.attributes.find(semantic);
        return it == primitive.attributes.end() ? -1 : it->second;
    };
    if (attribute("POSITION") == -1) {
        warn(what + " has no POSITION attribute: skipped");
        return std::nullopt;
    }
    using Types = std::initializer_list<int>;
    const Types floats{TINYGLTF_COMPONENT_TYPE_FLOAT};
    const std::string prefix = name_ + ": " + what;
    Attributes a{GltfAccessor(model_, attribute("POSITION"), prefix + " POSITION", TINYGLTF_TYPE_VEC3, floats), {},
                 {}, {}};
    const size_t n = a.positions.count();
    if (attribute("NORMAL") != -1)
        a.normals.emplace(model_, attribute("NORMAL"), prefix + " NORMAL", TINYGLTF_TYPE_VEC3, floats);
    if (attribute("TEXCOORD_0") != -1) {
        a.texcoords.emplace(model_, attribute("TEXCOORD_0"), prefix + " TEXCOORD_0", TINYGLTF_TYPE_VEC2,
                            Types{TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                                  TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT});
        if (a.texcoords->component_type() != TINYGLTF_COMPONENT_TYPE_FLOAT && !a.texcoords->normalized())
            fail(what + " TEXCOORD_0 has integer components that are not normalized");
    }
    for (const auto* attr : {&a.normals, &a.texcoords})
        if (*attr && (*attr)->count() != n)
            throw SceneError((*attr)->what() + " has " + std::to_string((*attr)->count()) +
                             " elements, but POSITION has " + std::to_string(n));
    if (primitive.indices != -1)
        a.indices.emplace(model_, primitive.indices, prefix + " indices", TINYGLTF_TYPE_SCALAR,
                          Types{TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                                TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT});
    return a;
}

// The vertex of each corner, in the order the mode gives them.
std::vector<uint32_t> GltfSceneBuilder::corner_vertices(const Attributes& attributes, const std::string& what) const {
    const size_t n = attributes.positions.count();
    const size_t c = attributes.indices ? attributes.indices->count() : n;
    std::vector<uint32_t> corners(c);
    for (size_t i = 0; i < c; ++i) {
        corners[i] = attributes.indices ? attributes.indices->index_at(i) : uint32_t(i);
        if (corners[i] >= n)
            fail(what + " index " + std::to_string(corners[i]) + " (element " + std::to_string(i) +
                 ") is out of range: POSITION has " + std::to_string(n) + " elements");
    }
    return corners;
}

size_t GltfSceneBuilder::add_vertices(const Attributes& attributes, const World& world) {
    const GltfAccessor& positions = attributes.positions;
    const std::optional<GltfAccessor>& normals = attributes.normals;
    const std::optional<GltfAccessor>& texcoords = attributes.texcoords;
    Scene& scene = loaded_.scene;
    const bool moving = poses_.moving();
    const dmat3 normals_open = normal_matrix(dmat3(world.open)), normals_close = normal_matrix(dmat3(world.close));
    const auto transform_normal = [](const dmat3& matrix, vec3 normal) {
        return vec3(try_normalize(matrix * dvec3(normal)).value_or(dvec3(0.0)));
    };
    if (texcoords && !loaded_.has_texcoords) {
        scene.texcoords.assign(scene.positions.size(), vec2(0.0f));
        loaded_.has_texcoords = true;
    }
    const size_t base = scene.positions.size();
    for (size_t i = 0; i < positions.count(); ++i) {
        const std::string element = " element " + std::to_string(i);
        const vec3 p = positions.vec3_at(i);
        if (!is_finite(p)) throw SceneError(positions.what() + element + " is not finite");
        const dvec3 wp(world.open * dvec4(p, 1.0));
        const dvec3 wp_close = moving ? dvec3(world.close * dvec4(p, 1.0)) : wp;
        if (!fits_float(wp) || !fits_float(wp_close))
            throw SceneError(positions.what() + element + " is not finite after the node transform");
        scene.positions.push_back(vec3(wp));
        if (moving) scene.positions_close.push_back(vec3(wp_close));
        vec3 normal(0.0f);  // finalisation computes the missing ones
        if (normals) {
            normal = normals->vec3_at(i);
            if (!is_finite(normal)) throw SceneError(normals->what() + element + " is not finite");
        }
        scene.normals.push_back(transform_normal(normals_open, normal));
        if (moving) scene.normals_close.push_back(transform_normal(normals_close, normal));
        if (loaded_.has_texcoords) {
            const vec2 uv = texcoords ? texcoords->vec2_at(i) : vec2(0.0f);
            if (!std::isfinite(uv.x) || !std::isfinite(uv.y))
                throw SceneError(texcoords->what() + element + " is not finite");
            scene.texcoords.push_back(uv);
        }
    }
    return base;
}

// `count` triangles of `corners` in the order `mode` gives them, their vertices
// counted from `base`, wound back when the transform mirrors them.
void GltfSceneBuilder::add_triangles(int mode, const std::vector<uint32_t>& corners, size_t count, size_t base,
                                     bool mirrored, uint32_t material) {
    Scene& scene = loaded_.scene;
    const auto add = [&](uint32_t a, uint32_t b, uint32_t d) {
        scene.triangles.push_back(uvec3(base) + (mirrored ? uvec3(a, d, b) : uvec3(a, b, d)));
        scene.triangle_materials.push_back(material);
    };
    for (size_t i = 0; i < count; ++i) {
        if (mode == TINYGLTF_MODE_TRIANGLES)
            add(corners[3 * i], corners[3 * i + 1], corners[3 * i + 2]);
        else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP)  // odd triangles swap two corners to keep the winding
            add(corners[i], corners[i + 1 + i % 2], corners[i + 2 - i % 2]);
        else
            add(corners[i + 1], corners[i + 2], corners[0]);
    }
}

void GltfSceneBuilder::add_camera(const tinygltf::Node& node, const std::string& what, const World& world) {
    if (node.camera < 0 || size_t(node.camera) >= model_.cameras.size())
        fail(what + ".camera refers to camera " + std::to_string(node.camera) + ", which does not exist");
    const tinygltf::Camera& source = model_.cameras[size_t(node.camera)];
    const std::string name = at("cameras", size_t(node.camera));
    if (source.type != "perspective") {
        warn(name + " is " + in_quotes(source.type) + ", not a perspective camera: skipped");
        return;
    }
    // A glTF camera looks down its node's -Z with +Y up.
    const auto set_pose = [&](const dmat4& transform, auto& pose) {
        const dmat3 m(transform);
        const dvec3 position(transform[3]);
        const dvec3 forward = glm::normalize(m * dvec3(0.0, 0.0, -1.0));
        const dvec3 up = glm::normalize(m * dvec3(0.0, 1.0, 0.0));
        if (!fits_float(forward) || !fits_float(up) || !fits_float(position) || !fits_float(position + forward))
            fail(what + ": its transform collapses the view of " + name + " or puts it out of range");
        for (int k = 0; k < 3; ++k) {
            pose.add_position(float(position[k]));
            pose.add_target(float(position[k] + forward[k]));
            pose.add_up(float(up[k]));
        }
    };
    Camera camera;
    set_pose(world.open, camera);
    if (world.close != world.open) set_pose(world.close, *camera.mutable_shutter_close());
    // Out of float's range, the field of view becomes infinite for the limits to refuse.
    const double fov_y = glm::degrees(source.perspective.yfov);
    camera.set_fov_y(std::abs(fov_y) < 1e30 ? float(fov_y) : std::numeric_limits<float>::infinity());
    try {
        apply_limits(camera, name_ + ": " + name);
    } catch (const std::invalid_argument& e) {
        throw SceneError(e.what());
    }
    const std::string& label = !source.name.empty() ? source.name : !node.name.empty() ? node.name : name;
    loaded_.scene.cameras.push_back({label, std::move(camera)});
}

void GltfSceneBuilder::add_light(const tinygltf::Node& node, const std::string& what, const dmat4& world) {
    const auto extension = node.extensions.find("KHR_lights_punctual");
    if (extension == node.extensions.end()) return;
    const tinygltf::Value& value = extension->second;
    const std::string field = what + ".extensions.KHR_lights_punctual.light";
    if (!value.IsObject() || !value.Has("light") || !value.Get("light").IsInt())
        fail(field + " is missing or not an integer");
    const int index = value.Get("light").GetNumberAsInt();
    if (index < 0 || size_t(index) >= model_.lights.size())
        fail(field + " refers to light " + std::to_string(index) + ", which does not exist");
    const tinygltf::Light& light = model_.lights[size_t(index)];
    const std::string name = "KHR_lights_punctual.lights[" + std::to_string(index) + "]";
    Light out;
    try {
        out = read_gltf_light(light, name, world);
    } catch (const std::invalid_argument& e) {
        fail(what + ": " + e.what());
    }
    out.name = !light.name.empty() ? light.name : !node.name.empty() ? node.name : name;
    loaded_.scene.lights.push_back(std::move(out));
}

}  // namespace

LoadedScene build_gltf_scene(const tinygltf::Model& model, const std::string& scene_name,
                             std::span<const SceneAdditions::Motion> motions) {
    return GltfSceneBuilder(model, scene_name, motions).build();
}

}  // namespace rt
