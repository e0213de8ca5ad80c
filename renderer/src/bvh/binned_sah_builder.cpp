#include "bvh/binned_sah_builder.h"

#include <algorithm>
#include <memory>
#include <thread>
#include <vector>

#include "bvh/build_refs.h"
#include "bvh/fork_join_executor.h"
#include "bvh/sah_bins.h"
#include "bvh/sah_partition.h"

namespace rt::bvh {
namespace {

using namespace detail;

// Below this many primitives a subtree is not worth a thread.
constexpr uint32_t kMinParallelPrims = 1024;

// What a node's build needs to know of its primitives before looking at them.
struct NodeInput {
    Range range;
    Bounds3 bounds;
    Bounds3 centroid_bounds;
    int buffer;  // which of the two reference arrays holds range
};
template <typename Ref>
class BinnedSahBuilder {
  public:
    BinnedSahBuilder(const BuildOptions& options, ForkJoinExecutor& executor, uint32_t count)
        : options_(options), executor_(executor), count_(count) {
        options_.bin_count = std::clamp(options_.bin_count, 2u, kMaxBins);
        options_.max_leaf_size = std::max(options_.max_leaf_size, 1u);
        options_.leaf_block_size = std::max(options_.leaf_block_size, 1u);
        refs_[0].reset(new Ref[count]);
    }

    Ref* refs() { return refs_[0].get(); }

    // Builds the tree over refs() as filled in by the caller, whose bounds
    // and centroid bounds are given.
    Bvh run(const Bounds3& bounds, const Bounds3& centroid_bounds) {
        Bvh bvh;
        if (count_ >= kBlockedNodeSize) refs_[1].reset(new Ref[count_]);
        prim_ids_.resize(count_);
        // A binary tree over n primitives has at most 2n - 1 nodes; left
        // uninitialised, as most slots stay unused.
        slots_.reset(new Node[2 * size_t(count_) - 1]);
        ScratchBins scratch;
        uint32_t next_slot = 1;
        bvh.depth = build(0, next_slot, {{0, count_}, bounds, centroid_bounds, 0}, 0, scratch);
        bvh.nodes = pack();
        bvh.prim_ids = std::move(prim_ids_);
        return bvh;
    }

  private:
    // SAH cost of `count` primitives in a box of unit area.
    float prim_cost(uint32_t count) const {
        const uint32_t block = options_.leaf_block_size;
        const uint32_t blocks = block == 1 ? count : (count + block - 1) / block;
        return float(blocks) * options_.block_cost;
    }

