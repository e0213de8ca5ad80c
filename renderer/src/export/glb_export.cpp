// The scene's geometry, lights, cameras and background mapped onto glTF. The
// document's bookkeeping is glb_writer.cpp's and the materials are
// glb_materials.cpp's, so what is here is only where each part of a Scene goes.
#include "export/glb_export.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include <glm/gtc/quaternion.hpp>

#include "util/proto_limits.h"
#include "integrator/sampling.h"
#include "export/glb_materials.h"
#include "export/glb_writer.h"

namespace rt {
namespace {

using Json = nlohmann::json;

// The UV sphere standing in for an analytic sphere: enough facets for a round
// outline in the viewer, few enough to keep the file small.
constexpr uint32_t kSphereSegments = 48;  // around the axis
constexpr uint32_t kSphereRings = 24;     // from pole to pole

// A background as rt.SceneExtras writes it, so that the GLB loads back with it.
Json background_json(const Background& background) {
    if (background.solid()) return {{"background", gltf_array3(background.top)}};
    return {{"background_gradient",
             {{"bottom", gltf_array3(background.bottom)},
              {"horizon", gltf_array3(background.horizon)},
              {"top", gltf_array3(background.top)}}}};
}

// A UV sphere of radius 1 around the origin, wound counterclockwise seen from
// outside; its normals are its positions.
struct UnitSphere {
    std::vector<vec3> positions;
    std::vector<uint32_t> indices;
};

UnitSphere unit_sphere() {
    UnitSphere sphere;
    for (uint32_t ring = 0; ring <= kSphereRings; ++ring) {
        const float theta = kPi * float(ring) / float(kSphereRings);
        for (uint32_t segment = 0; segment <= kSphereSegments; ++segment) {
            const float phi = 2.0f * kPi * float(segment) / float(kSphereSegments);
            sphere.positions.emplace_back(-std::cos(phi) * std::sin(theta), std::cos(theta),
                                          std::sin(phi) * std::sin(theta));
        }
    }
    const auto vertex = [](uint32_t ring, uint32_t segment) { return ring * (kSphereSegments + 1) + segment; };
    for (uint32_t ring = 0; ring < kSphereRings; ++ring) {
        for (uint32_t segment = 0; segment < kSphereSegments; ++segment) {
            const uint32_t a = vertex(ring, segment + 1), b = vertex(ring, segment);
            const uint32_t c = vertex(ring + 1, segment), d = vertex(ring + 1, segment + 1);
            // The triangles touching a pole would have no area.
            if (ring != 0) sphere.indices.insert(sphere.indices.end(), {a, b, d});
            if (ring != kSphereRings - 1) sphere.indices.insert(sphere.indices.end(), {b, c, d});
        }
    }
    return sphere;
}

// The shortest turn of -Z onto the unit vector d (half-way vector; about X when opposite).
glm::quat rotation_from_minus_z(vec3 d) {
    const vec3 a(0.0f, 0.0f, -1.0f);
    const float w = 1.0f + glm::dot(a, d);
    return w < 1e-6f ? glm::quat(0.0f, 1.0f, 0.0f, 0.0f) : glm::normalize(glm::quat(w, glm::cross(a, d)));
}

const char* light_type(LightKind kind) {
    return kind == SPOT ? "spot" : kind == DIRECTIONAL ? "directional" : "point";
}

class GlbExporter {
  public:
    explicit GlbExporter(const Scene& scene) : scene_(scene) {}

    std::string run();

  private:
    std::vector<std::vector<uint32_t>> triangles_by_material(size_t first, size_t count) const;
    int add_triangle_mesh(const std::string& name, size_t first, size_t count);
    Json primitive(size_t material, const std::vector<uint32_t>& vertices, const std::vector<uint32_t>& indices);
    void add_tangents(const std::vector<uint32_t>& vertices, Json& attributes);

    void add_meshes();
    void add_spheres();
    void add_lights();
    void add_cameras();

