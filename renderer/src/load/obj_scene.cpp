// The parse of an OBJ (obj_loader.h) as our scene. The parser only splits the
// text: every index, count and number it hands back is checked here, and
// textures are read through the scene folder (scene_files.h). An rt.NodeMotion
// moves the faces of every object or group of its name (the `o` or `g` line
// they follow last) in world space.
#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <string_view>
#include <tuple>
#include <unordered_map>

#include <glm/gtc/type_ptr.hpp>

#include "load/node_transform.h"
#include "load/obj_loader.h"
#include "load/texture_decode.h"

namespace rt {
namespace {

// A corner's vertex; corners that share one must also share their motion.
struct CornerKey {
    int v, vn, vt, motion;
    bool operator==(const CornerKey&) const = default;
};

struct CornerHash {
    size_t operator()(const CornerKey& k) const {
        return std::hash<uint64_t>()(uint64_t(uint32_t(k.v)) << 32 ^ uint64_t(uint32_t(k.vn)) << 16 ^
                                     uint64_t(uint32_t(k.vt)) ^ uint64_t(uint32_t(k.motion)) << 48);
    }
};

class ObjSceneBuilder {
  public:
    ObjSceneBuilder(const SceneFolder& folder, const tinyobj::attrib_t& attrib)
        : folder_(folder), name_(folder.scene_name()), attrib_(attrib) {}

    LoadedScene build(const std::vector<tinyobj::shape_t>& shapes,
                      const std::vector<tinyobj::material_t>& materials,
                      std::span<const SceneAdditions::Motion> motions);

  private:
    // Pass 1: returns, for each position, the sum of the area vectors of the faces that give it no normal.
    std::vector<dvec3> check_faces(const std::vector<tinyobj::shape_t>& shapes, size_t material_count);
    // For each shape, the index of the motion that names it, or -1.
    std::vector<int> match_motions(const std::vector<tinyobj::shape_t>& shapes,
                                   std::span<const SceneAdditions::Motion> motions) const;
    // Pass 2: shape s moved by motion moved_by[s] (-1: none).
    void add_faces(const std::vector<tinyobj::shape_t>& shapes, const std::vector<dvec3>& smooth,
                   const std::vector<int>& moved_by);
    // The vertex of a corner met for the first time, and its place at shutter close.
    void add_vertex(const CornerKey& key, const std::vector<dvec3>& smooth);
    void add_close(int v, vec3 normal, int motion);
    [[noreturn]] void fail(const std::string& problem) const { throw SceneError(name_ + ": " + problem); }
    void check_range(const std::vector<double>& values, size_t width, const char* kind) const;
    Material convert(const tinyobj::material_t& source);
    int texture(const std::string& file, bool clamp, const std::string& what,
                Texture::Encoding encoding = Texture::Encoding::Srgb);
    dvec3 position(int v) const { return glm::make_vec3(&attrib_.vertices[3 * size_t(v)]); }

