// The scene's ray queries: a BVH over its triangles (bvh/) plus its analytic
// spheres. This is the only interface the integrator, the debugger and rtcore use.
//
// In a moving scene each triangle's box is the union of its boxes at shutter
// open and close, which holds it all the time in between since its vertices
// move in straight lines; a ray meets the triangle as it is at ray.time.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "util/bounds.h"
#include "bvh/bvh.h"
#include "util/ray.h"
#include "geometry/scene.h"

namespace rt {

// What one traversal did, for the debugger and the BVH-cost output.
struct TraversalStats {
    uint32_t nodes_visited = 0;     // nodes whose boxes were tested
    uint32_t triangles_tested = 0;
};

struct TraversalRecord : TraversalStats {
    std::vector<uint32_t> visited_nodes;  // in visiting order
};

struct AccelStats {
    size_t triangles = 0;
    size_t nodes = 0;
    size_t leaves = 0;
    uint32_t depth = 0;     // levels below the root
    double build_ms = 0.0;
    double sah_cost = 0.0;
};

class Accelerator {
  public:
    // Builds the BVH on `threads` threads (0: all cores). The scene must outlive this.
    explicit Accelerator(const Scene& scene, unsigned threads = 0);

    // Closest hit with 0 < t < ray.t_max, at ray.time. The overloads taking stats or a
    // record (here and below) add this traversal to what they already hold.
    bool intersect(const Ray& ray, Hit& hit) const;
    bool intersect(const Ray& ray, Hit& hit, TraversalStats& stats) const;
    bool intersect(const Ray& ray, Hit& hit, TraversalRecord& record) const;

    // How much light passes along the ray for 0 < t < ray.t_max: 0 at the
    // first opaque hit (where the traversal stops), 1 with no hit, and the
    // product of (1 - alpha) over BLEND surfaces in between. MASK holes and
    // fully transparent texels are no hits, for these queries as for intersect.
    float visibility(const Ray& ray) const;
    float visibility(const Ray& ray, TraversalStats& stats) const;
    float visibility(const Ray& ray, TraversalRecord& record) const;
    // visibility() == 0.
    bool occluded(const Ray& ray) const { return visibility(ray) == 0.0f; }
    bool occluded(const Ray& ray, TraversalStats& stats) const { return visibility(ray, stats) == 0.0f; }
    bool occluded(const Ray& ray, TraversalRecord& record) const { return visibility(ray, record) == 0.0f; }

    const bvh::Bvh& bvh() const { return bvh_; }
    const AccelStats& stats() const { return stats_; }
    const Scene& scene() const { return scene_; }

    // Boxes of the nodes at one level (0 = root), or of all leaves (level < 0).
    struct LevelBoxes {
        std::vector<uint32_t> nodes;
        std::vector<Bounds3> bounds;
        std::vector<uint32_t> triangles;  // triangles under each node
    };
    LevelBoxes boxes(int level) const;

  private:
    // kMoving: the scene moves; kFiltered: some triangle's material has alpha
    // (MASK or BLEND), and hits on it pass the hit filter. Template flags, so a
    // still, opaque scene's leaves pay nothing for motion or alpha they do not have.
    template <bool kMoving, bool kFiltered, typename Observer>
    bool closest_hit(const Ray& ray, Hit& hit, Observer&& observer) const;
    // Returns whether an opaque hit stopped the ray; scales `visibility` by
    // the BLEND surfaces it passed.
    template <bool kMoving, bool kFiltered, typename Observer>
    bool any_hit(const Ray& ray, float& visibility, Observer&& observer) const;
    template <typename Observer>
    bool closest_hit(const Ray& ray, Hit& hit, Observer&& observer) const;
    template <typename Observer>
    float visibility_of(const Ray& ray, Observer&& observer) const;
    // The vertices of the triangle at leaf position i as they are at `time`.
    std::array<vec3, 3> moving_triangle(uint32_t i, float time) const;

    const Scene& scene_;
    bvh::Bvh bvh_;
    // Triangle vertices in BVH leaf order, so a leaf reads contiguous memory:
    // at shutter open, and at close when the scene moves (else empty).
    std::vector<vec3> ordered_vertices_;  // 3 per triangle
    std::vector<vec3> ordered_vertices_close_;
    // 1 for each triangle, in leaf order, whose material has alpha; empty when none has.
    std::vector<uint8_t> ordered_alpha_;
    AccelStats stats_;
};

}  // namespace rt