    const Scene& scene_;
    GlbWriter writer_;
};

// The triangles [first, first + count) of each material, in the scene's order: one primitive each.
std::vector<std::vector<uint32_t>> GlbExporter::triangles_by_material(size_t first, size_t count) const {
    std::vector<std::vector<uint32_t>> by_material(scene_.materials.size());
    for (size_t t = first; t < first + count; ++t) {
        const uint32_t material = scene_.triangle_materials[t];
        if (material >= by_material.size())
            throw std::invalid_argument("export_glb(): triangle " + std::to_string(t) + " has material " +
                                        std::to_string(material) + ", but the scene has " +
                                        std::to_string(by_material.size()));
        by_material[material].push_back(uint32_t(t));
    }
    return by_material;
}

// The primitive of one material: the scene's `vertices` (in their new order)
// and `indices` into that order.
Json GlbExporter::primitive(size_t material, const std::vector<uint32_t>& vertices,
                            const std::vector<uint32_t>& indices) {
    std::vector<vec3> positions, normals;
    std::vector<vec2> texcoords, texcoords1;
    std::vector<glm::vec4> colors;
    for (uint32_t v : vertices) {
        positions.push_back(scene_.positions[v]);
        normals.push_back(scene_.normals[v]);
        if (!scene_.texcoords.empty()) texcoords.push_back(scene_.texcoords[v]);
        if (!scene_.texcoords1.empty()) texcoords1.push_back(scene_.texcoords1[v]);
        if (!scene_.colors.empty()) colors.push_back(scene_.colors[v]);
    }
    Json attributes = {{"POSITION", writer_.add_positions(positions)}, {"NORMAL", writer_.add_vec3s(normals)}};
    // The viewer draws what shading reads: both UV sets and the vertex colours.
    if (!texcoords.empty()) attributes["TEXCOORD_0"] = writer_.add_vec2s(texcoords);
    if (!texcoords1.empty()) attributes["TEXCOORD_1"] = writer_.add_vec2s(texcoords1);
    if (!colors.empty()) attributes["COLOR_0"] = writer_.add_vec4s(colors);
    if (has_texture(scene_, scene_.materials[material].normal_texture)) add_tangents(vertices, attributes);
    return {{"attributes", attributes},
            {"indices", writer_.add_indices(indices)},
            {"material", material},
            {"mode", kGltfTriangles}};
}

// A glTF mesh of triangles [first, first + count); -1 when there are none.
int GlbExporter::add_triangle_mesh(const std::string& name, size_t first, size_t count) {
    const std::vector<std::vector<uint32_t>> by_material = triangles_by_material(first, count);
    // Each primitive holds only the vertices its triangles use, renumbered.
    constexpr uint32_t kUnused = UINT32_MAX;
    std::vector<uint32_t> local(scene_.positions.size(), kUnused);
    Json primitives = Json::array();
    for (size_t material = 0; material < by_material.size(); ++material) {
        if (by_material[material].empty()) continue;
        std::vector<uint32_t> vertices, indices;
        for (uint32_t t : by_material[material]) {
            for (int k = 0; k < 3; ++k) {
                const uint32_t v = scene_.triangles[t][k];
                if (local[v] == kUnused) {
                    local[v] = uint32_t(vertices.size());
                    vertices.push_back(v);
                }
                indices.push_back(local[v]);
            }
        }
        for (uint32_t v : vertices) local[v] = kUnused;  // free for the next material's numbering
        primitives.push_back(primitive(material, vertices, indices));
    }
    if (primitives.empty()) return -1;
    return writer_.append("meshes", {{"name", name}, {"primitives", std::move(primitives)}});
}

// The world-space triangles as one mesh; each shared mesh once, and a node
// per instance with its transform, so the viewer gets the sharing too.
void GlbExporter::add_meshes() {
    const int world = add_triangle_mesh("triangles", 0, scene_.world_triangles());
    if (world >= 0) writer_.add_node({{"name", "triangles"}, {"mesh", world}});
    std::vector<int> meshes;
    for (size_t m = 0; m < scene_.meshes.size(); ++m)
        meshes.push_back(add_triangle_mesh("shared mesh " + std::to_string(m), scene_.meshes[m].first_triangle,
                                           scene_.meshes[m].triangle_count));
    for (size_t i = 0; i < scene_.instances.size(); ++i) {
        const Instance& instance = scene_.instances[i];
        if (meshes[instance.mesh] < 0) continue;
        const glm::mat3& m = instance.to_world.linear;
        const vec3& t = instance.to_world.translation;
        Json matrix = Json::array();  // column-major, as glTF wants it
        for (int c = 0; c < 3; ++c) matrix.insert(matrix.end(), {m[c][0], m[c][1], m[c][2], 0.0f});
        matrix.insert(matrix.end(), {t.x, t.y, t.z, 1.0f});
        writer_.add_node({{"name", "instance " + std::to_string(i)}, {"mesh", meshes[instance.mesh]}, {"matrix", matrix}});
    }
}

// The tangents a normal-mapped primitive's vertices have (the file's or
// MikkTSpace's), so that the viewer bends its normals in the same frame
// rather than in one of its own. glTF wants w = +-1 everywhere: a vertex
// without one gets a tangent perpendicular to its normal.
void GlbExporter::add_tangents(const std::vector<uint32_t>& vertices, Json& attributes) {
    if (scene_.tangents.empty()) return;
    std::vector<glm::vec4> tangents;
    for (uint32_t v : vertices) {
        glm::vec4 t = scene_.tangents[v];
        if (t.w == 0.0f) {
            const vec3 n = scene_.normals[v];
            const vec3 axis = std::abs(n.x) < 0.9f ? vec3(1.0f, 0.0f, 0.0f) : vec3(0.0f, 1.0f, 0.0f);
            t = glm::vec4(glm::normalize(glm::cross(n, axis)), 1.0f);
        }
        tangents.push_back(t);
    }
    if (std::all_of(vertices.begin(), vertices.end(), [&](uint32_t v) { return scene_.tangents[v].w == 0.0f; })) return;
    attributes["TANGENT"] = writer_.add_vec4s(tangents);
}

void GlbExporter::add_spheres() {
    if (scene_.spheres.empty()) return;
    // One tessellation for all: each sphere's node scales and places it.
    const UnitSphere unit = unit_sphere();
    const int positions = writer_.add_positions(unit.positions);
    const int normals = writer_.add_vec3s(unit.positions);
    const int indices = writer_.add_indices(unit.indices);
    for (size_t i = 0; i < scene_.spheres.size(); ++i) {
        const Sphere& sphere = scene_.spheres[i];
        const std::string name = "sphere " + std::to_string(i);
        const int mesh =
            writer_.append("meshes", {{"name", name},
                                      {"primitives", {{{"attributes", {{"POSITION", positions}, {"NORMAL", normals}}},
                                                       {"indices", indices},
                                                       {"material", sphere.material},
                                                       {"mode", kGltfTriangles}}}}});
        writer_.add_node(
            {{"name", name},
             {"mesh", mesh},
             {"translation", gltf_array3(sphere.center)},
             {"scale", gltf_array3(vec3(sphere.radius))},
             {"extras", {{"rt", {{"sphere", {{"center", gltf_array3(sphere.center)}, {"radius", sphere.radius}}}}}}}});
    }
}

void GlbExporter::add_lights() {
    if (scene_.lights.empty()) return;
    Json lights = Json::array();
    for (size_t i = 0; i < scene_.lights.size(); ++i) {
        const Light& light = scene_.lights[i];
        // KHR_lights_punctual splits colour times candela into a colour and an intensity.
        const float peak = max_component(light.intensity);
        Json spec = {{"type", light_type(light.kind)},
                     {"color", gltf_array3(peak > 0.0f ? light.intensity / peak : vec3(1.0f))},
                     {"intensity", std::max(peak, 0.0f)}};
        Json node = {{"translation", gltf_array3(light.position)},
                     {"extensions", {{"KHR_lights_punctual", {{"light", i}}}}}};
        if (!light.name.empty()) spec["name"] = node["name"] = light.name;
        if (light.range > 0.0f) spec["range"] = light.range;
        if (light.kind != POINT) {
            // The node's -Z is the light's direction.
            const glm::quat q = rotation_from_minus_z(light.direction);
            node["rotation"] = {q.x, q.y, q.z, q.w};
        }
        if (light.kind == SPOT)
            spec["spot"] = {{"innerConeAngle", std::acos(light.cos_inner)},
                            {"outerConeAngle", std::acos(light.cos_outer)}};
        // glTF has no spherical lights or suns of a size; the style guide's advice: extras.
        if (light.radius > 0.0f) node["extras"] = {{"rt", {{"radius", light.radius}}}};
        if (light.angular_diameter > 0.0f)
            spec["extras"] = {{"rt", {{"angular_diameter", light.angular_diameter * 180.0f / kPi}}}};
        if (i >= scene_.lights.size() - scene_.rig_lights) node["extras"] = {{"rt", {{"default_rig", true}}}};
        lights.push_back(std::move(spec));
        writer_.add_node(std::move(node));
    }
    writer_.doc()["extensions"]["KHR_lights_punctual"]["lights"] = std::move(lights);
    writer_.doc()["extensionsUsed"].push_back("KHR_lights_punctual");
}

void GlbExporter::add_cameras() {
    const Bounds3 bounds = scene_.bounds();
    // glTF wants a near plane; a thousandth of the scene keeps all of it in view.
    const float znear = 1e-3f * (bounds.empty() ? 1.0f : std::max(glm::length(bounds.extent()), 1e-30f));
    for (const SceneCamera& named : scene_.cameras) {
        Camera camera = named.camera;
        apply_limits(camera, "camera " + named.name);  // fills the default field of view
        const auto read = [](const google::protobuf::RepeatedField<float>& v, vec3 fallback) {
            return v.size() == 3 ? vec3(v[0], v[1], v[2]) : fallback;
        };
        const vec3 position = read(camera.position(), vec3(0.0f));
        const vec3 forward = glm::normalize(read(camera.target(), vec3(0.0f, 0.0f, -1.0f)) - position);
        vec3 right = glm::cross(forward, read(camera.up(), vec3(0.0f, 1.0f, 0.0f)));
        vec3 unused;
        if (!(glm::length(right) > 1e-6f)) orthonormal_basis(forward, right, unused);  // no usable up
        right = glm::normalize(right);
        // A glTF camera looks down its node's -Z with +Y up.
        const glm::quat rotation = glm::quat_cast(mat3(right, glm::cross(right, forward), -forward));

        Json spec = {{"type", "perspective"},
                     {"perspective", {{"yfov", camera.fov_y() * kPi / 180.0f}, {"znear", znear}}}};
        if (camera.projection() == ORTHOGRAPHIC) {
            // The image's aspect is the render's, unknown here: xmag = ymag (the
            // loader reads only ymag). zfar is required; the scene fits well inside.
            const float ymag = 0.5f * camera.ortho_height();
            const float zfar = 1e6f * znear + glm::length(position - (bounds.empty() ? vec3(0.0f) : bounds.center()));
            spec = {{"type", "orthographic"},
                    {"orthographic", {{"xmag", ymag}, {"ymag", ymag}, {"znear", 0.0f}, {"zfar", zfar}}}};
        }
        if (!named.name.empty()) spec["name"] = named.name;
        Json node = {{"camera", writer_.append("cameras", std::move(spec))},
                     {"translation", gltf_array3(position)},
                     {"rotation", {rotation.x, rotation.y, rotation.z, rotation.w}}};
        if (!named.name.empty()) node["name"] = named.name;
        writer_.add_node(std::move(node));
    }
}

std::string GlbExporter::run() {
    add_materials(scene_, writer_);
    add_meshes();
    add_spheres();
    add_lights();
    add_cameras();
    Json scene = {{"extras", {{"rt", background_json(scene_.background)}}}};
    // What misses see while the default rig lights the scene; beside extras.rt,
    // which the loader reads, as a scene loaded back has the rig's lights as its own.
    if (scene_.rig_lights > 0) scene["extras"]["rt_default_rig"] = background_json(scene_.rig_background);
    return writer_.container(std::move(scene));
}

}  // namespace

std::string export_glb(const Scene& scene) { return GlbExporter(scene).run(); }

}  // namespace rt
