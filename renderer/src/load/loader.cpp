// Dispatch by format, the sidecar, and the finalisation both loaders share.
#include "load/loader.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <optional>
#include <stdexcept>

#include "load/format_loaders.h"
#include "load/generate_tangents.h"
#include "load/light_rig.h"
#include "load/scene_extras.h"
#include "load/scene_files.h"
#include "geometry/triangle.h"

namespace rt {
namespace {

namespace fs = std::filesystem;

enum class Format { Gltf, Glb, Obj };

Format format_of(const std::string& file_name) {
    std::string extension = fs::path(file_name).extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    if (extension == ".gltf") return Format::Gltf;
    if (extension == ".glb") return Format::Glb;
    if (extension == ".obj") return Format::Obj;
    throw SceneError(file_name + ": unknown scene format " + in_quotes(extension) +
                     " (expected .gltf, .glb or .obj)");
}

LoadedScene load_format(Format format, std::span<const unsigned char> data, const SceneFolder& folder,
                        std::span<const SceneAdditions::Motion> motions) {
    return format == Format::Obj ? load_obj(data, folder, motions)
                                 : load_gltf(data, format == Format::Glb, folder, motions);
}

SceneAdditions read_sidecar(std::string_view json, const std::string& source) {
    try {
        return read_scene_extras(json, source);
    } catch (const std::invalid_argument& e) {
        throw SceneError(e.what());
    }
}

// Everything but the motions, which the format loaders apply.
void add_extras(SceneAdditions& additions, Scene& scene) {
    for (auto& sphere : additions.spheres) {
        scene.spheres.push_back({sphere.center, sphere.radius, uint32_t(scene.materials.size())});
        scene.materials.push_back(std::move(sphere.material));
    }
    for (auto& light : additions.lights) scene.lights.push_back(std::move(light));
    if (additions.background) scene.background = *additions.background;
    for (auto& camera : additions.cameras) scene.cameras.push_back(std::move(camera));
}

// Triangles no ray can hit (no area, or a vertex that is not finite, at both
// ends of the shutter interval) would only cost traversal time and poison
// normals; they go, counted.
void drop_degenerate_triangles(Scene& scene, const std::string& name) {
    const auto hittable = [](const std::vector<vec3>& positions, uvec3 tri) {
        const double area = doubled_area(positions[tri.x], positions[tri.y], positions[tri.z]);
        return area > 0.0 && std::isfinite(area);
    };
    size_t kept = 0;
    // Shared meshes keep their order; their ranges shrink by what they lose.
    size_t mesh = 0;
    std::vector<SharedMesh> meshes = scene.meshes;
    for (size_t t = 0; t < scene.triangles.size(); ++t) {
        for (; mesh < meshes.size() && t == scene.meshes[mesh].first_triangle; ++mesh) meshes[mesh].first_triangle = uint32_t(kept);
        const uvec3 tri = scene.triangles[t];
        if (!hittable(scene.positions, tri) && !(scene.moving() && hittable(scene.positions_close, tri))) continue;
        scene.triangles[kept] = tri;
        scene.triangle_materials[kept] = scene.triangle_materials[t];
        ++kept;
    }
    for (; mesh < meshes.size(); ++mesh) meshes[mesh].first_triangle = uint32_t(kept);
    for (size_t m = 0; m < meshes.size(); ++m)
        meshes[m].triangle_count = uint32_t((m + 1 < meshes.size() ? meshes[m + 1].first_triangle : kept) - meshes[m].first_triangle);
    scene.meshes = std::move(meshes);
    scene.degenerate_triangles = scene.triangles.size() - kept;
    scene.triangles.resize(kept);
    scene.triangle_materials.resize(kept);
    if (scene.degenerate_triangles > 0)
        scene.warnings.push_back(name + ": dropped " + std::to_string(scene.degenerate_triangles) +
                                 " degenerate triangles (zero area, or not finite)");
}

// Keeps only the vertices some triangle uses, so that bounds and memory reflect
// the geometry that is there.
void drop_unused_vertices(Scene& scene, bool has_texcoords) {
    std::vector<uint32_t> remap(scene.positions.size(), UINT32_MAX);
    std::vector<vec3> positions, normals, positions_close, normals_close;
    std::vector<vec2> texcoords, texcoords1;
    std::vector<glm::vec4> colors, tangents;
    for (uvec3& tri : scene.triangles) {
        for (int k = 0; k < 3; ++k) {
            uint32_t& index = remap[tri[k]];
            if (index == UINT32_MAX) {
                index = uint32_t(positions.size());
                positions.push_back(scene.positions[tri[k]]);
                normals.push_back(scene.normals[tri[k]]);
                if (has_texcoords) texcoords.push_back(scene.texcoords[tri[k]]);
                // Empty when no mesh has them, else one per vertex.
                if (!scene.texcoords1.empty()) texcoords1.push_back(scene.texcoords1[tri[k]]);
                if (!scene.colors.empty()) colors.push_back(scene.colors[tri[k]]);
                if (!scene.tangents.empty()) tangents.push_back(scene.tangents[tri[k]]);
                if (scene.moving()) {
                    positions_close.push_back(scene.positions_close[tri[k]]);
                    normals_close.push_back(scene.normals_close[tri[k]]);
                }
            }
            tri[k] = index;
        }
    }
    scene.positions = std::move(positions);
    scene.normals = std::move(normals);
    scene.texcoords = std::move(texcoords);
    scene.texcoords1 = std::move(texcoords1);
    scene.colors = std::move(colors);
    scene.tangents = std::move(tangents);
    scene.positions_close = std::move(positions_close);
    scene.normals_close = std::move(normals_close);
}

// A normal the file did not give (zero) becomes the area-weighted average of
// the faces around the vertex; where those cancel out, the first face's normal.
void complete_normals(const std::vector<uvec3>& triangles, const std::vector<vec3>& positions,
                      std::vector<vec3>& normals) {
    const auto usable = [](vec3 n) {
        const float length = glm::length(n);
        return length > 0.0f && std::isfinite(length);
    };
    if (std::all_of(normals.begin(), normals.end(), usable)) {
        for (vec3& n : normals) n = glm::normalize(n);
        return;
    }
    std::vector<dvec3> sums(normals.size(), dvec3(0.0));
    std::vector<dvec3> first(normals.size(), dvec3(0.0));
    for (const uvec3& tri : triangles) {
        const dvec3 p0(positions[tri.x]);
        const dvec3 area = glm::cross(dvec3(positions[tri.y]) - p0, dvec3(positions[tri.z]) - p0);
        for (int k = 0; k < 3; ++k) {
            if (usable(normals[tri[k]])) continue;
            sums[tri[k]] += area;
            if (first[tri[k]] == dvec3(0.0)) first[tri[k]] = glm::normalize(area);
        }
    }
    for (size_t v = 0; v < normals.size(); ++v) {
        vec3& n = normals[v];
        if (usable(n)) {
            n = glm::normalize(n);
            continue;
        }
        n = vec3(try_normalize(sums[v]).value_or(first[v]));
    }
}

// What both loaders leave to the end: geometry no ray can hit, missing normals,
// triangles without a material, and a word to the user about missing lights.
void finalise(LoadedScene& loaded, const std::string& name) {
    Scene& scene = loaded.scene;
    drop_degenerate_triangles(scene, name);
    drop_unused_vertices(scene, loaded.has_texcoords);
    complete_normals(scene.triangles, scene.positions, scene.normals);
    if (scene.moving()) {
        complete_normals(scene.triangles, scene.positions_close, scene.normals_close);
        // Motions that end where they start (a full turn, an animation that
        // loops) leave the scene still, and the renderer on its static path,
        // unless an instance moves (its mesh's vertices stand still).
        const bool instance_moves =
            std::any_of(scene.instances.begin(), scene.instances.end(), [](const Instance& i) { return i.moving; });
        if (!instance_moves && scene.positions_close == scene.positions && scene.normals_close == scene.normals) {
            scene.positions_close.clear();
            scene.normals_close.clear();
        }
    }

    generate_tangents(scene, name);  // needs the complete normals

    const auto unassigned = std::find(scene.triangle_materials.begin(), scene.triangle_materials.end(), kNoMaterial);
    if (unassigned != scene.triangle_materials.end()) {
        const uint32_t index = uint32_t(scene.materials.size());
        Material neutral;  // grey Lambertian: see docs/materials.md
        neutral.name = "default";
        neutral.diffuse = vec3(0.8f);
        scene.materials.push_back(neutral);
        std::replace(unassigned, scene.triangle_materials.end(), kNoMaterial, index);
    }
    if (scene.lights.empty()) {
        add_light_rig(scene);
        scene.warnings.push_back(name + ": scene has no lights: lit by the default light rig (a key and a fill "
                                        "directional light from the camera's side, a pale sky); the setting "
                                        "light_rig NO_RIG turns it off");
    }
}

Scene load(Format format, std::span<const unsigned char> data, const SceneFolder& folder,
           const std::optional<std::vector<unsigned char>>& sidecar, const std::string& sidecar_name) {
    // Read first: its motions move the file's nodes as they are loaded.
    SceneAdditions sidecar_additions;  // none without a sidecar
    if (sidecar)
        sidecar_additions = read_sidecar(
            std::string_view(reinterpret_cast<const char*>(sidecar->data()), sidecar->size()),
            sidecar_name + ": extras");
    LoadedScene loaded = load_format(format, data, folder, sidecar_additions.motions);
    for (SceneAdditions& additions : loaded.extras) add_extras(additions, loaded.scene);
    add_extras(sidecar_additions, loaded.scene);
    finalise(loaded, folder.scene_name());
    // Warnings quote the file as errors do (SceneError's constructor).
    for (std::string& warning : loaded.scene.warnings) warning = printable(warning);
    return std::move(loaded.scene);
}

}  // namespace


void check_geometry_limits(const Scene& scene, size_t vertices, size_t triangles, const std::string& what) {
    if (vertices > kMaxSceneVertices - scene.positions.size())
        throw SceneError(what + ": the scene would have more than " + std::to_string(kMaxSceneVertices) +
                         " vertices");
    if (triangles > kMaxSceneTriangles - scene.triangles.size())
        throw SceneError(what + ": the scene would have more than " + std::to_string(kMaxSceneTriangles) +
                         " triangles");
}

Scene load_scene(const fs::path& file) {
    const SceneFolder folder = SceneFolder::of_file(file);
    const std::string& name = folder.scene_name();
    const Format format = format_of(name);
    const auto data = read_file(file, name);
    if (!data) throw SceneError(name + ": file not found");
    // cornell.obj -> cornell.rt.json, beside it and held to the same folder.
    const std::string sidecar_name = file.stem().string() + ".rt.json";
    const auto sidecar = folder.read(sidecar_name, "sidecar");
    return load(format, *data, folder, sidecar, sidecar_name);
}

Scene load_scene_from_memory(std::span<const std::byte> data, std::string_view file_name) {
    const SceneFolder folder = SceneFolder::none(file_name);
    const Format format = format_of(folder.scene_name());
    const std::span<const unsigned char> bytes(reinterpret_cast<const unsigned char*>(data.data()), data.size());
    if (bytes.size() > kMaxSceneFileBytes)
        throw SceneError(folder.scene_name() + ": is larger than the limit of " + std::to_string(kMaxSceneFileBytes) +
                         " bytes");
    return load(format, bytes, folder, std::nullopt, "");
}

}  // namespace rt
