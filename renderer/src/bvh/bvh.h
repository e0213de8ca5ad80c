// A bounding volume hierarchy as plain data: the nodes and the primitive
// numbers its leaves point into. Builders (binned_sah_builder.h) make one,
// traversal (traverse.h) reads one; neither knows what the primitives are.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "bvh/node.h"

namespace rt::bvh {

// Deepest tree a builder may make; traversal stacks are sized by it.
inline constexpr uint32_t kMaxDepth = 64;

// Layout: nodes[0] is the root; every child comes after its parent, so one
// forward or backward pass over `nodes` visits parents before or after their
// children. A subtree's leaves cover one contiguous range of prim_ids.
struct Bvh {
    std::vector<Node> nodes;          // empty when there are no primitives
    std::vector<uint32_t> prim_ids;   // primitive numbers in leaf order
    uint32_t depth = 0;               // levels below the root

    bool empty() const { return nodes.empty(); }

    size_t leaf_count() const {
        size_t leaves = 0;
        for (const Node& node : nodes) leaves += node.is_leaf();
        return leaves;
    }

    // Level of each node, 0 for the root.
    std::vector<uint32_t> node_levels() const {
        std::vector<uint32_t> levels(nodes.size(), 0);
        for (size_t i = 0; i < nodes.size(); ++i) {
            if (nodes[i].is_leaf()) continue;
            levels[nodes[i].left_child()] = levels[i] + 1;
            levels[nodes[i].left_child() + 1] = levels[i] + 1;
        }
        return levels;
    }

    // Number of primitives in the leaves under each node.
    std::vector<uint32_t> subtree_prim_counts() const {
        std::vector<uint32_t> counts(nodes.size(), 0);
        for (size_t i = nodes.size(); i-- > 0;) {
            const Node& node = nodes[i];
            counts[i] = node.is_leaf() ? node.prim_count
                                       : counts[node.left_child()] + counts[node.left_child() + 1];
        }
        return counts;
    }

    // Expected cost of a random ray through the tree (surface area heuristic):
    // each node costs `traversal_cost` and each primitive 1, weighted by the
    // chance that a ray hitting the root hits the node's box.
    double sah_cost(double traversal_cost) const {
        if (nodes.empty()) return 0.0;
        const double root_area = nodes[0].bounds().surface_area();
        if (root_area <= 0.0) return 0.0;
        double cost = 0.0;
        for (const Node& node : nodes) {
            const double area = node.bounds().surface_area();
            cost += area * (node.is_leaf() ? double(node.prim_count) : traversal_cost);
        }
        return cost / root_area;
    }
};

}  // namespace rt::bvh
