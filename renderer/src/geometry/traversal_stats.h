// What one traversal did, for the debugger and the BVH-cost output.
#pragma once

#include <cstdint>
#include <vector>

namespace rt {

struct TraversalStats {
    uint32_t nodes_visited = 0;     // wide nodes whose child boxes were tested
    uint32_t triangles_tested = 0;  // triangles in the leaf blocks tested
};

// The nodes and leaves visited in one tree a top-level leaf leads to, in that
// tree's numbering: an instance's (its mesh's tree), or the world tree's.
struct EnteredTree {
    uint32_t entry = 0;  // an instance number, or AccelScene::kWorldEntry
    std::vector<uint32_t> visited_nodes;
    std::vector<uint32_t> visited_leaves;
};

struct TraversalRecord : TraversalStats {
    // In visiting order, numbered as bvh::WideBvh numbers its boxes: the wide
    // nodes whose child boxes were tested, and the leaves whose triangles were.
    // With instances these are the top-level tree's, and `entered` holds each
    // entry of its leaves that was entered, in entering order.
    std::vector<uint32_t> visited_nodes;
    std::vector<uint32_t> visited_leaves;
    std::vector<EnteredTree> entered;
};

}  // namespace rt
