// What the ray query kernels read: the wide BVHs and their triangle blocks, the
// tree over the instances when the scene has any, and the observers the
// debugger passes. Kept apart from Accelerator so that the kernels, compiled
// once per SIMD path (accel_kernels.inl), see plain data.
#pragma once

#include <vector>

#include "bvh/wide_bvh.h"
#include "geometry/scene.h"
#include "geometry/traversal_stats.h"
#include "geometry/triangle_block.h"
#include "util/ray.h"

namespace rt {

// One tree over triangles: the scene's world-space ones, or one shared mesh's
// in its own space. Its blocks hold Scene::triangles numbers.
struct AccelData {
    const Scene* scene = nullptr;
    bvh::WideBvh bvh;  // its prim_ids are dropped once copied into `blocks`
    // The triangles at shutter open, and their motion (close - open) when the
    // scene moves (else empty).
    HugePageVector<TriangleBlock> blocks;
    HugePageVector<TriangleBlock> blocks_motion;
    bool moving = false;
    bool filtered = false;  // some triangle's material has alpha (MASK or BLEND)
};

// The scene's queries: spheres, then its triangle trees. With instances, a
// top-level tree over the instances' world boxes (and the world-space
// triangles' tree as one more entry) leads to the trees they place; without,
// the world tree alone, as fast as a scene with no instancing at all.
struct AccelScene {
    const Scene* scene = nullptr;
    AccelData world;
    std::vector<AccelData> meshes;  // one per Scene::meshes entry
    // Its leaves' prim_ids are entries: an instance number, or kWorldEntry.
    bvh::WideBvh top;
    static constexpr uint32_t kWorldEntry = kNoInstance - 1;

    bool instanced() const { return !top.empty(); }
    // Whether packets take the packet traversal: an opaque world tree only.
    bool packets_serve() const { return !instanced() && !world.filtered && !world.bvh.empty(); }
    const AccelData& tree_of(uint32_t entry) const {
        return entry == kWorldEntry ? world : meshes[scene->instances[entry].mesh];
    }
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

// Inside the tree a top-level entry leads to: the nodes and triangles count
// with the rest, and a record lists the boxes, in that tree's numbering, apart.
struct TreeRecordingObserver {
    TraversalRecord& record;
    size_t tree;  // into record.entered, which may grow while this lives
    void visit_node(uint32_t node) {
        ++record.nodes_visited;
        record.entered[tree].visited_nodes.push_back(node);
    }
    void visit_leaf(uint32_t leaf) { record.entered[tree].visited_leaves.push_back(leaf); }
    void test_triangles(uint32_t count) { record.triangles_tested += count; }
};

inline SilentObserver nested(SilentObserver o, uint32_t) { return o; }
inline CountingObserver nested(CountingObserver o, uint32_t) { return o; }
inline TreeRecordingObserver nested(RecordingObserver o, uint32_t entry) {
    o.record.entered.push_back({entry, {}, {}});
    return {o.record, o.record.entered.size() - 1};
}

// The query kernels of one SIMD path (accel_kernels.inl). intersect() finds
// the closest hit; visibility() the light passing along the ray.
struct AccelKernels {
    bool (*intersect)(const AccelScene&, const Ray&, Hit&);
    bool (*intersect_counted)(const AccelScene&, const Ray&, Hit&, TraversalStats&);
    bool (*intersect_recorded)(const AccelScene&, const Ray&, Hit&, TraversalRecord&);
    float (*visibility)(const AccelScene&, const Ray&);
    float (*visibility_counted)(const AccelScene&, const Ray&, TraversalStats&);
    float (*visibility_recorded)(const AccelScene&, const Ray&, TraversalRecord&);
    // Up to bvh::kPacketSize coherent rays at once (accel_packet_kernels.inl).
    bool (*intersect_packet)(const AccelScene&, const Ray*, uint32_t, Hit*);
    bool (*visibility_packet)(const AccelScene&, const Ray*, uint32_t, float*);
};

namespace generic { extern const AccelKernels kKernels; }
namespace avx2 { extern const AccelKernels kKernels; }
namespace avx512 { extern const AccelKernels kKernels; }

}  // namespace rt
