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
#include "load/gltf_attributes.h"
#include "load/gltf_camera.h"
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
    using Attributes = GltfPrimitiveAttributes;
    std::vector<Reference> root_nodes() const;
    void add_primitive(const tinygltf::Primitive& primitive, const std::string& what, const World& world);
    // Nothing, with a warning, for a primitive without positions.
    std::optional<Attributes> read_attributes(const tinygltf::Primitive& primitive, const std::string& what);
    // Appends the primitive's vertices in world space; returns the first one's index.
    size_t add_vertices(const Attributes& attributes, const World& world);
    // TEXCOORD_1, COLOR_0 and TANGENT of the vertices add_vertices appends.
    void add_extra_attributes(const Attributes& attributes, const World& world);
    void add_triangles(int mode, const std::vector<uint32_t>& corners, size_t count, size_t base, bool mirrored,
                       uint32_t material);
    // `node` names the drawing node for the user: its name, or nodes[i].
    void add_mesh(size_t mesh, const World& world, const std::string& node);
    bool instanceable(size_t mesh, const World& world) const;
    void add_shared_meshes();
    void add_camera(const tinygltf::Node& node, const std::string& what, const World& world);
    void add_light(const tinygltf::Node& node, const std::string& what, const dmat4& world);

    const tinygltf::Model& model_;
    const std::string& name_;
    LoadedScene loaded_;
    GltfMaterials materials_;
    GltfPoses poses_;
    // Nodes per mesh, and the still placements of each mesh drawn more than
    // once, which become instances of one stored copy (geometry/instance.h).
    std::vector<uint32_t> mesh_uses_;
    std::vector<std::vector<World>> placements_;
    std::vector<std::vector<std::string>> placing_nodes_;  // beside placements_
    std::vector<size_t> placed_order_;  // meshes in the order of their first placement
    // Whether Scene::texcoords1, colors and tangents hold one per vertex yet.
    bool has_texcoords1_ = false, has_colors_ = false, has_tangents_ = false;
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
    mesh_uses_.assign(model_.meshes.size(), 0);
    placements_.assign(model_.meshes.size(), {});
    placing_nodes_.assign(model_.meshes.size(), {});
    for (const tinygltf::Node& node : model_.nodes)
        if (node.mesh >= 0 && size_t(node.mesh) < model_.meshes.size()) ++mesh_uses_[size_t(node.mesh)];
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
            add_mesh(size_t(node.mesh), world[index], node.name.empty() ? at("nodes", index) : node.name);
        }
        if (node.camera != -1) add_camera(node, what, world[index]);
        // Lights stand still: where they are when the shutter opens.
        add_light(node, what, world[index].open);
        for (auto child = node.children.rbegin(); child != node.children.rend(); ++child)
            stack.push_back({*child, int(index), what + ".children"});
    }
    add_shared_meshes();
    return std::move(loaded_);
}

namespace {

// Float holds the transform and its inverse: no scale beyond 1e±12 or so.
bool invertible_in_float(const dmat4& m) {
    const double det = glm::determinant(dmat3(m));
    return std::isfinite(det) && std::abs(det) > 1e-36 && std::abs(det) < 1e36 && fits_float(dvec3(m[3]));
}

// The blend (1 - t) open + t close stays invertible for every t in [0, 1]:
// its determinant, a cubic in t, is fixed by four values and must keep the
// sign it has at open, well away from zero, at its ends and turning points.
bool blend_stays_invertible(const dmat4& open, const dmat4& close) {
    const auto det = [&](double t) { return glm::determinant((1.0 - t) * dmat3(open) + t * dmat3(close)); };
    const double d0 = det(0.0), d1 = det(1.0 / 3.0), d2 = det(2.0 / 3.0), d3 = det(1.0);
    // Newton's forward differences to the power basis a + b t + c t^2 + e t^3.
    const double a = d0;
    const double e = 4.5 * (d3 - 3.0 * d2 + 3.0 * d1 - d0);
    const double c = 4.5 * (d2 - 2.0 * d1 + d0) - e;
    const double b = 3.0 * (d1 - d0) - c / 3.0 - e / 9.0;
    const auto cubic = [&](double t) { return a + t * (b + t * (c + t * e)); };
    double low = std::min(std::abs(d0), std::abs(d3));
    bool same_sign = (d0 > 0.0) == (d3 > 0.0);
    // Turning points: roots of b + 2c t + 3e t^2 inside (0, 1), in the form
    // that keeps a tiny leading coefficient (a rounded-off e) from cancelling.
    const double qa = 3.0 * e, qb = 2.0 * c, qc = b;
    std::vector<double> turns;
    if (const double disc = qb * qb - 4.0 * qa * qc; disc >= 0.0) {
        const double q = -0.5 * (qb + std::copysign(std::sqrt(disc), qb));
        if (q != 0.0) turns.push_back(qc / q);
        if (qa != 0.0) turns.push_back(q / qa);
    }
    for (double t : turns) {
        if (!(t > 0.0 && t < 1.0)) continue;
        const double v = cubic(t);
        same_sign = same_sign && (v > 0.0) == (d0 > 0.0);
        low = std::min(low, std::abs(v));
    }
    // Relative to the ends: a blend a million times thinner than the mesh at
    // open or close is as good as flat in float (and rounding hides a zero).
    return same_sign && low > 1e-6 * std::max(std::abs(d0), std::abs(d3));
}

}  // namespace

// A mesh that several nodes draw is stored once and instanced under
// transforms that can be inverted, at every time of the shutter for a moving
// node; elsewhere (flattened to a plane at some time) its triangles are
// copied into world space as before.
bool GltfSceneBuilder::instanceable(size_t mesh, const World& world) const {
    if (mesh_uses_[mesh] < 2 || !invertible_in_float(world.open)) return false;
    return world.open == world.close ||
           (invertible_in_float(world.close) && blend_stays_invertible(world.open, world.close));
}