    const SceneFolder& folder_;
    const std::string& name_;
    const tinyobj::attrib_t& attrib_;
    LoadedScene loaded_;
    std::span<const SceneAdditions::Motion> motions_;
    std::vector<dmat4> close_;                // where each motion puts its objects at shutter close
    std::vector<glm::dmat3> close_normals_;  // and their normals
    std::map<std::tuple<std::string, bool, int>, int> textures_;  // (file, clamp, encoding) -> texture
    size_t texture_bytes_ = kMaxSceneTextureBytes;  // what the textures may still take
};

void ObjSceneBuilder::check_range(const std::vector<double>& values, size_t width, const char* kind) const {
    for (size_t i = 0; i < values.size(); ++i)
        if (!fits_float(dvec3(values[i])))
            fail(std::string(kind) + " #" + std::to_string(i / width + 1) + " is not a finite float");
}

Material ObjSceneBuilder::convert(const tinyobj::material_t& source) {
    const std::string what = "material " + in_quotes(source.name);
    const dvec3 kd = glm::make_vec3(source.diffuse), ks = glm::make_vec3(source.specular);
    if (!fits_float(kd) || !fits_float(ks) || !fits_float(dvec3(source.shininess)))
        fail(what + " has a Kd, Ks or Ns that is not a finite float");
    if (glm::any(glm::lessThan(kd, dvec3(0.0))) || glm::any(glm::lessThan(ks, dvec3(0.0))) || source.shininess < 0.0)
        fail(what + " has a negative Kd, Ks or Ns");
    if (!fits_float(dvec3(source.dissolve)) || !fits_float(dvec3(source.ior)))
        fail(what + " has a d, Tr or Ni that is not a finite float");
    // The mapping and its reasons: docs/materials.md.
    Material out;
    // MTL's dissolve becomes a clear dielectric's transmission, with Ni its
    // index. Exporters write any Ni (often 0) for opaque materials: checked
    // only where it is used.
    const double dissolve = std::clamp(source.dissolve, 0.0, 1.0);
    if (dissolve < 1.0) {
        if (source.ior < 1.0)
            fail(what + " is transparent (d < 1) with Ni " + shown(source.ior) +
                 ", expected an index of refraction of at least 1");
        out.transmission = vec3(float(1.0 - dissolve));
        out.ior = float(source.ior);
    }
    out.name = source.name;
    out.diffuse = vec3(kd);
    out.specular = vec3(ks);
    out.shininess = float(std::min(source.shininess, 100000.0));
    // illum 3, 5 and 7 are MTL's "reflection on, ray trace" models. Ks may
    // exceed 1 as the weight of a lobe, but no mirror returns more light than
    // it gets: above 1 a path between two mirrors would grow without bound.
    if (source.illum == 3 || source.illum == 5 || source.illum == 7)
        out.reflectance = glm::min(out.specular, vec3(1.0f));
    if (!source.diffuse_texname.empty())
        out.base_color_texture.index = texture(source.diffuse_texname, source.diffuse_texopt.clamp, what + " map_Kd");
    // `norm` (the PBR extension's tangent-space normal map, -bm its scale) is
    // glTF's normalTexture; map_Bump is a height map, which is not read.
    if (!source.normal_texname.empty()) {
        out.normal_texture.index =
            texture(source.normal_texname, source.normal_texopt.clamp, what + " norm", Texture::Encoding::Linear);
        const double scale = source.normal_texopt.bump_multiplier;
        if (!std::isfinite(scale)) fail(what + " norm -bm is not a finite number");
        out.normal_scale = float(std::clamp(scale, -1e4, 1e4));
    }
    return out;
}

int ObjSceneBuilder::texture(const std::string& file, bool clamp, const std::string& what,
                             Texture::Encoding encoding) {
    const auto key = std::make_tuple(file, clamp, int(encoding));
    if (const auto cached = textures_.find(key); cached != textures_.end()) return cached->second;
    int& mapped = textures_[key];
    mapped = -1;
    const auto bytes = folder_.read(file, what);
    std::string problem = "not found";
    std::optional<Texture> decoded;
    if (bytes) decoded = decode_texture(*bytes, name_ + ": " + what + " " + in_quotes(file), encoding, texture_bytes_,
                                        problem);
    if (!decoded) {
        loaded_.scene.warnings.push_back(name_ + ": " + what + " " + in_quotes(file) + " " + problem +
                                         ": texture ignored");
        return mapped;
    }
    decoded->wrap_s = decoded->wrap_t = clamp ? Texture::Wrap::ClampToEdge : Texture::Wrap::Repeat;
    mapped = int(loaded_.scene.textures.size());
    loaded_.scene.textures.push_back(std::move(*decoded));
    return mapped;
}

std::string_view trimmed(std::string_view text) {
    const size_t start = text.find_first_not_of(" \t\r");
    if (start == std::string_view::npos) return {};
    return text.substr(start, text.find_last_not_of(" \t\r") - start + 1);
}

std::vector<int> ObjSceneBuilder::match_motions(const std::vector<tinyobj::shape_t>& shapes,
                                                std::span<const SceneAdditions::Motion> motions) const {
    std::unordered_map<std::string_view, std::vector<size_t>> shapes_by_name;
    for (size_t s = 0; s < shapes.size(); ++s) shapes_by_name[trimmed(shapes[s].name)].push_back(s);
    std::vector<int> moved_by(shapes.size(), -1);
    for (size_t m = 0; m < motions.size(); ++m) {
        const std::string what = "object or group " + in_quotes(motions[m].node);
        const auto named = shapes_by_name.find(motions[m].node);
        if (named == shapes_by_name.end())
            throw SceneError(motions[m].source + ": the scene " + name_ + " has no " + what);
        for (size_t s : named->second) {
            if (moved_by[s] >= 0) throw SceneError(motions[m].source + ": " + what + " has a motion already");
            moved_by[s] = int(m);
        }
    }
    return moved_by;
}

LoadedScene ObjSceneBuilder::build(const std::vector<tinyobj::shape_t>& shapes,
                                   const std::vector<tinyobj::material_t>& materials,
                                   std::span<const SceneAdditions::Motion> motions) {
    check_range(attrib_.vertices, 3, "v");
    check_range(attrib_.normals, 3, "vn");
    check_range(attrib_.texcoords, 2, "vt");
    for (const tinyobj::material_t& material : materials) loaded_.scene.materials.push_back(convert(material));
    const std::vector<dvec3> smooth = check_faces(shapes, materials.size());

    // Where the motions put each object at shutter close; identity for parts they leave out.
    const std::vector<int> moved_by = match_motions(shapes, motions);
    motions_ = motions;
    for (const SceneAdditions::Motion& motion : motions) {
        close_.push_back(motion.close.over({}).matrix());
        close_normals_.push_back(normal_matrix(glm::dmat3(close_.back())));
    }
    add_faces(shapes, smooth, moved_by);
    return std::move(loaded_);
}

// Pass 1: check every face, count, and sum the area-weighted normal of each
// position over the faces that give it none (all such faces are smoothed
// together, whatever their `s` group: docs/materials.md).
std::vector<dvec3> ObjSceneBuilder::check_faces(const std::vector<tinyobj::shape_t>& shapes, size_t material_count) {
    const size_t nv = attrib_.vertices.size() / 3, nn = attrib_.normals.size() / 3, nt = attrib_.texcoords.size() / 2;
    size_t triangle_count = 0;
    std::vector<dvec3> smooth(nv, dvec3(0.0));
    for (const tinyobj::shape_t& shape : shapes) {
        const tinyobj::mesh_t& mesh = shape.mesh;
        const std::string what = "object " + in_quotes(shape.name);
        size_t offset = 0;
        for (size_t f = 0; f < mesh.num_face_vertices.size(); ++f) {
            // tinyobjloader stores corner counts in a byte and drops faces of fewer
            // than 3: a count out of step with the indices means one wrapped around.
            const size_t count = mesh.num_face_vertices[f];
            if (count < 3 || count > mesh.indices.size() - offset)
                fail(what + " has a face with more than 255 vertices");
            const std::string face = what + " face " + std::to_string(f + 1);
            for (size_t k = 0; k < count; ++k) {
                const tinyobj::index_t& i = mesh.indices[offset + k];
                if (i.vertex_index < 0 || size_t(i.vertex_index) >= nv)
                    fail(face + ": vertex index is out of range (" + std::to_string(nv) + " vertices)");
                if (i.normal_index < -1 || (i.normal_index >= 0 && size_t(i.normal_index) >= nn))
                    fail(face + ": normal index is out of range (" + std::to_string(nn) + " normals)");
                if (i.texcoord_index < -1 || (i.texcoord_index >= 0 && size_t(i.texcoord_index) >= nt))
                    fail(face + ": texture coordinate index is out of range (" + std::to_string(nt) + ")");
            }
            const int material = mesh.material_ids[f];
            if (material < -1 || (material >= 0 && size_t(material) >= material_count))
                fail(face + ": material index is out of range");
            // The polygon's area vector: the sum of its fan triangles' cross products.
            dvec3 area(0.0);
            const dvec3 p0 = position(mesh.indices[offset].vertex_index);
            for (size_t k = 1; k + 1 < count; ++k)
                area += glm::cross(position(mesh.indices[offset + k].vertex_index) - p0,
                                   position(mesh.indices[offset + k + 1].vertex_index) - p0);
            for (size_t k = 0; k < count; ++k) {
                const tinyobj::index_t& i = mesh.indices[offset + k];
                if (i.normal_index < 0) smooth[size_t(i.vertex_index)] += area;
            }
            triangle_count += count - 2;
            offset += count;
        }
        if (offset != mesh.indices.size()) fail(what + " has a face with more than 255 vertices");
        if (!shape.lines.indices.empty() || !shape.points.indices.empty())
            loaded_.scene.warnings.push_back(name_ + ": " + what + " has lines or points: only faces are rendered");
    }
    check_geometry_limits(loaded_.scene, 0, triangle_count, name_);
    return smooth;
}

// Pass 2: one vertex per distinct (position, normal, texcoord) triple, and
// each polygon as a fan of triangles.
void ObjSceneBuilder::add_faces(const std::vector<tinyobj::shape_t>& shapes, const std::vector<dvec3>& smooth,
                                const std::vector<int>& moved_by) {
    Scene& scene = loaded_.scene;
    loaded_.has_texcoords = attrib_.texcoords.size() / 2 > 0;
    std::unordered_map<CornerKey, uint32_t, CornerHash> vertices;
    std::vector<uint32_t> polygon;
    for (size_t shape_index = 0; shape_index < shapes.size(); ++shape_index) {
        const tinyobj::mesh_t& mesh = shapes[shape_index].mesh;
        size_t offset = 0;
        for (size_t f = 0; f < mesh.num_face_vertices.size(); ++f) {
            const size_t count = mesh.num_face_vertices[f];
            polygon.clear();
            for (size_t k = 0; k < count; ++k) {
                const tinyobj::index_t& i = mesh.indices[offset + k];
                const CornerKey key{i.vertex_index, i.normal_index, i.texcoord_index, moved_by[shape_index]};
                const auto [it, added] = vertices.try_emplace(key, uint32_t(scene.positions.size()));
                if (added) add_vertex(key, smooth);
                polygon.push_back(it->second);
            }
            const int material = mesh.material_ids[f];
            for (size_t k = 1; k + 1 < count; ++k) {
                scene.triangles.push_back(uvec3(polygon[0], polygon[k], polygon[k + 1]));
                scene.triangle_materials.push_back(material < 0 ? kNoMaterial : uint32_t(material));
            }
            offset += count;
        }
    }
}

void ObjSceneBuilder::add_vertex(const CornerKey& key, const std::vector<dvec3>& smooth) {
    Scene& scene = loaded_.scene;
    check_geometry_limits(scene, 1, 0, name_);
    scene.positions.push_back(vec3(position(key.v)));
    // Sums of area vectors can exceed float's range: normalise first.
    const dvec3 n = key.vn >= 0 ? glm::make_vec3(&attrib_.normals[3 * size_t(key.vn)]) : smooth[size_t(key.v)];
    const vec3 normal = vec3(try_normalize(n).value_or(dvec3(0.0)));
    scene.normals.push_back(normal);
    if (!motions_.empty()) add_close(key.v, normal, key.motion);
    // OBJ puts v = 0 at the bottom of an image, our textures at the top.
    if (loaded_.has_texcoords) {
        const double* uv = key.vt >= 0 ? &attrib_.texcoords[2 * size_t(key.vt)] : nullptr;
        scene.texcoords.push_back(uv ? vec2(float(uv[0]), float(1.0 - uv[1])) : vec2(0.0f));
    }
}

// Once anything moves, every vertex has a place at shutter close: its own when
// it stands still.
void ObjSceneBuilder::add_close(int v, vec3 normal, int motion) {
    dvec3 p = position(v);
    if (motion >= 0) {
        const size_t m = size_t(motion);
        p = dvec3(close_[m] * glm::dvec4(p, 1.0));
        if (!fits_float(p))
            throw SceneError(motions_[m].source + ": moves v #" + std::to_string(v + 1) + " out of range");
        normal = vec3(try_normalize(close_normals_[m] * dvec3(normal)).value_or(dvec3(0.0)));
    }
    loaded_.scene.positions_close.push_back(vec3(p));
    loaded_.scene.normals_close.push_back(normal);
}

}  // namespace

LoadedScene build_obj_scene(const SceneFolder& folder, const tinyobj::attrib_t& attrib,
                            const std::vector<tinyobj::shape_t>& shapes,
                            const std::vector<tinyobj::material_t>& materials,
                            std::span<const SceneAdditions::Motion> motions) {
    return ObjSceneBuilder(folder, attrib).build(shapes, materials, motions);
}

}  // namespace rt
