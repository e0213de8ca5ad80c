#include "bvh/binned_sah_builder.h"

#include <algorithm>
#include <atomic>
#include <thread>
#include <vector>

namespace rt::bvh {
namespace {

// Runs two independent jobs, the first on a helper thread while a spare one
// remains. The builder calls it the same way whatever the thread count, so
// sequential and parallel builds share one code path and one result. A helper
// hands its thread back as soon as its job is done, not when the fork joins:
// the first split of a mesh is often lopsided (the dragon's: 44 ms against
// 820 ms), and a thread kept until the join would idle through the rest.
class ForkJoinExecutor {
  public:
    explicit ForkJoinExecutor(unsigned threads) : spare_threads_(int(std::max(threads, 1u)) - 1) {}

    template <typename First, typename Second>
    void run(First&& first, Second&& second) {
        if (!take_spare_thread()) {
            first();
            second();
            return;
        }
        std::thread helper([this, &first] {
            first();
            spare_threads_.fetch_add(1, std::memory_order_relaxed);
        });
        second();
        helper.join();
    }

  private:
    bool take_spare_thread() {
        int spare = spare_threads_.load(std::memory_order_relaxed);
        while (spare > 0)
            if (spare_threads_.compare_exchange_weak(spare, spare - 1, std::memory_order_relaxed))
                return true;
        return false;
    }

    std::atomic<int> spare_threads_;
};

constexpr uint32_t kMaxBins = 32;
// Below this many primitives a subtree is not worth a thread.
constexpr uint32_t kMinParallelPrims = 1024;

struct Range {
    uint32_t begin;
    uint32_t end;
    uint32_t size() const { return end - begin; }
};

// Maps centroids to bins along each axis of a node's centroid bounds.
struct BinMapping {
    vec3 origin;
    vec3 scale;  // bins per unit length; 0 on axes that cannot be split
    uint32_t bin_count;

    BinMapping(const Bounds3& centroid_bounds, uint32_t bins) : origin(centroid_bounds.min), bin_count(bins) {
        const vec3 extent = centroid_bounds.extent();
        for (int axis = 0; axis < 3; ++axis) {
            const float s = float(bins) / extent[axis];
            scale[axis] = extent[axis] > 0.0f && std::isfinite(s) ? s : 0.0f;
        }
    }

    bool splittable(int axis) const { return scale[axis] > 0.0f; }

    // A NaN centroid lands in bin 0, here and in the partition alike.
    uint32_t bin(vec3 centroid, int axis) const {
        const float position = (centroid[axis] - origin[axis]) * scale[axis];
        return position > 0.0f ? std::min(uint32_t(position), bin_count - 1) : 0;
    }
};

// Trivially constructed: a node resets only the bin_count bins it uses.
struct Bin {
    vec3 min;
    vec3 max;
    uint32_t count;

    void reset() { *this = {vec3(kInfinity), vec3(-kInfinity), 0}; }
    void add(const Bounds3& b) {
        min = glm::min(min, b.min);
        max = glm::max(max, b.max);
        ++count;
    }
    Bounds3 bounds() const { return {min, max}; }
};

struct Split {
    int axis = -1;           // -1: no axis separates the centroids
    uint32_t first_right_bin = 0;
    float cost = kInfinity;  // sum over both sides of box area times primitive count
};

class BinnedSahBuilder {
  public:
    BinnedSahBuilder(std::span<const Bounds3> prim_bounds, std::span<const vec3> centroids,
                     const BuildOptions& options, ForkJoinExecutor& executor)
        : prim_bounds_(prim_bounds), centroids_(centroids), options_(options), executor_(executor) {
        options_.bin_count = std::clamp(options_.bin_count, 2u, kMaxBins);
        options_.max_leaf_size = std::max(options_.max_leaf_size, 1u);
    }

    Bvh run() {
        Bvh bvh;
        const auto count = uint32_t(prim_bounds_.size());
        if (count == 0) return bvh;
        prim_ids_.resize(count);
        for (uint32_t i = 0; i < count; ++i) prim_ids_[i] = i;
        // A binary tree over n primitives has at most 2n - 1 nodes.
        slots_.resize(2 * size_t(count) - 1);
        bvh.depth = build(0, 1, {0, count}, 0);
        bvh.nodes = pack();
        bvh.prim_ids = std::move(prim_ids_);
        return bvh;
    }

