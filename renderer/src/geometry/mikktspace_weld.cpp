// The connectivity half of the MikkTSpace port (mikktspace.h): welding equal
// corners and finding each triangle's neighbours, as mikktspace.c does them.
// Which corner represents a weld and the order the edge sort leaves edges in
// both decide which triangles become neighbours, so both are the reference's
// own, quirks included (its edge sub-sorts skip the last run of equal keys).
#include <algorithm>
#include <bit>
#include <limits>
#include <optional>
#include <unordered_map>

#include "geometry/mikktspace_detail.h"

namespace rt::mikktspace_detail {
namespace {

constexpr int kCells = 2048;

struct TmpVert {
    float vert[3];
    int index;
};

// Kept out of line, as the reference insists, so that every call rounds the
// same way for the same value.
[[gnu::noinline]] int find_grid_cell(float min, float max, float value) {
    const float index = float(kCells) * ((value - min) / (max - min));
    // The reference converts to int unchecked; NaN and out-of-range values
    // land in the end cells, as x86's conversion and its clamp put them.
    if (!(index >= 0.0f)) return 0;
    if (index >= float(kCells)) return kCells - 1;
    return int(index);
}

bool same_corner(const Mesh& mesh, int a, int b) {
    const vec3 pa = mesh.position(a), pb = mesh.position(b);
    const vec3 na = mesh.normal(a), nb = mesh.normal(b);
    const vec3 ta = mesh.texcoord(a), tb = mesh.texcoord(b);
    return pa.x == pb.x && pa.y == pb.y && pa.z == pb.z && na.x == nb.x && na.y == nb.y && na.z == nb.z &&
           ta.x == tb.x && ta.y == tb.y && ta.z == tb.z;
}

// A corner's attributes as bits for hashing, canonical under float
// equality; none when one is NaN.
struct CornerKey {
    uint32_t bits[9];
    bool operator==(const CornerKey&) const = default;
};

struct CornerKeyHash {
    size_t operator()(const CornerKey& key) const {
        uint64_t h = 1469598103934665603ull;  // FNV-1a
        for (uint32_t b : key.bits) h = (h ^ b) * 1099511628211ull;
        return size_t(h);
    }
};

std::optional<CornerKey> corner_key(const Mesh& mesh, int index) {
    const vec3 p = mesh.position(index), n = mesh.normal(index), t = mesh.texcoord(index);
    const float values[9] = {p.x, p.y, p.z, n.x, n.y, n.z, t.x, t.y, t.z};
    CornerKey key;
    for (int k = 0; k < 9; ++k) {
        if (std::isnan(values[k])) return std::nullopt;
        key.bits[k] = std::bit_cast<uint32_t>(values[k] == 0.0f ? 0.0f : values[k]);
    }
    return key;
}

// The weld at the end of MergeVertsFast's recursion: each corner takes the
// representative of the first corner before it in [left, right] with equal
// attributes. The reference compares each with all before it; a leaf of
// many corners at one position (a hostile fan) is welded through a hash of
// the same equality instead (-0 equal to +0, NaN to nothing), which picks
// the same first corner.
void weld_leaf(std::vector<int>& tri_list, const std::vector<TmpVert>& tmp, const Mesh& mesh, int left, int right) {
    if (right - left < 32) {
        for (int l = left; l <= right; ++l) {
            const int i = tmp[size_t(l)].index;
            for (int l2 = left; l2 < l; ++l2) {
                const int i2 = tmp[size_t(l2)].index;
                if (same_corner(mesh, tri_list[size_t(i)], tri_list[size_t(i2)])) {
                    tri_list[size_t(i)] = tri_list[size_t(i2)];
                    break;
                }
            }
        }
        return;
    }
    std::unordered_map<CornerKey, int, CornerKeyHash> first;
    for (int l = left; l <= right; ++l) {
        const int i = tmp[size_t(l)].index;
        const std::optional<CornerKey> key = corner_key(mesh, tri_list[size_t(i)]);
        if (!key) continue;  // NaN: equal to nothing
        const auto [it, added] = first.try_emplace(*key, i);
        if (!added) tri_list[size_t(i)] = tri_list[size_t(it->second)];
    }
}

// MergeVertsFast: split [left, right] at the middle of its widest axis until
// a split no longer separates, then weld by comparing all attributes.
void merge_verts(std::vector<int>& tri_list, std::vector<TmpVert>& tmp, const Mesh& mesh, int left, int right) {
    float lo[3], hi[3];
    for (int c = 0; c < 3; ++c) lo[c] = hi[c] = tmp[size_t(left)].vert[c];
    for (int l = left + 1; l <= right; ++l)
        for (int c = 0; c < 3; ++c) {
            if (lo[c] > tmp[size_t(l)].vert[c]) lo[c] = tmp[size_t(l)].vert[c];
            if (hi[c] < tmp[size_t(l)].vert[c]) hi[c] = tmp[size_t(l)].vert[c];
        }
    const float dx = hi[0] - lo[0], dy = hi[1] - lo[1], dz = hi[2] - lo[2];
    const int channel = dy > dx && dy > dz ? 1 : dz > dx ? 2 : 0;
    const float sep = 0.5f * (hi[channel] + lo[channel]);
    if (!std::isfinite(sep)) return;  // all NaN: the reference gives up on the cell

    if (sep >= hi[channel] || sep <= lo[channel]) {
        weld_leaf(tri_list, tmp, mesh, left, right);
        return;
    }

    int il = left, ir = right;
    while (il < ir) {
        bool ready_left = false, ready_right = false;
        while (!ready_left && il < ir) {
            ready_left = !(tmp[size_t(il)].vert[channel] < sep);
            if (!ready_left) ++il;
        }
        while (!ready_right && il < ir) {
            ready_right = tmp[size_t(ir)].vert[channel] < sep;
            if (!ready_right) --ir;
        }
        if (ready_left && ready_right) {
            std::swap(tmp[size_t(il)], tmp[size_t(ir)]);
            ++il;
            --ir;
        }
    }
    if (il == ir) {
        if (tmp[size_t(ir)].vert[channel] < sep) ++il;
        else --ir;
    }
    if (left < ir) merge_verts(tri_list, tmp, mesh, left, ir);
    if (il < right) merge_verts(tri_list, tmp, mesh, il, right);
}

struct Edge {
    int key[3];  // i0 (the smaller corner), i1, f
};

// QuickSortEdges, with its seeded pivots: the order it leaves equal keys in
// matters, since the sub-sorts below miss a run.
void sort_edges(std::vector<Edge>& edges, int left, int right, int channel, uint32_t seed) {
    const int count = right - left + 1;
    if (count < 2) return;
    if (count == 2) {
        if (edges[size_t(left)].key[channel] > edges[size_t(right)].key[channel])
            std::swap(edges[size_t(left)], edges[size_t(right)]);
        return;
    }
    seed = seed + std::rotl(seed, int(seed & 31)) + 3;
    int il = left, ir = right;
    const int mid = edges[size_t(int(seed % uint32_t(count)) + left)].key[channel];
    do {
        while (edges[size_t(il)].key[channel] < mid) ++il;
        while (edges[size_t(ir)].key[channel] > mid) --ir;
        if (il <= ir) {
            std::swap(edges[size_t(il)], edges[size_t(ir)]);
            ++il;
            --ir;
        }
    } while (il <= ir);
    if (left < ir) sort_edges(edges, left, ir, channel, seed);
    if (il < right) sort_edges(edges, il, right, channel, seed);
}

// GetEdge: which edge of `corners` joins a and b, and its corners in the
// triangle's winding.
void get_edge(int& i0, int& i1, int& edge, const int* corners, int a, int b) {
    if (corners[0] == a || corners[0] == b) {
        if (corners[1] == a || corners[1] == b) {
            edge = 0, i0 = corners[0], i1 = corners[1];
        } else {
            edge = 2, i0 = corners[2], i1 = corners[0];
        }
    } else {
        edge = 1, i0 = corners[1], i1 = corners[2];
    }
}

}  // namespace

void weld_corners(std::vector<int>& tri_list, const Mesh& mesh, int triangles) {
    const int corners = triangles * 3;
    vec3 lo = mesh.position(0), hi = lo;  // the reference starts from corner index 0
    for (int i = 1; i < corners; ++i) {
        const vec3 p = mesh.position(tri_list[size_t(i)]);
        for (int c = 0; c < 3; ++c) {
            if (lo[c] > p[c]) lo[c] = p[c];
            else if (hi[c] < p[c]) hi[c] = p[c];
        }
    }
    const vec3 dim = hi - lo;
    const int channel = dim.y > dim.x && dim.y > dim.z ? 1 : dim.z > dim.x ? 2 : 0;
    const float min = lo[channel], max = hi[channel];

    std::vector<int> cell_of(static_cast<size_t>(corners)), count(kCells, 0), offset(kCells, 0);
    for (int i = 0; i < corners; ++i) {
        cell_of[size_t(i)] = find_grid_cell(min, max, mesh.position(tri_list[size_t(i)])[channel]);
        ++count[size_t(cell_of[size_t(i)])];
    }
    for (int k = 1; k < kCells; ++k) offset[size_t(k)] = offset[size_t(k - 1)] + count[size_t(k - 1)];
    std::vector<int> table(static_cast<size_t>(corners)), filled(kCells, 0);
    for (int i = 0; i < corners; ++i) {
        const int cell = cell_of[size_t(i)];
        table[size_t(offset[size_t(cell)] + filled[size_t(cell)]++)] = i;
    }

    std::vector<TmpVert> tmp(size_t(*std::max_element(count.begin(), count.end())));
    for (int k = 0; k < kCells; ++k) {
        const int entries = count[size_t(k)];
        if (entries < 2) continue;
        for (int e = 0; e < entries; ++e) {
            const int i = table[size_t(offset[size_t(k)] + e)];
            const vec3 p = mesh.position(tri_list[size_t(i)]);
            tmp[size_t(e)] = TmpVert{{p.x, p.y, p.z}, i};
        }
        merge_verts(tri_list, tmp, mesh, 0, entries - 1);
    }
}

void build_neighbours(std::vector<TriInfo>& infos, const std::vector<int>& tri_list, int triangles) {
    const uint32_t seed = 39871946;  // INTERNAL_RND_SORT_SEED
    const int entries = triangles * 3;
    std::vector<Edge> edges(static_cast<size_t>(entries));
    for (int f = 0; f < triangles; ++f)
        for (int i = 0; i < 3; ++i) {
            const int i0 = tri_list[size_t(f * 3 + i)], i1 = tri_list[size_t(f * 3 + (i < 2 ? i + 1 : 0))];
            edges[size_t(f * 3 + i)] = Edge{{std::min(i0, i1), i0 < i1 ? i1 : i0, f}};
        }
    sort_edges(edges, 0, entries - 1, 0, seed);
    // Sub-sorts by i1, then f, of each run of equal keys but the last (as the reference does).
    for (int channel = 1; channel < 3; ++channel) {
        int start = 0;
        for (int i = 1; i < entries; ++i) {
            bool same = edges[size_t(start)].key[0] == edges[size_t(i)].key[0];
            if (channel == 2) same = same && edges[size_t(start)].key[1] == edges[size_t(i)].key[1];
            if (!same) {
                sort_edges(edges, start, i - 1, channel, seed);
                start = i;
            }
        }
    }

    for (int i = 0; i < entries; ++i) {
        const Edge& e = edges[size_t(i)];
        const int f = e.key[2];
        int i0_a, i1_a, edge_a;
        get_edge(i0_a, i1_a, edge_a, &tri_list[size_t(f * 3)], e.key[0], e.key[1]);
        if (infos[size_t(f)].neighbours[edge_a] != -1) continue;
        for (int j = i + 1; j < entries && edges[size_t(j)].key[0] == e.key[0] && edges[size_t(j)].key[1] == e.key[1];
             ++j) {
            const int t = edges[size_t(j)].key[2];
            int i0_b, i1_b, edge_b;
            get_edge(i1_b, i0_b, edge_b, &tri_list[size_t(t * 3)], edges[size_t(j)].key[0], edges[size_t(j)].key[1]);
            if (i0_a == i0_b && i1_a == i1_b && infos[size_t(t)].neighbours[edge_b] == -1) {
                infos[size_t(f)].neighbours[edge_a] = t;
                infos[size_t(t)].neighbours[edge_b] = f;
                break;
            }
        }
    }
}

}  // namespace rt::mikktspace_detail
