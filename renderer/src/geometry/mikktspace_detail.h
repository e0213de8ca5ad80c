// What the two halves of the MikkTSpace port (mikktspace.h) share: the
// reference's corner indices and per-triangle records, and its float
// arithmetic, written out so that every rounding is the reference's (glm's
// normalize multiplies by an inverse square root, the reference by 1 / length).
#pragma once

#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "geometry/mikktspace.h"

namespace rt::mikktspace_detail {

// The reference's triangle flags.
enum : int { kDegenerate = 1, kGroupWithAny = 4, kOrientPreserving = 8 };

inline float dot3(vec3 a, vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline float length3(vec3 v) { return std::sqrt(dot3(v, v)); }
inline vec3 scale3(float s, vec3 v) { return vec3(s * v.x, s * v.y, s * v.z); }
inline vec3 normalize3(vec3 v) { return scale3(1 / length3(v), v); }
inline bool not_zero(float x) { return std::fabs(x) > 1.17549435e-38f; }  // FLT_MIN
inline bool not_zero(vec3 v) { return not_zero(v.x) || not_zero(v.y) || not_zero(v.z); }
// The part of v perpendicular to n, normalised where it is not zero.
inline vec3 project_normalized(vec3 v, vec3 n) {
    const vec3 p = v - scale3(dot3(n, v), n);
    return not_zero(p) ? normalize3(p) : p;
}

// A corner named as the reference names it: (face << 2) | vertex.
inline int corner_index(int face, int vertex) { return (face << 2) | (vertex & 3); }

class Mesh {
public:
    explicit Mesh(std::span<const TangentCorner> corners) : corners_(corners) {}
    const TangentCorner& corner(int index) const { return corners_[size_t(index >> 2) * 3 + size_t(index & 3)]; }
    vec3 position(int index) const { return corner(index).position; }
    vec3 normal(int index) const { return corner(index).normal; }
    // The reference reads texcoords as (u, v, 1).
    vec3 texcoord(int index) const { return vec3(corner(index).texcoord, 1.0f); }

private:
    std::span<const TangentCorner> corners_;
};

struct TriInfo {
    int neighbours[3] = {-1, -1, -1};  // the triangle across edge i (corner i to i + 1), or -1
    int group[3] = {-1, -1, -1};       // the group of corner i, or -1
    vec3 os{0.0f}, ot{0.0f};           // normalised first-order derivatives dP/ds, dP/dt
    float mag_s = 0.0f, mag_t = 0.0f;  // their magnitudes
    int face = 0;                      // the input triangle, whose corners are 3 * face + i
    int flags = 0;
};

// GenerateSharedVerticesIndexList: each corner index in `tri_list` replaced
// by that of the first corner in its cell with the same position, normal and
// texcoord, through the reference's grid and recursive split.
void weld_corners(std::vector<int>& tri_list, const Mesh& mesh, int triangles);

// BuildNeighborsFast: the neighbour across each edge of the first
// `triangles` triangles, matched through the reference's edge sort.
void build_neighbours(std::vector<TriInfo>& infos, const std::vector<int>& tri_list, int triangles);

}  // namespace rt::mikktspace_detail
