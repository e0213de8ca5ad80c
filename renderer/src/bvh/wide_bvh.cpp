#include "bvh/wide_bvh.h"

#include <limits>

#include "util/math.h"

namespace rt::bvh {

size_t WideBvh::leaf_count() const {
    size_t leaves = 0;
    for (const WideNode& node : nodes)
        for (const ChildRef& child : node.child) leaves += !child.empty() && child.is_leaf();
    return leaves;
}

namespace {

uint32_t leaf_prims(const WideBvh& bvh, ChildRef leaf) {
    uint32_t prims = 0;
    const size_t first = size_t(leaf.first_block()) * kBlockWidth;
    for (size_t i = first; i < first + size_t(leaf.block_count()) * kBlockWidth; ++i) prims += bvh.prim_ids[i] != kNoPrim;
    return prims;
}

}  // namespace

std::vector<WideBvh::Box> WideBvh::boxes(const std::function<uint32_t(ChildRef)>& leaf_prims_of) const {
    std::vector<Box> out;
    if (nodes.empty()) return out;
    const auto prims_in = [&](ChildRef leaf) { return leaf_prims_of ? leaf_prims_of(leaf) : leaf_prims(*this, leaf); };
    // Children follow their parents, so one backward pass sums the primitives
    // and one forward pass knows every parent's level and box before its children.
    std::vector<uint32_t> node_prims(nodes.size(), 0);
    for (size_t i = nodes.size(); i-- > 0;)
        for (const ChildRef& child : nodes[i].child)
            if (!child.empty()) node_prims[i] += child.is_leaf() ? prims_in(child) : node_prims[child.node()];
    std::vector<uint32_t> node_level(nodes.size(), 0);
    std::vector<Bounds3> node_bounds(nodes.size());
    node_bounds[0] = nodes[0].bounds();
    out.push_back({0, 0, node_bounds[0], node_prims[0], false});
    for (uint32_t i = 0; i < nodes.size(); ++i) {
        for (uint32_t c = 0; c < kWideWidth; ++c) {
            const ChildRef child = nodes[i].child[c];
            if (child.empty()) continue;
            const Bounds3 b = child_bounds(i, c);
            if (child.is_leaf()) {
                out.push_back({leaf_id(child), node_level[i] + 1, b, prims_in(child), true});
            } else {
                node_level[child.node()] = node_level[i] + 1;
                node_bounds[child.node()] = b;
                out.push_back({child.node(), node_level[i] + 1, b, node_prims[child.node()], false});
            }
        }
    }
    return out;
}

double WideBvh::sah_cost(double node_cost, double block_cost) const {
    if (nodes.empty()) return 0.0;
    const double root_area = nodes[0].bounds().surface_area();
    if (root_area <= 0.0) return 0.0;
    double cost = node_cost;  // the root is always entered
    for (const WideNode& node : nodes)
        for (uint32_t c = 0; c < kWideWidth; ++c) {
            const ChildRef child = node.child[c];
            if (child.empty()) continue;
            const double area = node.child_bounds(c).surface_area() / root_area;  // at shutter open
            cost += area * (child.is_leaf() ? block_cost * child.block_count() : node_cost);
        }
    return cost;
}

namespace {

// lower + t * (upper - lower) rounds three times; a vertex interpolated the
// same way, three times too. Both errors stay below gamma_bound(3) times the
// largest magnitude involved, so twice that on each side covers them.
Bounds3 widened(const Bounds3& b, float scale) {
    const vec3 pad = 2.0f * gamma_bound(3) * scale * vec3(1.0f);
    return {b.min - pad, b.max + pad};
}

float magnitude(const Bounds3& a, const Bounds3& b) {
    return glm::max(max_component(glm::max(glm::abs(a.min), glm::abs(a.max))),
                    max_component(glm::max(glm::abs(b.min), glm::abs(b.max))));
}

}  // namespace

void refit_motion(WideBvh& bvh, std::span<const Bounds3> open, std::span<const Bounds3> close,
                  std::span<const uint8_t> moves) {
    bvh.motion.assign(bvh.nodes.size(), WideBoxes{});
    std::vector<Bounds3> node_open(bvh.nodes.size()), node_close(bvh.nodes.size());
    std::vector<uint8_t> node_moves(bvh.nodes.size(), 0);
    // Children follow their parents: a backward pass has every child's boxes ready.
    for (size_t i = bvh.nodes.size(); i-- > 0;) {
        WideNode& node = bvh.nodes[i];
        for (uint32_t c = 0; c < kWideWidth; ++c) {
            const ChildRef child = node.child[c];
            if (child.empty()) {
                // Inverted but finite: the interpolation of infinities would be NaN,
                // which the box test ignores rather than rejects.
                constexpr float kMax = std::numeric_limits<float>::max();
                const Bounds3 never{vec3(kMax), vec3(-kMax)};
                node.set_child(c, child, never);
                for (int axis = 0; axis < 3; ++axis) {
                    bvh.motion[i].lower[axis][c] = 0.0f;
                    bvh.motion[i].upper[axis][c] = 0.0f;
                }
                continue;
            }
            Bounds3 at_open, at_close;
            bool child_moves = false;
            if (child.is_leaf()) {
                const size_t first = size_t(child.first_block()) * kBlockWidth;
                for (size_t k = first; k < first + size_t(child.block_count()) * kBlockWidth; ++k) {
                    if (bvh.prim_ids[k] == kNoPrim) continue;
                    at_open.extend(open[bvh.prim_ids[k]]);
                    at_close.extend(close[bvh.prim_ids[k]]);
                    child_moves = child_moves || moves[bvh.prim_ids[k]] != 0;
                }
            } else {
                at_open = node_open[child.node()];
                at_close = node_close[child.node()];
                child_moves = node_moves[child.node()] != 0;
            }
            node_open[i].extend(at_open);
            node_close[i].extend(at_close);
            node_moves[i] = node_moves[i] || child_moves;
            // Padding a still child by its magnitude made every ray leaving
            // a large still floor enter the floor's leaf again (dragon_2
            // moving tested 32% more triangles than still).
            const float scale = child_moves ? magnitude(at_open, at_close) : 0.0f;
            const Bounds3 o = widened(at_open, scale), k = widened(at_close, scale);
            node.set_child(c, child, o);
            // The difference the box test's interpolation took, rounded as it rounded it.
            for (int axis = 0; axis < 3; ++axis) {
                bvh.motion[i].lower[axis][c] = k.min[axis] - o.min[axis];
                bvh.motion[i].upper[axis][c] = k.max[axis] - o.max[axis];
            }
        }
    }
}

}  // namespace rt::bvh