void GltfSceneBuilder::add_mesh(size_t mesh, const World& world, const std::string& node) {
    if (instanceable(mesh, world)) {
        if (placements_[mesh].empty()) placed_order_.push_back(mesh);
        placements_[mesh].push_back(world);
        placing_nodes_[mesh].push_back(node);
        return;
    }
    const tinygltf::Mesh& m = model_.meshes[mesh];
    for (size_t k = 0; k < m.primitives.size(); ++k)
        add_primitive(m.primitives[k], at("meshes", mesh) + "." + at("primitives", k), world);
}

// After every node: the shared meshes' triangles are the tail of the scene's,
// in their own space; a mesh placed only once after all is copied like any.
void GltfSceneBuilder::add_shared_meshes() {
    Scene& scene = loaded_.scene;
    std::vector<size_t> shared;
    for (size_t mesh : placed_order_) {
        if (placements_[mesh].size() == 1) {
            const tinygltf::Mesh& m = model_.meshes[mesh];
            for (size_t k = 0; k < m.primitives.size(); ++k)
                add_primitive(m.primitives[k], at("meshes", mesh) + "." + at("primitives", k), placements_[mesh][0]);
        } else {
            shared.push_back(mesh);
        }
    }
    for (size_t mesh : shared) {
        const uint32_t first = uint32_t(scene.triangles.size());
        const tinygltf::Mesh& m = model_.meshes[mesh];
        for (size_t k = 0; k < m.primitives.size(); ++k)
            add_primitive(m.primitives[k], at("meshes", mesh) + "." + at("primitives", k), World{});
        const uint32_t number = uint32_t(scene.meshes.size());
        scene.meshes.push_back({first, uint32_t(scene.triangles.size()) - first});
        const auto affine = [](const dmat4& m) { return Affine{mat3(dmat3(m)), vec3(dvec3(m[3]))}; };
        for (const World& placement : placements_[mesh])
            scene.instances.push_back(Instance::make(number, affine(placement.open), affine(placement.close)));
        scene.instance_names.insert(scene.instance_names.end(), placing_nodes_[mesh].begin(), placing_nodes_[mesh].end());
    }
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
    const std::vector<uint32_t> corners = corner_vertices(*attributes, name_ + ": " + what);

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
    if (attribute_accessor(primitive, "POSITION") == -1) {
        warn(what + " has no POSITION attribute: skipped");
        return std::nullopt;
    }
    return read_primitive_attributes(model_, primitive, name_ + ": " + what);
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
    add_extra_attributes(attributes, world);
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

// Like texcoords: a vector stays empty until a primitive has the attribute, then
// the vertices before it get the default, as do primitives without it later.
void GltfSceneBuilder::add_extra_attributes(const Attributes& attributes, const World& world) {
    Scene& scene = loaded_.scene;
    const size_t n = attributes.positions.count();
    const auto start = [&](const std::optional<GltfAccessor>& accessor, bool& has, auto& values, auto fallback) {
        if (accessor && !has) {
            values.assign(scene.positions.size(), fallback);
            has = true;
        }
        if (has && !accessor) values.insert(values.end(), n, fallback);
        return has && accessor;
    };
    const auto finite = [](glm::vec4 v) { return is_finite(vec3(v)) && std::isfinite(v.w); };
    const auto not_finite = [](const GltfAccessor& accessor, size_t i) {
        return SceneError(accessor.what() + " element " + std::to_string(i) + " is not finite");
    };
    if (start(attributes.texcoords1, has_texcoords1_, scene.texcoords1, vec2(0.0f)))
        for (size_t i = 0; i < n; ++i) {
            const vec2 uv = attributes.texcoords1->vec2_at(i);
            if (!finite(glm::vec4(uv, 0.0f, 0.0f))) throw not_finite(*attributes.texcoords1, i);
            scene.texcoords1.push_back(uv);
        }
    if (start(attributes.colors, has_colors_, scene.colors, glm::vec4(1.0f)))
        for (size_t i = 0; i < n; ++i) {
            const glm::vec4 color = attributes.colors->vec4_at(i);  // a VEC3 colour gets alpha 1
            if (!finite(color)) throw not_finite(*attributes.colors, i);
            scene.colors.push_back(color);
        }
    // Tangents follow the surface like positions do (the upper 3x3, not the
    // normal matrix); a mirroring transform flips the bitangent, so w too.
    // They take the shutter-open pose only: Scene has no tangents at close.
    // A tangent that does not normalise becomes (0, 0, 0, 0), "none", for
    // finalisation to compute like a missing one.
    if (start(attributes.tangents, has_tangents_, scene.tangents, glm::vec4(0.0f))) {
        const dmat3 m(world.open);
        const double handedness = glm::determinant(m) < 0.0 ? -1.0 : 1.0;
        for (size_t i = 0; i < n; ++i) {
            const glm::vec4 t = attributes.tangents->vec4_at(i);
            if (!finite(t)) throw not_finite(*attributes.tangents, i);
            const std::optional<dvec3> direction = try_normalize(m * dvec3(vec3(t)));
            const double w = (t.w < 0.0f ? -1.0 : 1.0) * handedness;
            scene.tangents.push_back(direction && fits_float(*direction) ? glm::vec4(vec3(*direction), float(w))
                                                                         : glm::vec4(0.0f));
        }
    }
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
    try {
        read_gltf_projection(source, name, camera);
    } catch (const std::invalid_argument& e) {
        fail(e.what());
    }
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
