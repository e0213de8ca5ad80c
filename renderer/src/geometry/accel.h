// The scene's ray queries: an eight-wide BVH over its triangles (bvh/), with
// the triangles in SIMD-ready leaf blocks, plus its analytic spheres. This is
// the only interface the integrator, the debugger and rtcore use.
//
// A scene with instances (geometry/instance.h) gets one tree per shared mesh,
// in the mesh's space, and a top-level tree over the instances' world boxes
// (Embree's two-level instancing): a ray entering an instance's box is taken
// into the mesh's space and meets its tree there. Hits say which instance.
//
// The tree is built as a binary SAH tree (bvh/binned_sah_builder.h) and
// collapsed (bvh/wide_collapse.h). The queries run the kernels of the widest
// SIMD path the CPU has (util/cpu_features.h); every path returns the same hits.
//
// In a moving scene the tree is built over the union of each triangle's boxes
// at shutter open and close, then each node keeps its children's boxes at
// both times (bvh::refit_motion): a ray tests them interpolated to ray.time,
// which hold the triangles then since their vertices move in straight lines,
// and meets each triangle as it is at ray.time.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "bvh/packet_rays.h"
#include "geometry/accel_data.h"
#include "geometry/scene.h"
#include "geometry/traversal_stats.h"
#include "util/bounds.h"
#include "util/cpu_features.h"
#include "util/ray.h"

namespace rt {

// Summed over every tree: the world tree, each shared mesh's and the top-level one.
struct AccelStats {
    size_t triangles = 0;   // stored, each shared mesh's once
    size_t instances = 0;
    size_t nodes = 0;       // wide nodes
    size_t leaves = 0;
    size_t leaf_blocks = 0;  // blocks of four triangle slots
    // Of the tree boxes() walks: the top-level one when there are instances, else the world tree.
    uint32_t depth = 0;     // levels below the root, leaves included
    double build_ms = 0.0;
    double sah_cost = 0.0;  // bvh::WideBvh::sah_cost with the costs below
    size_t node_bytes = 0;  // the wide nodes (and the top-level tree's entries)
    size_t leaf_bytes = 0;  // the triangle blocks (both of them in a moving scene)
};

class Accelerator {
  public:
    // Builds the BVH on `threads` threads (0: all cores). The scene must
    // outlive this. `path` picks the kernels; by default simd_path().
    explicit Accelerator(const Scene& scene, unsigned threads = 0);
    Accelerator(const Scene& scene, unsigned threads, SimdPath path);

    // Closest hit with 0 < t < ray.t_max, at ray.time. The overloads taking stats or a
    // record (here and below) add this traversal to what they already hold.
    bool intersect(const Ray& ray, Hit& hit) const { return kernels_->intersect(data_, ray, hit); }
    bool intersect(const Ray& ray, Hit& hit, TraversalStats& stats) const {
        return kernels_->intersect_counted(data_, ray, hit, stats);
    }
    bool intersect(const Ray& ray, Hit& hit, TraversalRecord& record) const {
        return kernels_->intersect_recorded(data_, ray, hit, record);
    }

    // How much light passes along the ray for 0 < t < ray.t_max: 0 at the
    // first opaque hit (where the traversal stops), 1 with no hit, and the
    // product of (1 - alpha) over BLEND surfaces in between. MASK holes and
    // fully transparent texels are no hits, for these queries as for intersect.
    float visibility(const Ray& ray) const { return kernels_->visibility(data_, ray); }
    float visibility(const Ray& ray, TraversalStats& stats) const {
        return kernels_->visibility_counted(data_, ray, stats);
    }
    float visibility(const Ray& ray, TraversalRecord& record) const {
        return kernels_->visibility_recorded(data_, ray, record);
    }
    // visibility() == 0.
    bool occluded(const Ray& ray) const { return visibility(ray) == 0.0f; }
    bool occluded(const Ray& ray, TraversalStats& stats) const { return visibility(ray, stats) == 0.0f; }
    bool occluded(const Ray& ray, TraversalRecord& record) const { return visibility(ray, record) == 0.0f; }

    // Packets of up to kPacketSize coherent rays, such as a tile's 4 x 4 camera
    // rays (one origin) or an orthographic beam (one direction), and for
    // visibility any shadow rays, such as a point's samples of an area light:
    // the answers of the single-ray queries, found with one traversal of the
    // tree (bvh/packet_rays.h, bvh/packet_masked_traverse.inl); in a moving
    // scene each ray at its time. Other packets, and scenes with alpha or
    // instances (packets_serve() false), are traced ray by ray. Returns whether the packet traversal served them. Throws
    // std::invalid_argument when the spans differ in size or hold more than
    // kPacketSize rays.
    static constexpr uint32_t kPacketSize = bvh::kPacketSize;
    bool intersect(std::span<const Ray> rays, std::span<Hit> hits) const;
    bool visibility(std::span<const Ray> rays, std::span<float> visibility) const;
    // Whether packets of this scene go through the packet traversal.
    bool packets_serve() const;

    // The world-space triangles' tree.
    const bvh::WideBvh& wide_bvh() const { return data_.world.bvh; }
    const AccelStats& stats() const { return stats_; }
    const Scene& scene() const { return *data_.scene; }
    SimdPath simd() const { return path_; }

    // Boxes of the tree at one level (0 = root), or of all leaves (level < 0),
    // numbered as TraversalRecord::visited_nodes numbers them: the top-level
    // tree's when there are instances, whose leaves count the triangles they place.
    struct LevelBoxes {
        std::vector<uint32_t> nodes;
        std::vector<Bounds3> bounds;
        std::vector<uint32_t> triangles;  // triangles under each box
        std::vector<uint8_t> leaf;        // 1 where the box is a leaf's
        uint32_t depth = 0;               // of the tree walked: levels below its root
        Affine to_world;                  // from the tree's space: an instance's transform
    };
    // The tree to walk: the top level (a scene's only tree when it has no
    // instances), or one that a top-level entry leads to (EnteredTree::entry:
    // an instance number, or AccelScene::kWorldEntry for the triangles placed
    // once). Throws std::invalid_argument for an entry the scene lacks.
    static constexpr uint32_t kTopTree = ~0u;
    LevelBoxes boxes(int level, uint32_t tree = kTopTree) const;
    // Instances the top level places, and whether it has a world-tree entry.
    size_t instance_count() const { return data_.scene->instances.size(); }
    bool has_world_entry() const { return data_.instanced() && !data_.world.bvh.empty(); }

  private:
    AccelScene data_;
    SimdPath path_;
    const AccelKernels* kernels_;
    AccelStats stats_;
};

}  // namespace rt