    // Builds the subtree over the node's range: its root goes to slots_[root]
    // and its other nodes into the 2 * size - 2 slots from `next_slot` on, which
    // it advances past those it used. Children take the next two slots, and the
    // left subtree's nodes come before the right one's, except where the two
    // subtrees may be built at once: there each takes a range of slots fixed
    // by its primitive count, and next_slot moves past both. Where a subtree
    // lands never depends on which thread built what before it. Returns the
    // subtree's height. `scratch` is reset, and left so.
    uint32_t build(uint32_t root, uint32_t& next_slot, const NodeInput& in, uint32_t depth, ScratchBins& scratch) {
        const Range range = in.range;
        Node& node = slots_[root];
        node.set_bounds(in.bounds);
        node.first_child_or_first_prim = range.begin;
        node.prim_count = range.size();
        if (range.size() == 1 || depth == kMaxDepth) return make_leaf(in);
        // Costs in units of this box's area times one primitive (block) test.
        const float area = in.bounds.surface_area();
        const float leaf_cost = prim_cost(range.size()) * area;
        if (range.size() <= options_.max_leaf_size && no_split_beats(in, area, leaf_cost)) return make_leaf(in);

        const BinMapping mapping(in.centroid_bounds, options_.bin_count);
        const bool blocked = range.size() >= kBlockedNodeSize;
        std::vector<BinSet> block_bins;
        BinSet& bins = scratch.bins;
        uint32_t occupied[3];
        Ref* const refs = refs_[in.buffer].get();
        if (blocked) {
            const uint32_t block_count = (range.size() + kBlockSize - 1) / kBlockSize;
            block_bins.resize(block_count);
            executor_.parallel_for(block_count, [&](uint32_t block) {
                const uint32_t begin = range.begin + block * kBlockSize;
                const uint32_t end = std::min(range.end, begin + kBlockSize);
                uint32_t block_occupied[3];
                block_bins[block].reset();
                block_bins[block].add(refs + begin, end - begin, mapping, block_occupied);
            });
            for (const BinSet& block : block_bins) bins.merge(block, options_.bin_count);
        } else {
            bins.add(refs + range.begin, range.size(), mapping, occupied);
        }
        if (blocked)
            for (int axis = 0; axis < 3; ++axis) occupied[axis] = bins.occupied(axis);
        const Split split = find_split(bins, mapping, occupied);

        const float split_cost = options_.traversal_cost * area + split.cost;
        if (range.size() <= options_.max_leaf_size && !(split_cost < leaf_cost)) {
            bins.clear(occupied);
            return make_leaf(in);
        }

        NodeInput left{{range.begin, 0}, {}, {}, in.buffer};
        NodeInput right{{0, range.end}, {}, {}, in.buffer};
        if (split.axis >= 0) {
            const uint32_t axis_bins = occupied[split.axis];
            const Box4 left_box = bins.box(split.axis, axis_bins, 0, split.first_right_bin);
            const Box4 right_box = bins.box(split.axis, axis_bins, split.first_right_bin, options_.bin_count);
            left.bounds = left_box.bounds();
            right.bounds = right_box.bounds();
            bins.clear(occupied);
            Box4 left_centroids, right_centroids;
            uint32_t middle;
            if (blocked) {
                middle = partition_blocked(refs_[in.buffer].get(), refs_[1 - in.buffer].get(), range, mapping, split,
                                           block_bins, executor_, left_centroids, right_centroids);
                left.buffer = right.buffer = 1 - in.buffer;
            } else {
                middle = partition_in_place(refs, range, mapping, split, left_centroids, right_centroids);
            }
            left.range.end = right.range.begin = middle;
            left.centroid_bounds = left_centroids.bounds();
            right.centroid_bounds = right_centroids.bounds();
        } else {
            // Without a separating axis all centroids coincide: any halving is as good.
            bins.clear(occupied);
            const uint32_t middle = range.begin + range.size() / 2;
            left.range.end = right.range.begin = middle;
            measure(refs, left);
            measure(refs, right);
        }
        const uint32_t children = next_slot;
        node.first_child_or_first_prim = children;
        node.prim_count = 0;
        next_slot += 2;

        uint32_t left_height = 0;
        uint32_t right_height = 0;
        if (std::min(left.range.size(), right.range.size()) >= kMinParallelPrims) {
            const uint32_t end_slot = children + 2 * range.size() - 2;
            // The left subtree may be built on another thread, with bins of its own.
            auto build_left = [&] {
                ScratchBins left_scratch;
                uint32_t left_next = children + 2;
                left_height = build(children, left_next, left, depth + 1, left_scratch);
            };
            auto build_right = [&] {
                uint32_t right_next = children + 2 + 2 * left.range.size() - 2;
                right_height = build(children + 1, right_next, right, depth + 1, scratch);
            };
            executor_.run(build_left, build_right);
            next_slot = end_slot;
        } else {
            left_height = build(children, next_slot, left, depth + 1, scratch);
            right_height = build(children + 1, next_slot, right, depth + 1, scratch);
        }
        return 1 + std::max(left_height, right_height);
    }

