// What the ray query kernels read: the wide BVH and its triangle blocks, and
// the observers the debugger passes. Kept apart from Accelerator so that the
// kernels, compiled once per SIMD path (accel_kernels.inl), see plain data.
#pragma once

#include <vector>

#include "bvh/wide_bvh.h"
#include "geometry/scene.h"
#include "geometry/traversal_stats.h"
#include "geometry/triangle_block.h"
#include "util/ray.h"

namespace rt {

struct AccelData {
    const Scene* scene = nullptr;
    bvh::WideBvh bvh;  // its prim_ids are dropped once copied into `blocks`
    // The triangles at shutter open, and their motion (close - open) when the
    // scene moves (else empty).
    std::vector<TriangleBlock> blocks;
    std::vector<TriangleBlock> blocks_motion;
    bool moving = false;
    bool filtered = false;  // some triangle's material has alpha (MASK or BLEND)
};

struct SilentObserver {
    void visit_node(uint32_t) {}
    void visit_leaf(uint32_t) {}
    void test_triangles(uint32_t) {}
};

struct CountingObserver {
    TraversalStats& stats;
    void visit_node(uint32_t) { ++stats.nodes_visited; }
    void visit_leaf(uint32_t) {}
    void test_triangles(uint32_t count) { stats.triangles_tested += count; }
};

struct RecordingObserver {
    TraversalRecord& record;
    void visit_node(uint32_t node) {
        ++record.nodes_visited;
        record.visited_nodes.push_back(node);
    }
    void visit_leaf(uint32_t leaf) { record.visited_leaves.push_back(leaf); }
    void test_triangles(uint32_t count) { record.triangles_tested += count; }
};

// The query kernels of one SIMD path (accel_kernels.inl). intersect() finds
// the closest hit; visibility() the light passing along the ray.
struct AccelKernels {
    bool (*intersect)(const AccelData&, const Ray&, Hit&);
    bool (*intersect_counted)(const AccelData&, const Ray&, Hit&, TraversalStats&);
    bool (*intersect_recorded)(const AccelData&, const Ray&, Hit&, TraversalRecord&);
    float (*visibility)(const AccelData&, const Ray&);
    float (*visibility_counted)(const AccelData&, const Ray&, TraversalStats&);
    float (*visibility_recorded)(const AccelData&, const Ray&, TraversalRecord&);
};

namespace generic { extern const AccelKernels kKernels; }
namespace avx2 { extern const AccelKernels kKernels; }

}  // namespace rt