  private:
    // Builds the subtree over prim_ids_[range]: its root goes to slots_[root]
    // and its other nodes into the 2 * size - 2 slots from `descendants` on, so
    // where a subtree lands never depends on which thread built what before it.
    // Returns the subtree's height.
    uint32_t build(uint32_t root, uint32_t descendants, Range range, uint32_t depth) {
        Bounds3 bounds;
        Bounds3 centroid_bounds;
        for (uint32_t i = range.begin; i < range.end; ++i) {
            bounds.extend(prim_bounds_[prim_ids_[i]]);
            centroid_bounds.extend(centroids_[prim_ids_[i]]);
        }
        Node& node = slots_[root];
        node.set_bounds(bounds);
        node.first_child_or_first_prim = range.begin;
        node.prim_count = range.size();

        if (range.size() == 1 || depth == kMaxDepth) return 0;
        const BinMapping mapping(centroid_bounds, options_.bin_count);
        const Split split = find_split(range, mapping);
        // Costs in units of this box's area times one primitive test.
        const float leaf_cost = float(range.size()) * bounds.surface_area();
        const float split_cost = options_.traversal_cost * bounds.surface_area() + split.cost;
        if (range.size() <= options_.max_leaf_size && !(split_cost < leaf_cost)) return 0;

        // Without a separating axis all centroids coincide: any halving is as good.
        const uint32_t middle = split.axis >= 0 ? partition(range, mapping, split) : range.begin + range.size() / 2;
        node.first_child_or_first_prim = descendants;
        node.prim_count = 0;

        const Range left{range.begin, middle};
        const Range right{middle, range.end};
        const uint32_t left_descendants = descendants + 2;
        const uint32_t right_descendants = left_descendants + 2 * left.size() - 2;
        uint32_t left_height = 0;
        uint32_t right_height = 0;
        auto build_left = [&] { left_height = build(descendants, left_descendants, left, depth + 1); };
        auto build_right = [&] { right_height = build(descendants + 1, right_descendants, right, depth + 1); };
        if (std::min(left.size(), right.size()) >= kMinParallelPrims) {
            executor_.run(build_left, build_right);
        } else {
            build_left();
            build_right();
        }
        return 1 + std::max(left_height, right_height);
    }

    Split find_split(Range range, const BinMapping& mapping) const {
        const uint32_t bin_count = options_.bin_count;
        Bin bins[3][kMaxBins];
        for (auto& axis_bins : bins)
            for (uint32_t b = 0; b < bin_count; ++b) axis_bins[b].reset();
        for (uint32_t i = range.begin; i < range.end; ++i) {
            const uint32_t id = prim_ids_[i];
            for (int axis = 0; axis < 3; ++axis) bins[axis][mapping.bin(centroids_[id], axis)].add(prim_bounds_[id]);
        }

        Split best;
        for (int axis = 0; axis < 3; ++axis) {
            if (!mapping.splittable(axis)) continue;
            // right_costs[b]: area times count of bins b and up.
            float right_costs[kMaxBins];
            Bounds3 right;
            uint32_t right_count = 0;
            for (uint32_t b = bin_count - 1; b > 0; --b) {
                right.extend(bins[axis][b].bounds());
                right_count += bins[axis][b].count;
                right_costs[b] = right.surface_area() * float(right_count);
            }
            Bounds3 left;
            uint32_t left_count = 0;
            for (uint32_t b = 1; b < bin_count; ++b) {
                left.extend(bins[axis][b - 1].bounds());
                left_count += bins[axis][b - 1].count;
                if (left_count == 0 || left_count == range.size()) continue;
                const float cost = left.surface_area() * float(left_count) + right_costs[b];
                if (cost < best.cost) best = {axis, b, cost};
            }
        }
        return best;
    }

    uint32_t partition(Range range, const BinMapping& mapping, const Split& split) {
        const auto first = prim_ids_.begin() + range.begin;
        const auto middle = std::partition(first, prim_ids_.begin() + range.end, [&](uint32_t id) {
            return mapping.bin(centroids_[id], split.axis) < split.first_right_bin;
        });
        return uint32_t(middle - prim_ids_.begin());
    }

    // Copies the used slots into a dense array in depth-first order, keeping
    // each pair of children adjacent.
    std::vector<Node> pack() const {
        struct Move {
            uint32_t slot;
            uint32_t packed;
        };
        std::vector<Node> nodes{slots_[0]};
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

    std::span<const Bounds3> prim_bounds_;
    std::span<const vec3> centroids_;
    BuildOptions options_;
    ForkJoinExecutor& executor_;
    std::vector<uint32_t> prim_ids_;
    std::vector<Node> slots_;
};

}  // namespace

Bvh build_binned_sah(std::span<const Bounds3> prim_bounds, std::span<const vec3> centroids,
                     const BuildOptions& options) {
    const unsigned threads = options.threads != 0 ? options.threads : std::thread::hardware_concurrency();
    ForkJoinExecutor executor(threads);
    return BinnedSahBuilder(prim_bounds, centroids, options, executor).run();
}

}  // namespace rt::bvh
