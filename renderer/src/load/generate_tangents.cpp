#include "load/generate_tangents.h"

#include <cstdint>
#include <string>

#include "geometry/mikktspace.h"

namespace rt {
namespace {

// A new vertex with every attribute of `v`: whatever per-vertex array Scene
// holds (scene.h) must be copied here.
uint32_t duplicate_vertex(Scene& scene, uint32_t v) {
    const auto copy = [v](auto& values) {
        if (!values.empty()) values.push_back(values[v]);
    };
    copy(scene.positions);
    copy(scene.normals);
    copy(scene.texcoords);
    copy(scene.texcoords1);
    copy(scene.colors);
    copy(scene.tangents);
    copy(scene.positions_close);
    copy(scene.normals_close);
    return uint32_t(scene.positions.size() - 1);
}

bool needs_tangents(const Scene& scene, uint32_t triangle) {
    const Material& m = scene.materials[scene.triangle_materials[triangle]];
    if (!m.normal_texture) return false;
    if (scene.tangents.empty()) return true;
    const uvec3 tri = scene.triangles[triangle];
    return scene.tangents[tri.x].w == 0.0f || scene.tangents[tri.y].w == 0.0f || scene.tangents[tri.z].w == 0.0f;
}

}  // namespace

void generate_tangents(Scene& scene, const std::string& name) {
    std::vector<uint32_t> chosen;
    bool missing_uvs = false;
    for (uint32_t t = 0; t < scene.triangles.size(); ++t) {
        if (scene.triangle_materials[t] >= scene.materials.size() || !needs_tangents(scene, t)) continue;
        const uint32_t set = scene.materials[scene.triangle_materials[t]].normal_texture.texcoord;
        if ((set == 0 ? scene.texcoords : scene.texcoords1).empty()) {
            missing_uvs = true;
            continue;
        }
        chosen.push_back(t);
    }
    if (missing_uvs)
        scene.warnings.push_back(name + ": a normal texture reads texture coordinates its mesh does not have: "
                                        "those triangles are shaded without it");
    if (chosen.empty()) return;

    std::vector<TangentCorner> corners;
    corners.reserve(chosen.size() * 3);
    for (uint32_t t : chosen) {
        const uint32_t set = scene.materials[scene.triangle_materials[t]].normal_texture.texcoord;
        const std::vector<vec2>& uvs = set == 0 ? scene.texcoords : scene.texcoords1;
        for (int k = 0; k < 3; ++k) {
            const uint32_t v = scene.triangles[t][k];
            corners.push_back({scene.positions[v], scene.normals[v], uvs[v]});
        }
    }
    const std::vector<glm::vec4> tangents = mikktspace_tangents(corners);

    if (scene.tangents.empty()) scene.tangents.assign(scene.positions.size(), glm::vec4(0.0f));
    // The vertices this pass gave a tangent, and the copies made of each, as
    // a chain: next_copy[v] is the next vertex holding v's other tangents.
    std::vector<uint8_t> ours(scene.positions.size(), 0);
    std::vector<uint32_t> next_copy(scene.positions.size(), UINT32_MAX);
    for (size_t i = 0; i < chosen.size(); ++i)
        for (int k = 0; k < 3; ++k) {
            uint32_t& corner = scene.triangles[chosen[i]][k];
            // glTF's v runs down the image, MikkTSpace's up: the bitangent turns.
            const glm::vec4 mikk = tangents[3 * i + size_t(k)];
            const glm::vec4 tangent(vec3(mikk), -mikk.w);
            uint32_t v = corner;
            if (scene.tangents[v].w != 0.0f && !ours[v]) continue;  // the file's own
            if (!ours[v]) {
                scene.tangents[v] = tangent;
                ours[v] = 1;
                continue;
            }
            while (scene.tangents[v] != tangent && next_copy[v] != UINT32_MAX) v = next_copy[v];
            if (scene.tangents[v] != tangent) {
                const uint32_t copy = duplicate_vertex(scene, v);
                scene.tangents[copy] = tangent;
                next_copy.push_back(UINT32_MAX);
                ours.push_back(1);
                next_copy[v] = copy;
                v = copy;
            }
            corner = v;
        }
}

}  // namespace rt
