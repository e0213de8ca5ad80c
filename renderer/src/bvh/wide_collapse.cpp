#include "bvh/wide_collapse.h"

#include <algorithm>
#include <stdexcept>
#include <vector>

#include "util/math.h"

namespace rt::bvh {
namespace {

// A child's box as the tree keeps it: widened by a few ulps of its largest
// side, along every axis it is not flat on. The watertight triangle test
// finds hits up to a rounding error (of the triangle's size, for a ray
// starting near it) beyond the triangle's edges: a ray started just short of
// a cube's edge and aimed at it crosses the face's plane a hair past the edge
// and still hits the face. An exact box, whose side lies on that edge (a leaf
// of the face's two triangles, as the SAH collapse makes them), would cull
// it. Not along a flat axis, where every hit lies in the plane itself: the
// ground quad's box would otherwise take in every shadow ray leaving the
// ground (25% slower shadow rays on the dragons). A parent is at least as
// large as its children and flat only where they are, so it still holds them.
Bounds3 widened(const Bounds3& b) {
    const vec3 extent = b.max - b.min;
    const float pad = 2.0f * gamma_bound(3) * max_component(extent);
    vec3 widening;
    for (int axis = 0; axis < 3; ++axis) widening[axis] = extent[axis] > 0.0f ? pad : 0.0f;
    return {b.min - widening, b.max + widening};
}

class Collapser {
  public:
    Collapser(const Bvh& binary, std::span<const Bounds3> prim_bounds, const CollapseOptions& options)
        : binary_(binary), prim_bounds_(prim_bounds), plan_(binary, options) {}

    WideBvh run() {
        if (binary_.empty()) return std::move(wide_);
        wide_.nodes.reserve(binary_.nodes.size() / 8 + 1);
        wide_.prim_ids.reserve(binary_.prim_ids.size() + binary_.prim_ids.size() / 4);
        wide_.nodes.emplace_back();
        const Node& root = binary_.nodes[0];
        if (root.is_leaf()) {
            place_leaf(0, 0, root.first_prim(), root.prim_count, widened(root.bounds()), 1);
        } else {
            fill(0, 0, 1);
        }
        return std::move(wide_);
    }

  private:
    // Appends the binary nodes that take `slots` child slots for `node`'s subtree.
    void gather(uint32_t node, uint32_t slots, uint32_t* out, uint32_t& count) const {
        while (slots > 1 && plan_.left_slots(node, slots) == 0) --slots;
        if (slots == 1) {
            out[count++] = node;
            return;
        }
        const uint32_t k = plan_.left_slots(node, slots);
        gather(binary_.nodes[node].left_child(), k, out, count);
        gather(binary_.nodes[node].left_child() + 1, slots - k, out, count);
    }

    // Makes wide node `slot` hold binary inner node `node`'s subtree as the
    // plan spreads it over eight slots. `level` is the slot's children's level.
    void fill(uint32_t slot, uint32_t node, uint32_t level) {
        uint32_t children[kWideWidth];
        uint32_t count = 0;
        const uint32_t k = plan_.wide_left_slots(node);
        gather(binary_.nodes[node].left_child(), k, children, count);
        gather(binary_.nodes[node].left_child() + 1, kWideWidth - k, children, count);
        // A node's inner children are allocated side by side before any of
        // them is filled: the nodes a ray visits after one another then tend
        // to share pages and cache lines.
        uint32_t indices[kWideWidth];
        for (uint32_t c = 0; c < count; ++c) {
            const uint32_t child = children[c];
            const Bounds3 bounds = widened(binary_.nodes[child].bounds());
            if (plan_.is_leaf(child)) {
                place_leaf(slot, c, plan_.first_prim(child), plan_.prims(child), bounds, level);
            } else {
                indices[c] = new_node(level);
                wide_.nodes[slot].set_child(c, ChildRef::inner(indices[c]), bounds);
            }
        }
        for (uint32_t c = 0; c < count; ++c)
            if (!plan_.is_leaf(children[c])) fill(indices[c], children[c], level + 1);
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
            place_leaf(index, k, begin, n, widened(b), level + 1);
        }
    }

    ChildRef make_leaf(uint32_t first, uint32_t count) {
        const size_t block = wide_.prim_ids.size() / kBlockWidth;
        if (block + kMaxLeafBlocks > ChildRef::kMaxBlocks)
            throw std::length_error("BVH: too many primitives for the wide BVH's leaf references");
        const uint32_t blocks = (count + kBlockWidth - 1) / kBlockWidth;
        wide_.prim_ids.insert(wide_.prim_ids.end(), binary_.prim_ids.begin() + first,
                              binary_.prim_ids.begin() + first + count);
        wide_.prim_ids.resize((block + blocks) * kBlockWidth, kNoPrim);
        return ChildRef::leaf(uint32_t(block), blocks);
    }

    uint32_t new_node(uint32_t level) {
        if (level >= kMaxWideDepth) throw std::length_error("BVH: the wide tree is too deep");
        wide_.nodes.emplace_back();
        wide_.depth = std::max(wide_.depth, level);
        return uint32_t(wide_.nodes.size() - 1);
    }

    const Bvh& binary_;
    std::span<const Bounds3> prim_bounds_;
    CollapsePlan plan_;
    WideBvh wide_;
};

}  // namespace

WideBvh collapse_to_wide(const Bvh& binary, std::span<const Bounds3> prim_bounds, const CollapseOptions& options) {
    return Collapser(binary, prim_bounds, options).run();
}

}  // namespace rt::bvh