    // Whether no split of a small node can cost less than its leaf, by a
    // bound that takes no binning: a split costs the traversal plus, for each
    // child, its area (at least that of each of its primitives) times what its
    // primitives cost (at least one block). Most small nodes of a mesh end
    // here. The margin, far above the rounding of either cost, keeps the
    // shortcut from ever taking a leaf the full evaluation would split.
    bool no_split_beats(const NodeInput& in, float area, float leaf_cost) const {
        if (!(options_.traversal_cost >= 0.0f && options_.block_cost >= 0.0f)) return false;
        const float bar = leaf_cost * 1.001f;
        float bound = options_.traversal_cost * area;
        if (bound >= bar) return true;
        const Ref* refs = refs_[in.buffer].get();
        float sum = 0.0f;  // of the primitives' areas
        float largest = 0.0f, smallest = kInfinity;  // NaN areas make sum NaN, and the bound fail
        for (uint32_t i = in.range.begin; i < in.range.end; ++i) {
            Box4 box;
            box.extend(refs[i].lower4(), refs[i].upper4());
            const float a = box.surface_area();
            sum += a;
            largest = std::max(largest, a);
            smallest = std::min(smallest, a);
        }
        // With one primitive a block, children cost their area times their
        // primitive count, at least the sum of their primitives' areas; else
        // at least a block's cost for the largest primitive's side and for
        // the other.
        bound += options_.block_cost * (options_.leaf_block_size == 1 ? sum : largest + smallest);
        return sum >= 0.0f && bound >= bar;
    }

    uint32_t make_leaf(const NodeInput& in) {
        const Ref* refs = refs_[in.buffer].get();
        for (uint32_t i = in.range.begin; i < in.range.end; ++i) prim_ids_[i] = refs[i].id;
        return 0;
    }

    // Sets the bounds and centroid bounds of in.range.
    static void measure(const Ref* refs, NodeInput& in) {
        Box4 box, centroids;
        for (uint32_t i = in.range.begin; i < in.range.end; ++i) {
            box.extend(refs[i].lower4(), refs[i].upper4());
            centroids.extend(refs[i].centroid4());
        }
        in.bounds = box.bounds();
        in.centroid_bounds = centroids.bounds();
    }

    // The cheapest split between bins on any axis, the first one on the
    // lowest axis among equals. Only bins that hold primitives are visited:
    // all boundaries between two consecutive occupied bins split alike, and the
    // first of them, just above the lower bin, is the one taken.
    Split find_split(const BinSet& bins, const BinMapping& mapping, const uint32_t (&occupied_bins)[3]) const {
        Split best;
        for (int axis = 0; axis < 3; ++axis) {
            if (!mapping.splittable(axis)) continue;
            const uint32_t occupied = occupied_bins[axis];
            if ((occupied & (occupied - 1)) == 0) continue;  // fewer than two
            // right_costs[b]: area times cost of bins b and up, at occupied bins
            // b but the lowest.
            float right_costs[kMaxBins];
            Box4 right;
            uint32_t right_count = 0;
            for (uint32_t rest = occupied; (rest & (rest - 1)) != 0;) {
                const auto b = uint32_t(31 - std::countl_zero(rest));
                rest &= ~(1u << b);
                right.extend(bins.bin[axis][b].lower, bins.bin[axis][b].upper);
                right_count += bins.count[axis][b];
                right_costs[b] = right.surface_area() * prim_cost(right_count);
            }
            Box4 left;
            uint32_t left_count = 0;
            for (uint32_t rest = occupied;;) {
                const auto b = uint32_t(std::countr_zero(rest));
                rest &= rest - 1;
                if (rest == 0) break;  // b is the last occupied bin
                left.extend(bins.bin[axis][b].lower, bins.bin[axis][b].upper);
                left_count += bins.count[axis][b];
                const float cost = left.surface_area() * prim_cost(left_count) +
                                   right_costs[std::countr_zero(rest)];
                if (cost < best.cost) best = {axis, b + 1, cost};
            }
        }
        return best;
    }

