// Front-to-back BVH traversal for closest-hit and any-hit queries. What the
// leaves hold is the caller's business: it passes the leaf test.
#pragma once

#include <cassert>
#include <cstdint>

#include "bvh/box_test.h"
#include "bvh/bvh.h"
#include "util/ray.h"

namespace rt::bvh {

enum class Query { closest_hit, any_hit };

// How far past the nearest hit so far a closest-hit query still enters boxes
// and tests triangles: far enough that a triangle at the same distance, or a
// rounding error nearer, in a box whose entry the box test rounds just past
// it, is still met. The answer, the nearest hit with ties going to the lower
// triangle number, then does not depend on the order of the traversal, so
// the packet and the single-ray queries agree.
inline constexpr float kTieReach = 0x1p-20f;  // the packet kernels' lanes use it too
inline float tie_reach(float t) { return t + t * kTieReach; }

// Sees every node whose box a traversal tests. The default one compiles away,
// so the plain queries pay nothing for the debugger's.
struct NoObserver {
    void visit_node(uint32_t) {}
};

inline void prefetch_children(const Bvh& bvh, const Node& node) {
    if (node.is_leaf()) return;
    // Pairs start at odd indices, so a pair spans two cache lines.
    __builtin_prefetch(&bvh.nodes[node.left_child()]);
    __builtin_prefetch(&bvh.nodes[node.left_child() + 1]);
}

// leaf_test(first, count, t_max) tests the primitives prim_ids[first, first +
// count) for hits with t < t_max; for closest-hit queries it lowers t_max to the
// nearest hit it finds. It returns whether it found one. Returns whether any
// leaf test did.
template <Query query, typename LeafTest, typename Observer = NoObserver>
bool traverse(const Bvh& bvh, const Ray& ray, LeafTest&& leaf_test, Observer&& observer = {}) {
    if (bvh.empty()) return false;
    const BoxRay box_ray(ray);
    float t_max = ray.t_max;
    observer.visit_node(0);
    if (!(entry_distance(bvh.nodes[0], box_ray, t_max) < t_max)) return false;

    // Nodes put aside for later, with the distance at which the ray enters them.
    struct Pending {
        uint32_t node;
        float t_entry;
    };
    Pending stack[kMaxDepth];
    uint32_t stack_size = 0;
    uint32_t current = 0;
    bool found = false;
    for (;;) {
        const Node& node = bvh.nodes[current];
        if (!node.is_leaf()) {
            const uint32_t left = node.left_child();
            // The next step reads the children of one of these two nodes: fetch
            // them while this pair is tested (a third faster on the full dragon).
            prefetch_children(bvh, bvh.nodes[left]);
            prefetch_children(bvh, bvh.nodes[left + 1]);
            const ChildEntries entries = child_entry_distances(&bvh.nodes[left], box_ray, t_max);
            observer.visit_node(left);
            observer.visit_node(left + 1);
            const bool hit_left = entries.hits & kHitLeft;
            const bool hit_right = entries.hits & kHitRight;
            if (hit_left || hit_right) {
                // Descend into the nearer child hit; the other one is written to
                // the stack either way but kept only when it was hit too. Branches
                // rather than arithmetic: for coherent rays they predict well, and
                // a predicted branch starts the next node's loads before this test
                // completes (branch-free selection measured a third slower).
                const bool right_first = !hit_left || (hit_right && entries.right < entries.left);
                assert(stack_size < kMaxDepth);
                stack[stack_size] = right_first ? Pending{left, entries.left} : Pending{left + 1, entries.right};
                stack_size += hit_left && hit_right;
                current = left + right_first;
                continue;
            }
        } else if (leaf_test(node.first_prim(), node.prim_count, t_max)) {
            found = true;
            if constexpr (query == Query::any_hit) return true;
        }
        // Resume with the latest node put aside that the ray still enters
        // before its closest hit so far.
        for (;;) {
            if (stack_size == 0) return found;
            const Pending& next = stack[--stack_size];
            if (next.t_entry < t_max) {
                current = next.node;
                break;
            }
        }
    }
}

}  // namespace rt::bvh
