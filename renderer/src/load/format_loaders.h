// The contract between loader.cpp and the per-format loaders (gltf_loader.cpp,
// obj_loader.cpp): what they hand back for the shared finalisation, and the
// limits they enforce before allocating anything a file's counts ask for.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "geometry/scene.h"
#include "load/scene_extras.h"
#include "load/scene_files.h"

namespace rt {

// Upper bounds on a scene's size. A count read from a file is checked against
// the data that backs it and against these before it sizes any allocation.
inline constexpr size_t kMaxSceneVertices = size_t(1) << 26;
inline constexpr size_t kMaxSceneTriangles = size_t(1) << 26;

// The material of a triangle its file gives none; finalisation supplies one.
inline constexpr uint32_t kNoMaterial = 0xffffffffu;

// A scene as a format loader leaves it, in world space:
// - `normals` has one entry per vertex, zero where the file gives none (the
//   finalisation computes those), and so has `normals_close` when anything moves;
// - `texcoords` has one entry per vertex when `has_texcoords`, else none;
// - `triangle_materials` may hold kNoMaterial;
// - degenerate triangles are still there.
struct LoadedScene {
    Scene scene;
    bool has_texcoords = false;

    // What the file itself says in the form of rt.SceneExtras (glTF
    // `extras.rt`), for loader.cpp to add; its motions are applied already.
    std::vector<SceneAdditions> extras;
};

// The loaders apply `motions` (from the sidecar) to the nodes, objects or
// groups they name, and throw SceneError for a name that matches none.

// A .gltf (JSON) or .glb (`binary`) file's content.
LoadedScene load_gltf(std::span<const unsigned char> data, bool binary, const SceneFolder& folder,
                      std::span<const SceneAdditions::Motion> motions);

// An .obj file's content.
LoadedScene load_obj(std::span<const unsigned char> data, const SceneFolder& folder,
                     std::span<const SceneAdditions::Motion> motions);

// Whether every component of `v` converts to a finite float: converting a double
// beyond float's range is undefined behaviour, not infinity.
inline bool fits_float(dvec3 v) {
    const double limit = std::numeric_limits<float>::max();
    return std::abs(v.x) <= limit && std::abs(v.y) <= limit && std::abs(v.z) <= limit;
}

// A number read from a file as a message shows it: 1e+300, not 301 digits.
inline std::string shown(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", value);
    return text;
}

// Throws SceneError naming `what` unless `vertices` and `triangles` more fit
// into `scene` within the limits above.
void check_geometry_limits(const Scene& scene, size_t vertices, size_t triangles, const std::string& what);

}  // namespace rt
