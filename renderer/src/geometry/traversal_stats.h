// What one traversal did, for the debugger and the BVH-cost output.
#pragma once

#include <cstdint>
#include <vector>

namespace rt {

struct TraversalStats {
    uint32_t nodes_visited = 0;     // wide nodes whose child boxes were tested
    uint32_t triangles_tested = 0;  // triangles in the leaf blocks tested
};

struct TraversalRecord : TraversalStats {
    // In visiting order, numbered as bvh::WideBvh numbers its boxes: the wide
    // nodes whose child boxes were tested, and the leaves whose triangles were.
    std::vector<uint32_t> visited_nodes;
    std::vector<uint32_t> visited_leaves;
};

}  // namespace rt
