#include "bvh/wide_collapse.h"

#include <algorithm>
#include <stdexcept>
#include <vector>

namespace rt::bvh {
namespace {

class Collapser {
  public:
    Collapser(const Bvh& binary, std::span<const Bounds3> prim_bounds, uint32_t merge_limit)
        : binary_(binary), prim_bounds_(prim_bounds), merge_limit_(merge_limit) {}

    WideBvh run() {
        if (binary_.empty()) return std::move(wide_);
        subtree_prims_ = binary_.subtree_prim_counts();
        subtree_first_.resize(binary_.nodes.size());
        for (size_t i = binary_.nodes.size(); i-- > 0;) {
            const Node& node = binary_.nodes[i];
            subtree_first_[i] = node.is_leaf() ? node.first_prim() : subtree_first_[node.left_child()];
        }
        wide_.nodes.reserve(binary_.nodes.size() / 4 + 1);
        wide_.prim_ids.reserve(binary_.prim_ids.size() + binary_.prim_ids.size() / 2);
        wide_.nodes.emplace_back();
        const Node& root = binary_.nodes[0];
        if (root.is_leaf()) {
            place_leaf(0, 0, root.first_prim(), root.prim_count, root.bounds(), 1);
        } else {
            fill(0, 0, 1);
        }
        return std::move(wide_);
    }

  private:
    // Makes wide node `slot` hold the children of binary inner node `node`,
    // opened up to kWideWidth of them. `level` is the slot's children's level.
    void fill(uint32_t slot, uint32_t node, uint32_t level) {
        uint32_t children[kWideWidth];
        uint32_t count = 2;
        children[0] = binary_.nodes[node].left_child();
        children[1] = children[0] + 1;
        while (count < kWideWidth) {
            // The inner child with the largest box: opening it removes the most
            // expected box tests.
            int widest = -1;
            float widest_area = -1.0f;
            for (uint32_t c = 0; c < count; ++c) {
                const Node& child = binary_.nodes[children[c]];
                const float area = child.bounds().surface_area();
                if (!leaf_like(children[c]) && area > widest_area) widest = int(c), widest_area = area;
            }
            if (widest < 0) break;
            const uint32_t opened = children[widest];
            children[widest] = binary_.nodes[opened].left_child();
            children[count++] = binary_.nodes[opened].left_child() + 1;
        }
        // A node's inner children are allocated side by side before any of
        // them is filled: the nodes a ray visits after one another then tend
        // to share pages and cache lines.
        uint32_t indices[kWideWidth];
        for (uint32_t c = 0; c < count; ++c) {
            const Node& child = binary_.nodes[children[c]];
            if (leaf_like(children[c])) {
                place_leaf(slot, c, subtree_first_[children[c]], subtree_prims_[children[c]], child.bounds(), level);
            } else {
                indices[c] = new_node(level);
                wide_.nodes[slot].set_child(c, ChildRef::inner(indices[c]), child.bounds());
            }
        }
        for (uint32_t c = 0; c < count; ++c)
            if (!leaf_like(children[c])) fill(indices[c], children[c], level + 1);
    }

    // A leaf, or a subtree small enough to be tested as one: its primitives
    // are contiguous, and one block test costs about what the box test of a
    // node of its few leaves would, before those leaves' own block tests.
    bool leaf_like(uint32_t node) const {
        return binary_.nodes[node].is_leaf() || subtree_prims_[node] <= merge_limit_;
    }

    // Puts binary_.prim_ids[first, first + count) under child c of wide node `slot`.
    void place_leaf(uint32_t slot, uint32_t c, uint32_t first, uint32_t count, const Bounds3& bounds, uint32_t level) {
        constexpr uint32_t kLeafPrims = kBlockWidth * kMaxLeafBlocks;
        if (count <= kLeafPrims) {
            wide_.nodes[slot].set_child(c, make_leaf(first, count), bounds);
            wide_.depth = std::max(wide_.depth, level);
            return;
        }
        // Primitives no split could separate: spread them over a subtree of
        // full leaves, eight to a node, in their binary order.
        const uint32_t index = new_node(level);
        wide_.nodes[slot].set_child(c, ChildRef::inner(index), bounds);
        uint32_t per_child = kLeafPrims;
        while (uint64_t(per_child) * kWideWidth < count) per_child *= kWideWidth;
        for (uint32_t k = 0, begin = first; begin < first + count; ++k, begin += per_child) {
            const uint32_t n = std::min(per_child, first + count - begin);
            Bounds3 b;
            for (uint32_t i = begin; i < begin + n; ++i) b.extend(prim_bounds_[binary_.prim_ids[i]]);
            place_leaf(index, k, begin, n, b, level + 1);
        }
    }

    ChildRef make_leaf(uint32_t first, uint32_t count) {
        const size_t block = wide_.prim_ids.size() / kBlockWidth;
        if (block + kMaxLeafBlocks > ChildRef::kMaxBlocks)
            throw std::length_error("BVH: too many primitives for the wide BVH's leaf references");
        for (uint32_t i = first; i < first + count; ++i) wide_.prim_ids.push_back(binary_.prim_ids[i]);
        while (wide_.prim_ids.size() % kBlockWidth != 0) wide_.prim_ids.push_back(kNoPrim);
        return ChildRef::leaf(uint32_t(block), (count + kBlockWidth - 1) / kBlockWidth);
    }

    uint32_t new_node(uint32_t level) {
        if (level >= kMaxWideDepth) throw std::length_error("BVH: the wide tree is too deep");
        wide_.nodes.emplace_back();
        wide_.depth = std::max(wide_.depth, level);
        return uint32_t(wide_.nodes.size() - 1);
    }

    const Bvh& binary_;
    std::span<const Bounds3> prim_bounds_;
    uint32_t merge_limit_;
    std::vector<uint32_t> subtree_prims_;
    std::vector<uint32_t> subtree_first_;
    WideBvh wide_;
};

}  // namespace

WideBvh collapse_to_wide(const Bvh& binary, std::span<const Bounds3> prim_bounds, uint32_t merge_limit) {
    return Collapser(binary, prim_bounds, merge_limit).run();
}

}  // namespace rt::bvh
