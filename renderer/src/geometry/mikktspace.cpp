// The tangent-space half of the MikkTSpace port (mikktspace.h): per-triangle
// derivatives, the groups of welded corners that share a tangent space, and
// the spaces themselves, as mikktspace.c's genTangSpace computes them with
// its default angular threshold (180 degrees: no split by angle). The
// reference's quad paths are gone: every face here is a triangle.
#include "geometry/mikktspace.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "geometry/mikktspace_detail.h"

namespace rt {
namespace {

using namespace mikktspace_detail;

struct TSpace {
    vec3 os{1.0f, 0.0f, 0.0f};
    float mag_s = 1.0f;
    vec3 ot{0.0f, 1.0f, 0.0f};
    float mag_t = 1.0f;
    int counter = 0;  // how many groups wrote it: a corner is in at most two
    bool orient = false;
};

struct Group {
    int vertex = 0;  // the welded corner index all its triangles share
    bool orient_preserving = false;
    std::vector<int> faces;
};

// AvgTSpace; the equality test keeps a space averaged with itself exact,
// which would otherwise split spaces later.
TSpace average(const TSpace& a, const TSpace& b) {
    TSpace r;
    if (a.mag_s == b.mag_s && a.mag_t == b.mag_t && a.os == b.os && a.ot == b.ot) {
        r.mag_s = a.mag_s, r.mag_t = a.mag_t, r.os = a.os, r.ot = a.ot;
        return r;
    }
    r.mag_s = 0.5f * (a.mag_s + b.mag_s);
    r.mag_t = 0.5f * (a.mag_t + b.mag_t);
    r.os = a.os + b.os;
    r.ot = a.ot + b.ot;
    if (not_zero(r.os)) r.os = normalize3(r.os);
    if (not_zero(r.ot)) r.ot = normalize3(r.ot);
    return r;
}

// InitTriInfo's derivatives (the thesis's equations 18 and 19): a triangle
// is good when its uv area and both derivatives are not zero.
void init_tri_info(std::vector<TriInfo>& infos, const std::vector<int>& tri_list, const Mesh& mesh, int triangles) {
    for (int f = 0; f < triangles; ++f) {
        TriInfo& info = infos[size_t(f)];
        info.flags |= kGroupWithAny;  // assumed bad
        const int* c = &tri_list[size_t(f * 3)];
        const vec3 v1 = mesh.position(c[0]), v2 = mesh.position(c[1]), v3 = mesh.position(c[2]);
        const vec3 t1 = mesh.texcoord(c[0]), t2 = mesh.texcoord(c[1]), t3 = mesh.texcoord(c[2]);
        const float t21x = t2.x - t1.x, t21y = t2.y - t1.y, t31x = t3.x - t1.x, t31y = t3.y - t1.y;
        const vec3 d1 = v2 - v1, d2 = v3 - v1;
        const float signed_area = t21x * t31y - t21y * t31x;
        const vec3 os = scale3(t31y, d1) - scale3(t21y, d2);
        const vec3 ot = scale3(-t31x, d1) + scale3(t21x, d2);
        if (signed_area > 0) info.flags |= kOrientPreserving;
        if (!not_zero(signed_area)) continue;
        const float abs_area = std::fabs(signed_area);
        const float len_os = length3(os), len_ot = length3(ot);
        const float sign = (info.flags & kOrientPreserving) == 0 ? -1.0f : 1.0f;
        if (not_zero(len_os)) info.os = scale3(sign / len_os, os);
        if (not_zero(len_ot)) info.ot = scale3(sign / len_ot, ot);
        info.mag_s = len_os / abs_area;
        info.mag_t = len_ot / abs_area;
        if (not_zero(info.mag_s) && not_zero(info.mag_t)) info.flags &= ~kGroupWithAny;
    }
    build_neighbours(infos, tri_list, triangles);
}

// AssignRecur: grow `group` through the triangles around its vertex that
// agree with it on orientation. The reference recurses; an explicit stack
// reaches the same triangles (acceptance does not depend on the order) without
// a hostile fan of a million triangles overflowing the call stack.
void assign(const std::vector<int>& tri_list, std::vector<TriInfo>& infos, int first, int group_index,
            std::vector<Group>& groups) {
    Group& group = groups[size_t(group_index)];
    std::vector<int> stack{first};
    while (!stack.empty()) {
        const int tri = stack.back();
        stack.pop_back();
        TriInfo& info = infos[size_t(tri)];
        const int* c = &tri_list[size_t(3 * tri)];
        const int i = c[0] == group.vertex ? 0 : c[1] == group.vertex ? 1 : c[2] == group.vertex ? 2 : -1;
        if (i < 0 || info.group[i] != -1) continue;  // i < 0: the reference asserts it never is
        // The first group to reach a group-with-anything triangle gives it its
        // orientation: the reference's one order dependency (between groups).
        if ((info.flags & kGroupWithAny) != 0 && info.group[0] == -1 && info.group[1] == -1 && info.group[2] == -1) {
            info.flags &= ~kOrientPreserving;
            info.flags |= group.orient_preserving ? kOrientPreserving : 0;
        }
        if (((info.flags & kOrientPreserving) != 0) != group.orient_preserving) continue;
        group.faces.push_back(tri);
        info.group[i] = group_index;
        const int left = info.neighbours[i], right = info.neighbours[i > 0 ? i - 1 : 2];
        if (right >= 0) stack.push_back(right);
        if (left >= 0) stack.push_back(left);
    }
}

// Build4RuleGroups.
std::vector<Group> build_groups(std::vector<TriInfo>& infos, const std::vector<int>& tri_list, int triangles) {
    std::vector<Group> groups;
    for (int f = 0; f < triangles; ++f)
        for (int i = 0; i < 3; ++i) {
            if ((infos[size_t(f)].flags & kGroupWithAny) != 0 || infos[size_t(f)].group[i] != -1) continue;
            const int g = int(groups.size());
            groups.push_back(Group{tri_list[size_t(f * 3 + i)], (infos[size_t(f)].flags & kOrientPreserving) != 0, {}});
            infos[size_t(f)].group[i] = g;
            groups[size_t(g)].faces.push_back(f);
            const int left = infos[size_t(f)].neighbours[i], right = infos[size_t(f)].neighbours[i > 0 ? i - 1 : 2];
            if (left >= 0) assign(tri_list, infos, left, g, groups);
            if (right >= 0) assign(tri_list, infos, right, g, groups);
        }
    return groups;
}

// EvalTspace: the group's derivatives projected into the vertex's tangent
// plane, weighted by the angle each triangle spans at the vertex.
TSpace eval_tspace(const std::vector<int>& members, const std::vector<int>& tri_list,
                   const std::vector<TriInfo>& infos, const Mesh& mesh, int vertex) {
    TSpace r;
    r.os = r.ot = vec3(0.0f);
    r.mag_s = r.mag_t = 0.0f;
    float angle_sum = 0.0f;
    for (int f : members) {
        const TriInfo& info = infos[size_t(f)];
        if ((info.flags & kGroupWithAny) != 0) continue;
        const int* c = &tri_list[size_t(3 * f)];
        const int i = c[0] == vertex ? 0 : c[1] == vertex ? 1 : 2;
        const vec3 n = mesh.normal(c[i]);
        const vec3 os = project_normalized(info.os, n), ot = project_normalized(info.ot, n);
        const vec3 p0 = mesh.position(c[i > 0 ? i - 1 : 2]), p1 = mesh.position(c[i]),
                   p2 = mesh.position(c[i < 2 ? i + 1 : 0]);
        const vec3 v1 = project_normalized(p0 - p1, n), v2 = project_normalized(p2 - p1, n);
        const float cos_angle = std::clamp(dot3(v1, v2), -1.0f, 1.0f);
        const float angle = float(std::acos(double(cos_angle)));
        r.os = r.os + scale3(angle, os);
        r.ot = r.ot + scale3(angle, ot);
        r.mag_s += angle * info.mag_s;
        r.mag_t += angle * info.mag_t;
        angle_sum += angle;
    }
    if (not_zero(r.os)) r.os = normalize3(r.os);
    if (not_zero(r.ot)) r.ot = normalize3(r.ot);
    if (angle_sum > 0) {
        r.mag_s /= angle_sum;
        r.mag_t /= angle_sum;
    }
    return r;
}

// GenerateTSpaces: within a group, each triangle's sub-group is the
// triangles whose projected derivatives lie within the angular threshold of
// its own; equal sub-groups share one space. At the default 180 degrees that
// is every triangle but those whose derivatives point exactly the other way
// (cos = -1 is not above the threshold). The test is quadratic in a group's
// size, as in the reference; past kMaxExactGroup triangles around one vertex
// (a hostile fan) the group is taken as one sub-group.
constexpr size_t kMaxExactGroup = 4096;

void output_tspace(std::vector<TSpace>& spaces, const TriInfo& info, int group_index, bool orient,
                   const TSpace& space) {
    const int index = info.group[0] == group_index ? 0 : info.group[1] == group_index ? 1 : 2;
    TSpace& out = spaces[size_t(3 * info.face + index)];
    if (out.counter == 1) {
        out = average(out, space);
        out.counter = 2;
    } else {
        out = space;
        out.counter = 1;
    }
    out.orient = orient;
}

void generate_tspaces(std::vector<TSpace>& spaces, const std::vector<TriInfo>& infos,
                      const std::vector<Group>& groups, const std::vector<int>& tri_list, const Mesh& mesh) {
    const float threshold = float(std::cos(double((180.0f * std::numbers::pi_v<float>) / 180.0f)));
    std::vector<vec3> os, ot;
    std::vector<std::pair<std::vector<int>, TSpace>> subgroups;
    for (size_t g = 0; g < groups.size(); ++g) {
        const Group& group = groups[g];
        const std::vector<int>& faces = group.faces;
        const vec3 n = mesh.normal(group.vertex);
        os.clear(), ot.clear(), subgroups.clear();
        for (int f : faces) {
            os.push_back(project_normalized(infos[size_t(f)].os, n));
            ot.push_back(project_normalized(infos[size_t(f)].ot, n));
        }
        if (faces.size() > kMaxExactGroup) {
            std::vector<int> members = faces;
            std::sort(members.begin(), members.end());
            const TSpace space = eval_tspace(members, tri_list, infos, mesh, group.vertex);
            for (int f : faces) output_tspace(spaces, infos[size_t(f)], int(g), group.orient_preserving, space);
            continue;
        }
        for (size_t i = 0; i < faces.size(); ++i) {
            const int f = faces[i];
            std::vector<int> members;
            for (size_t j = 0; j < faces.size(); ++j) {
                const int t = faces[j];
                const bool any = ((infos[size_t(f)].flags | infos[size_t(t)].flags) & kGroupWithAny) != 0;
                if (any || f == t || (dot3(os[i], os[j]) > threshold && dot3(ot[i], ot[j]) > threshold))
                    members.push_back(t);
            }
            std::sort(members.begin(), members.end());
            auto found = std::find_if(subgroups.begin(), subgroups.end(),
                                      [&](const auto& sub) { return sub.first == members; });
            if (found == subgroups.end()) {
                const TSpace space = eval_tspace(members, tri_list, infos, mesh, group.vertex);
                subgroups.emplace_back(std::move(members), space);
                found = subgroups.end() - 1;
            }
            output_tspace(spaces, infos[size_t(f)], int(g), group.orient_preserving, found->second);
        }
    }
}

// DegenPrologue: degenerate triangles (two equal positions) go last, the
// good ones keeping their order. Returns how many are good.
int degenerates_last(std::vector<int>& tri_list, std::vector<TriInfo>& infos, const Mesh& mesh, int total) {
    int degenerate = 0;
    for (int t = 0; t < total; ++t) {
        const vec3 p0 = mesh.position(tri_list[size_t(t * 3)]), p1 = mesh.position(tri_list[size_t(t * 3 + 1)]),
                   p2 = mesh.position(tri_list[size_t(t * 3 + 2)]);
        if (p0 == p1 || p0 == p2 || p1 == p2) {
            infos[size_t(t)].flags |= kDegenerate;
            ++degenerate;
        }
    }
    const int good = total - degenerate;
    for (int t = 0, next = 1; t < good; ++t) {
        if ((infos[size_t(t)].flags & kDegenerate) == 0) {
            next = std::max(next, t + 2);
            continue;
        }
        while (next < total && (infos[size_t(next)].flags & kDegenerate) != 0) ++next;
        if (next >= total) break;  // cannot happen: there are `good` good ones
        for (int i = 0; i < 3; ++i) std::swap(tri_list[size_t(t * 3 + i)], tri_list[size_t(next * 3 + i)]);
        std::swap(infos[size_t(t)], infos[size_t(next)]);
        ++next;
    }
    return good;
}

// DegenEpilogue: a degenerate triangle's corner copies the space of the
// first good corner welded to it; one welded to none keeps the default.
void copy_to_degenerates(std::vector<TSpace>& spaces, const std::vector<int>& tri_list,
                         const std::vector<TriInfo>& infos, int good, int total) {
    std::vector<int> first_good(size_t(total) * 4, -1);  // by welded corner index
    for (int j = 3 * good - 1; j >= 0; --j) first_good[size_t(tri_list[size_t(j)])] = j;
    for (int t = good; t < total; ++t)
        for (int i = 0; i < 3; ++i) {
            const int j = first_good[size_t(tri_list[size_t(t * 3 + i)])];
            if (j < 0) continue;
            spaces[size_t(3 * infos[size_t(t)].face + i)] = spaces[size_t(3 * infos[size_t(j / 3)].face + j % 3)];
        }
}

}  // namespace

std::vector<glm::vec4> mikktspace_tangents(std::span<const TangentCorner> corners) {
    if (corners.size() % 3 != 0) throw std::invalid_argument("mikktspace_tangents: corners are not whole triangles");
    // Corner indices are (face << 2) | vertex in an int.
    if (corners.size() / 3 > size_t(std::numeric_limits<int>::max() >> 3))
        throw std::invalid_argument("mikktspace_tangents: too many triangles");
    const int total = int(corners.size() / 3);
    std::vector<glm::vec4> tangents(corners.size(), glm::vec4(1.0f, 0.0f, 0.0f, 1.0f));
    if (total == 0) return tangents;
    const Mesh mesh(corners);

    std::vector<int> tri_list(size_t(total) * 3);
    std::vector<TriInfo> infos(static_cast<size_t>(total));
    for (int f = 0; f < total; ++f) {
        infos[size_t(f)].face = f;
        for (int i = 0; i < 3; ++i) tri_list[size_t(f * 3 + i)] = corner_index(f, i);
    }
    weld_corners(tri_list, mesh, total);

    const int good = degenerates_last(tri_list, infos, mesh, total);
    init_tri_info(infos, tri_list, mesh, good);
    std::vector<Group> groups = build_groups(infos, tri_list, good);
    std::vector<TSpace> spaces(corners.size());
    generate_tspaces(spaces, infos, groups, tri_list, mesh);

    copy_to_degenerates(spaces, tri_list, infos, good, total);

    for (size_t c = 0; c < corners.size(); ++c)
        tangents[c] = glm::vec4(spaces[c].os, spaces[c].orient ? 1.0f : -1.0f);
    return tangents;
}

}  // namespace rt
