#include "export/glb_export.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>

#include "util/proto_limits.h"
#include "integrator/sampling.h"
#include "export/texture_encode.h"

namespace rt {
namespace {

using Json = nlohmann::json;

// glTF's enumerations (glTF 2.0 specification, section 5).
constexpr int kFloat = 5126;
constexpr int kUnsignedInt = 5125;
constexpr int kTriangles = 4;
constexpr int kArrayBuffer = 34962;
constexpr int kElementArrayBuffer = 34963;
constexpr int kLinear = 9729;
constexpr int kLinearMipmapLinear = 9987;

// The UV sphere standing in for an analytic sphere: enough facets for a round
// outline in the viewer, few enough to keep the file small.
constexpr uint32_t kSphereSegments = 48;  // around the axis
constexpr uint32_t kSphereRings = 24;     // from pole to pole

static_assert(sizeof(vec3) == 12 && sizeof(vec2) == 8, "attributes are copied as packed floats");

Json array3(vec3 v) { return Json::array({v.x, v.y, v.z}); }

int wrap_mode(Texture::Wrap wrap) {
    switch (wrap) {
        case Texture::Wrap::ClampToEdge: return 33071;
        case Texture::Wrap::MirroredRepeat: return 33648;
        case Texture::Wrap::Repeat: break;
    }
    return 10497;
}

// The glTF roughness whose Beckmann lobe has the Phong exponent `shininess`:
// docs/materials.md's shininess = 2 / alpha^2 - 2 with alpha = roughness^2,
// solved for roughness, so the loader reads the same exponent back.
float roughness_of(float shininess) {
    const float alpha = std::sqrt(2.0f / (std::max(shininess, 0.0f) + 2.0f));
    return std::sqrt(alpha);
}

void append_u32(std::string& out, uint32_t v) {
    for (int shift = 0; shift < 32; shift += 8) out.push_back(char((v >> shift) & 0xff));
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

class GlbExporter {
  public:
    explicit GlbExporter(const Scene& scene) : scene_(scene), texture_indices_(scene.textures.size(), -1) {}

    std::string run();

  private:
    int add_view(const void* data, size_t bytes, int target);
    int add_accessor(int view, int component_type, size_t count, const char* type);
    int add_positions(const std::vector<vec3>& positions);
    int add_vec3s(const std::vector<vec3>& values);
    int add_indices(const std::vector<uint32_t>& indices);
    int add_node(Json node);
    int add_texture(int scene_texture);
    bool has_texture(const TextureRef& ref) const;
    Json texture_info(const TextureRef& ref);
    void add_surface(const Material& m, Json& material);

    void add_materials();
    void add_mesh();
    void add_spheres();
    void add_lights();
    void add_cameras();
    std::string container();

    const Scene& scene_;
    Json doc_ = {{"asset", {{"version", "2.0"}, {"generator", "rt export_glb"}}}, {"scene", 0}};
    Json scene_nodes_ = Json::array();
    std::string bin_;
    std::vector<int> texture_indices_;  // scene texture -> glTF texture, -1 until used
    bool emissive_strength_ = false;  // some material needs KHR_materials_emissive_strength
    bool texture_transform_ = false;  // some texture reference needs KHR_texture_transform
};

int GlbExporter::add_view(const void* data, size_t bytes, int target) {
    bin_.append((4 - bin_.size() % 4) % 4, '\0');
    Json view = {{"buffer", 0}, {"byteOffset", bin_.size()}, {"byteLength", bytes}};
    if (target != 0) view["target"] = target;
    bin_.append(static_cast<const char*>(data), bytes);
    doc_["bufferViews"].push_back(std::move(view));
    return int(doc_["bufferViews"].size() - 1);
}

int GlbExporter::add_accessor(int view, int component_type, size_t count, const char* type) {
    doc_["accessors"].push_back(
        {{"bufferView", view}, {"componentType", component_type}, {"count", count}, {"type", type}});
    return int(doc_["accessors"].size() - 1);
}

int GlbExporter::add_positions(const std::vector<vec3>& positions) {
    const int accessor = add_vec3s(positions);
    vec3 lo(kInfinity), hi(-kInfinity);
    for (const vec3& p : positions) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    // glTF requires the bounds of POSITION; viewers size their boxes by them.
    doc_["accessors"][size_t(accessor)]["min"] = array3(lo);
    doc_["accessors"][size_t(accessor)]["max"] = array3(hi);
    return accessor;
}

int GlbExporter::add_vec3s(const std::vector<vec3>& values) {
    return add_accessor(add_view(values.data(), values.size() * sizeof(vec3), kArrayBuffer), kFloat, values.size(),
                        "VEC3");
}

int GlbExporter::add_indices(const std::vector<uint32_t>& indices) {
    const int view = add_view(indices.data(), indices.size() * sizeof(uint32_t), kElementArrayBuffer);
    return add_accessor(view, kUnsignedInt, indices.size(), "SCALAR");
}

int GlbExporter::add_node(Json node) {
    doc_["nodes"].push_back(std::move(node));
    const int index = int(doc_["nodes"].size() - 1);
    scene_nodes_.push_back(index);
    return index;
}

int GlbExporter::add_texture(int scene_texture) {
    int& index = texture_indices_[size_t(scene_texture)];
    if (index >= 0) return index;
    const Texture& texture = scene_.textures[size_t(scene_texture)];
    const std::vector<unsigned char> png = encode_png(texture);
    doc_["images"].push_back({{"bufferView", add_view(png.data(), png.size(), 0)}, {"mimeType", "image/png"}});
    // Trilinear, as the renderer samples it (its ray cones pick the level
    // where the viewer's GPU uses screen-space derivatives).
    doc_["samplers"].push_back({{"magFilter", kLinear},
                                {"minFilter", kLinearMipmapLinear},
                                {"wrapS", wrap_mode(texture.wrap_s)},
                                {"wrapT", wrap_mode(texture.wrap_t)}});
    doc_["textures"].push_back({{"sampler", doc_["samplers"].size() - 1}, {"source", doc_["images"].size() - 1}});
    index = int(doc_["textures"].size() - 1);
    return index;
}

bool GlbExporter::has_texture(const TextureRef& ref) const {
    return ref && size_t(ref.index) < scene_.textures.size();
}

Json GlbExporter::texture_info(const TextureRef& ref) {
    Json info = {{"index", add_texture(ref.index)}};
    if (ref.texcoord != 0) info["texCoord"] = ref.texcoord;
    if (!ref.transform.identity()) {
        const TextureTransform& t = ref.transform;
        info["extensions"]["KHR_texture_transform"] = {
            {"offset", {t.offset.x, t.offset.y}}, {"rotation", t.rotation}, {"scale", {t.scale.x, t.scale.y}}};
        // three.js reads the transform's own texCoord, not the textureInfo's, when it has one.
        if (ref.texcoord != 0) info["extensions"]["KHR_texture_transform"]["texCoord"] = ref.texcoord;
        texture_transform_ = true;
    }
    return info;
}

// Emission, alpha and the occlusion map, as three.js's GLTFLoader reads them.
void GlbExporter::add_surface(const Material& m, Json& material) {
    if (m.emission != vec3(0.0f)) {
        // emissiveFactor stops at 1; the rest goes into the strength.
        const float strength = std::max(max_component(m.emission), 1.0f);
        material["emissiveFactor"] = array3(m.emission / strength);
        if (strength > 1.0f) {
            material["extensions"]["KHR_materials_emissive_strength"] = {{"emissiveStrength", strength}};
            emissive_strength_ = true;
        }
        if (has_texture(m.emissive_texture)) material["emissiveTexture"] = texture_info(m.emissive_texture);
    }
    if (m.alpha_mode == AlphaMode::Mask) {
        material["alphaMode"] = "MASK";
        material["alphaCutoff"] = m.alpha_cutoff;
    } else if (m.alpha_mode == AlphaMode::Blend) {
        material["alphaMode"] = "BLEND";
    }
    if (m.double_sided) material["doubleSided"] = true;
    if (has_texture(m.occlusion_texture)) {
        material["occlusionTexture"] = texture_info(m.occlusion_texture);
        material["occlusionTexture"]["strength"] = m.occlusion_strength;
    }
}

void GlbExporter::add_materials() {
    bool transmissive = false;
    for (const Material& m : scene_.materials) {
        // glTF's own inputs where the material came from them; an OBJ's Phong
        // terms as the nearest dielectric.
        const vec3 base = glm::clamp(m.metallic_roughness ? m.base_color : m.diffuse, 0.0f, 1.0f);
        Json pbr = {{"baseColorFactor", {base.r, base.g, base.b, m.alpha}},
                    {"metallicFactor", m.metallic_roughness ? m.metallic : 0.0f},
                    {"roughnessFactor", m.metallic_roughness ? m.roughness : roughness_of(m.shininess)}};
        if (has_texture(m.base_color_texture)) pbr["baseColorTexture"] = texture_info(m.base_color_texture);
        if (has_texture(m.metallic_roughness_texture))
            pbr["metallicRoughnessTexture"] = texture_info(m.metallic_roughness_texture);
        Json material = {{"pbrMetallicRoughness", std::move(pbr)}};
        add_surface(m, material);
        if (!m.name.empty()) material["name"] = m.name;
        material["extras"]["rt"]["phong"] = {{"diffuse", array3(m.diffuse)},
                                             {"specular", array3(m.specular)},
                                             {"shininess", m.shininess},
                                             {"reflectance", array3(m.reflectance)}};
        // Glass as glTF has it, for viewers; opaque materials stay as they were.
        if (m.transmission != vec3(0.0f)) {
            material["extensions"]["KHR_materials_transmission"] = {
                {"transmissionFactor", max_component(m.transmission)}};
            material["extensions"]["KHR_materials_ior"] = {{"ior", m.ior}};
            transmissive = true;
        }
        doc_["materials"].push_back(std::move(material));
    }
    if (transmissive)
        for (const char* extension : {"KHR_materials_transmission", "KHR_materials_ior"})
            doc_["extensionsUsed"].push_back(extension);
    if (emissive_strength_) doc_["extensionsUsed"].push_back("KHR_materials_emissive_strength");
    if (texture_transform_) doc_["extensionsUsed"].push_back("KHR_texture_transform");
}

void GlbExporter::add_mesh() {
    std::vector<std::vector<uint32_t>> by_material(scene_.materials.size());
    for (size_t t = 0; t < scene_.triangles.size(); ++t) {
        const uint32_t material = scene_.triangle_materials[t];
        if (material >= by_material.size())
            throw std::invalid_argument("export_glb(): triangle " + std::to_string(t) + " has material " +
                                        std::to_string(material) + ", but the scene has " +
                                        std::to_string(by_material.size()));
        by_material[material].push_back(uint32_t(t));
    }

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
        std::vector<vec3> positions, normals;
        std::vector<vec2> texcoords;
        for (uint32_t v : vertices) {
            positions.push_back(scene_.positions[v]);
            normals.push_back(scene_.normals[v]);
            if (!scene_.texcoords.empty()) texcoords.push_back(scene_.texcoords[v]);
            local[v] = kUnused;
        }
        Json attributes = {{"POSITION", add_positions(positions)}, {"NORMAL", add_vec3s(normals)}};
        if (!texcoords.empty())
            attributes["TEXCOORD_0"] = add_accessor(
                add_view(texcoords.data(), texcoords.size() * sizeof(vec2), kArrayBuffer), kFloat,
                texcoords.size(), "VEC2");
        primitives.push_back(
            {{"attributes", attributes}, {"indices", add_indices(indices)}, {"material", material}, {"mode", kTriangles}});
    }
    if (primitives.empty()) return;
    doc_["meshes"].push_back({{"name", "triangles"}, {"primitives", std::move(primitives)}});
    add_node({{"name", "triangles"}, {"mesh", doc_["meshes"].size() - 1}});
}

void GlbExporter::add_spheres() {
    if (scene_.spheres.empty()) return;
    // One tessellation for all: each sphere's node scales and places it.
    const UnitSphere unit = unit_sphere();
    const int positions = add_positions(unit.positions);
    const int normals = add_vec3s(unit.positions);
    const int indices = add_indices(unit.indices);
    for (size_t i = 0; i < scene_.spheres.size(); ++i) {
        const Sphere& sphere = scene_.spheres[i];
        const std::string name = "sphere " + std::to_string(i);
        doc_["meshes"].push_back({{"name", name},
                                  {"primitives", {{{"attributes", {{"POSITION", positions}, {"NORMAL", normals}}},
                                                   {"indices", indices},
                                                   {"material", sphere.material},
                                                   {"mode", kTriangles}}}}});
        add_node({{"name", name},
                  {"mesh", doc_["meshes"].size() - 1},
                  {"translation", array3(sphere.center)},
                  {"scale", array3(vec3(sphere.radius))},
                  {"extras", {{"rt", {{"sphere", {{"center", array3(sphere.center)}, {"radius", sphere.radius}}}}}}}});
    }
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

void GlbExporter::add_lights() {
    if (scene_.lights.empty()) return;
    Json lights = Json::array();
    for (size_t i = 0; i < scene_.lights.size(); ++i) {
        const Light& light = scene_.lights[i];
        // KHR_lights_punctual splits colour times candela into a colour and an intensity.
        const float peak = max_component(light.intensity);
        Json spec = {{"type", light_type(light.kind)},
                     {"color", array3(peak > 0.0f ? light.intensity / peak : vec3(1.0f))},
                     {"intensity", std::max(peak, 0.0f)}};
        Json node = {{"translation", array3(light.position)},
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
        add_node(std::move(node));
    }
    doc_["extensions"]["KHR_lights_punctual"]["lights"] = std::move(lights);
    doc_["extensionsUsed"].push_back("KHR_lights_punctual");
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
        Json node = {{"camera", doc_["cameras"].size()},
                     {"translation", array3(position)},
                     {"rotation", {rotation.x, rotation.y, rotation.z, rotation.w}}};
        if (!named.name.empty()) spec["name"] = node["name"] = named.name;
        doc_["cameras"].push_back(std::move(spec));
        add_node(std::move(node));
    }
}

// The GLB container (glTF 2.0 specification, section 4.4): a 12-byte header,
// the JSON chunk padded with spaces and the BIN chunk padded with zeros, both
// to 4 bytes.
std::string GlbExporter::container() {
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

std::string GlbExporter::run() {
    add_materials();
    add_mesh();
    add_spheres();
    add_lights();
    add_cameras();
    Json scene = {{"extras", {{"rt", {{"background", array3(scene_.background)}}}}}};
    if (!scene_nodes_.empty()) scene["nodes"] = scene_nodes_;  // glTF forbids empty arrays
    doc_["scenes"] = Json::array({std::move(scene)});
    return container();
}

}  // namespace

std::string export_glb(const Scene& scene) { return GlbExporter(scene).run(); }

}  // namespace rt