    // Copies the used slots into a dense array in depth-first order, keeping
    // each pair of children adjacent.
    std::vector<Node> pack() const {
        struct Move {
            uint32_t slot;
            uint32_t packed;
        };
        std::vector<Node> nodes;
        nodes.reserve(2 * size_t(count_) - 1);  // only the pages written are mapped
        nodes.push_back(slots_[0]);
        std::vector<Move> stack{{0, 0}};
        while (!stack.empty()) {
            const Move move = stack.back();
            stack.pop_back();
            if (slots_[move.slot].is_leaf()) continue;
            const uint32_t left_slot = slots_[move.slot].left_child();
            const auto left_packed = uint32_t(nodes.size());
            nodes[move.packed].first_child_or_first_prim = left_packed;
            nodes.push_back(slots_[left_slot]);
            nodes.push_back(slots_[left_slot + 1]);
            stack.push_back({left_slot + 1, left_packed + 1});
            stack.push_back({left_slot, left_packed});
        }
        return nodes;
    }

    BuildOptions options_;
    ForkJoinExecutor& executor_;
    uint32_t count_;
    // The primitives in the order the build has put them so far; nodes of at
    // least kBlockedNodeSize primitives move theirs from one array to the other.
    std::unique_ptr<Ref[]> refs_[2];
    std::vector<uint32_t> prim_ids_;
    std::unique_ptr<Node[]> slots_;
};

template <typename Ref>
struct Prepared {
    std::unique_ptr<BinnedSahBuilder<Ref>> builder;
    Bounds3 bounds;
    Bounds3 centroid_bounds;
    bool centered = true;
};

template <typename Ref>
Prepared<Ref> prepare(std::span<const Bounds3> prim_bounds, std::span<const vec3> centroids,
                      const BuildOptions& options, ForkJoinExecutor& executor) {
    const auto count = uint32_t(prim_bounds.size());
    Prepared<Ref> prepared;
    prepared.builder = std::make_unique<BinnedSahBuilder<Ref>>(options, executor, count);
    const uint32_t block_count = (count + kBlockSize - 1) / kBlockSize;
    struct BlockOut {
        Box4 bounds;
        Box4 centroid_bounds;
        bool centered;
    };
    std::vector<BlockOut> out(block_count);
    Ref* refs = prepared.builder->refs();
    executor.parallel_for(block_count, [&](uint32_t block) {
        const uint32_t begin = block * kBlockSize;
        const uint32_t end = std::min(count, begin + kBlockSize);
        out[block].centered =
            fill_refs(refs, prim_bounds, centroids, begin, end, out[block].bounds, out[block].centroid_bounds);
    });
    Box4 bounds, centroid_bounds;
    for (const BlockOut& o : out) {
        bounds.extend(o.bounds);
        centroid_bounds.extend(o.centroid_bounds);
        prepared.centered = prepared.centered && o.centered;
    }
    prepared.bounds = bounds.bounds();
    prepared.centroid_bounds = centroid_bounds.bounds();
    return prepared;
}

}  // namespace

Bvh build_binned_sah(std::span<const Bounds3> prim_bounds, std::span<const vec3> centroids,
                     const BuildOptions& options) {
    if (prim_bounds.empty()) return {};
    const unsigned threads = options.threads != 0 ? options.threads : std::thread::hardware_concurrency();
    ForkJoinExecutor executor(threads);
    {
        Prepared<CenteredRef> prepared = prepare<CenteredRef>(prim_bounds, centroids, options, executor);
        if (prepared.centered) return prepared.builder->run(prepared.bounds, prepared.centroid_bounds);
    }
    Prepared<StoredCentroidRef> prepared = prepare<StoredCentroidRef>(prim_bounds, centroids, options, executor);
    return prepared.builder->run(prepared.bounds, prepared.centroid_bounds);
}

}  // namespace rt::bvh
