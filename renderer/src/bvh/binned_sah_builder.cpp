#include "bvh/binned_sah_builder.h"

#include <emmintrin.h>  // SSE2, which every x86-64 CPU has

#include <algorithm>
#include <atomic>
#include <bit>
#include <cstring>
#include <memory>
#include <thread>
#include <type_traits>
#include <vector>

namespace rt::bvh {
namespace {

// Runs two independent jobs, the first on a helper thread while a spare one
// remains, and loops over blocks on as many spare threads as there are. The
// builder calls it the same way whatever the thread count, so sequential and
// parallel builds share one code path and one result. A thread is spare
// whenever it has nothing to do: a helper hands its thread back as soon as its
// job is done, not when the fork joins (the first split of a mesh is often
// lopsided, the dragon's 1 to 20), and a thread waiting at a join lends its
// own until the join completes.
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
        // Whoever comes first runs `first`: when the helper is slow to start
        // (its core busy elsewhere), this thread does not wait for it.
        std::atomic<bool> claimed{false};
        std::thread helper([this, &first, &claimed] {
            if (!claimed.exchange(true, std::memory_order_acq_rel)) first();
            spare_threads_.fetch_add(1, std::memory_order_relaxed);
        });
        second();
        if (!claimed.exchange(true, std::memory_order_acq_rel)) first();
        spare_threads_.fetch_add(1, std::memory_order_relaxed);
        helper.join();
        spare_threads_.fetch_sub(1, std::memory_order_relaxed);
    }

    // Calls f(i) for every i in [0, count), each exactly once, in any order
    // and on any thread.
    template <typename F>
    void parallel_for(uint32_t count, F&& f) {
        std::atomic<uint32_t> next{0};
        auto work = [&] {
            for (uint32_t i; (i = next.fetch_add(1, std::memory_order_relaxed)) < count;) f(i);
        };
        std::thread helpers[kMaxHelpers];
        uint32_t helper_count = 0;
        while (helper_count + 1 < count && helper_count < kMaxHelpers && take_spare_thread()) {
            helpers[helper_count++] = std::thread([this, &work] {
                work();
                spare_threads_.fetch_add(1, std::memory_order_relaxed);
            });
        }
        work();
        for (uint32_t h = 0; h < helper_count; ++h) helpers[h].join();
    }

  private:
    static constexpr uint32_t kMaxHelpers = 63;

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
// Nodes with at least this many primitives are binned in blocks of kBlockSize
// (on as many threads as are spare) and partitioned stably into the other
// buffer; smaller ones are binned in one pass and partitioned in place. Both
// choices depend on the node's size only, which keeps the tree independent of
// the thread count.
constexpr uint32_t kBlockedNodeSize = 1u << 15;
constexpr uint32_t kBlockSize = 1u << 13;

// The builder's copy of a primitive: its box, in SSE-loadable halves, and its
// number; the builder reorders these rather than numbers into the caller's
// arrays, so that binning and partitioning stream through memory. When every
// centroid is its box's centre, as the accelerator's are, 32 bytes hold all
// (CenteredRef); else the centroid comes along (StoredCentroidRef).
struct alignas(32) CenteredRef {
    float lower[3];
    uint32_t id;
    float upper[3];
    uint32_t unused;

    __m128 lower4() const { return _mm_load_ps(lower); }
    __m128 upper4() const { return _mm_load_ps(upper); }
    // As Bounds3::center computes it, so that the bins are the same. Lane 3
    // is cleared first: as a float the id is denormal, whose arithmetic takes
    // a slow microcode path (the build ran 2.5 times slower).
    __m128 centroid4() const {
        const __m128 xyz = _mm_castsi128_ps(_mm_setr_epi32(-1, -1, -1, 0));
        return _mm_mul_ps(_mm_add_ps(_mm_and_ps(lower4(), xyz), upper4()), _mm_set1_ps(0.5f));
    }
    float centroid(int axis) const { return 0.5f * (lower[axis] + upper[axis]); }
};

struct alignas(16) StoredCentroidRef {
    float lower[3];
    uint32_t id;
    float upper[3];
    uint32_t unused;
    float center[4];

    __m128 lower4() const { return _mm_load_ps(lower); }
    __m128 upper4() const { return _mm_load_ps(upper); }
    __m128 centroid4() const { return _mm_load_ps(center); }
    float centroid(int axis) const { return center[axis]; }
};

static_assert(sizeof(CenteredRef) == 32 && sizeof(StoredCentroidRef) == 48);

// An axis-aligned box in SSE registers; lane 3 means nothing. Min and max
// take the new value first, as glm::min and glm::max do, so that a NaN
// coordinate never enters a box, here or in Bounds3::extend.
struct Box4 {
    __m128 lower = _mm_set1_ps(kInfinity);
    __m128 upper = _mm_set1_ps(-kInfinity);

    void extend(__m128 point) {
        lower = _mm_min_ps(point, lower);
        upper = _mm_max_ps(point, upper);
    }
    void extend(__m128 other_lower, __m128 other_upper) {
        lower = _mm_min_ps(other_lower, lower);
        upper = _mm_max_ps(other_upper, upper);
    }
    void extend(const Box4& other) { extend(other.lower, other.upper); }

    Bounds3 bounds() const {
        alignas(16) float l[4], u[4];
        _mm_store_ps(l, lower);
        _mm_store_ps(u, upper);
        return {vec3(l[0], l[1], l[2]), vec3(u[0], u[1], u[2])};
    }

    // Bounds3::surface_area, the same operations in the same order. Lane 3
    // of `lower` is cleared first: it may hold primitive numbers (see
    // CenteredRef).
    float surface_area() const {
        if (_mm_movemask_ps(_mm_cmpgt_ps(lower, upper)) & 0x7) return 0.0f;
        const __m128 xyz = _mm_castsi128_ps(_mm_setr_epi32(-1, -1, -1, 0));
        const __m128 e = _mm_sub_ps(upper, _mm_and_ps(lower, xyz));  // upper's lane 3 is 0
        // x y, y z, z x
        const __m128 products = _mm_mul_ps(e, _mm_shuffle_ps(e, e, _MM_SHUFFLE(3, 0, 2, 1)));
        const __m128 sum = _mm_add_ss(_mm_add_ss(products, _mm_shuffle_ps(products, products, 1)),
                                      _mm_shuffle_ps(products, products, 2));
        return 2.0f * _mm_cvtss_f32(sum);
    }
};

// Maps centroids to bins along each axis of a node's centroid bounds.
struct BinMapping {
    vec3 origin;
    vec3 scale;  // bins per unit length; 0 on axes that cannot be split
    uint32_t bin_count;
    __m128 origin4;
    __m128 scale4;
    __m128 last_bin4;

    BinMapping(const Bounds3& centroid_bounds, uint32_t bins) : origin(centroid_bounds.min), bin_count(bins) {
        const vec3 extent = centroid_bounds.extent();
        for (int axis = 0; axis < 3; ++axis) {
            const float s = float(bins) / extent[axis];
            scale[axis] = extent[axis] > 0.0f && std::isfinite(s) ? s : 0.0f;
        }
        origin4 = _mm_setr_ps(origin.x, origin.y, origin.z, 0.0f);
        scale4 = _mm_setr_ps(scale.x, scale.y, scale.z, 0.0f);
        last_bin4 = _mm_set1_ps(float(bins - 1));
    }

    bool splittable(int axis) const { return scale[axis] > 0.0f; }

    // The bin of a centroid along each axis: (centroid - origin) * scale,
    // rounded down into [0, bin_count). A NaN centroid lands in bin 0.
    __m128i bins(__m128 centroid) const {
        __m128 position = _mm_mul_ps(_mm_sub_ps(centroid, origin4), scale4);
        position = _mm_max_ps(position, _mm_setzero_ps());  // NaN -> 0
        return _mm_cvttps_epi32(_mm_min_ps(position, last_bin4));
    }

    // Whether a centroid's bin along `axis` is below `bin`: the same position
    // as bins() computes, compared before rounding (for an integer `bin`
    // floor(p) < bin exactly when p < bin); NaN is below.
    bool below(float centroid, int axis, float bin) const {
        const float position = (centroid - origin[axis]) * scale[axis];
        return !(position >= bin);
    }
};

// Bins of one node along all three axes. Trivially constructed; reset once,
// then cleared after each use, which touches only the bins that were used.
struct BinSet {
    struct Bin {
        __m128 lower;
        __m128 upper;
    };
    Bin bin[3][kMaxBins];
    uint32_t count[3][kMaxBins];

    void reset() {
        const __m128 inf = _mm_set1_ps(kInfinity), minus_inf = _mm_set1_ps(-kInfinity);
        for (int axis = 0; axis < 3; ++axis) {
            for (uint32_t b = 0; b < kMaxBins; ++b) {
                bin[axis][b].lower = inf;
                bin[axis][b].upper = minus_inf;
            }
            std::memset(count[axis], 0, sizeof(count[axis]));
        }
    }

    void merge(const BinSet& other, uint32_t bin_count) {
        for (int axis = 0; axis < 3; ++axis) {
            for (uint32_t b = 0; b < bin_count; ++b) {
                bin[axis][b].lower = _mm_min_ps(other.bin[axis][b].lower, bin[axis][b].lower);
                bin[axis][b].upper = _mm_max_ps(other.bin[axis][b].upper, bin[axis][b].upper);
                count[axis][b] += other.count[axis][b];
            }
        }
    }

    template <typename Ref>
    void add(const Ref& ref, const BinMapping& mapping, uint32_t* occupied = nullptr) {
        const __m128 lo = ref.lower4();
        const __m128 hi = ref.upper4();
        const __m128i b = mapping.bins(ref.centroid4());
        const auto bx = uint32_t(_mm_cvtsi128_si32(b));
        const auto by = uint32_t(_mm_cvtsi128_si32(_mm_shuffle_epi32(b, 0x55)));
        const auto bz = uint32_t(_mm_cvtsi128_si32(_mm_shuffle_epi32(b, 0xaa)));
        bin[0][bx].lower = _mm_min_ps(lo, bin[0][bx].lower);
        bin[0][bx].upper = _mm_max_ps(hi, bin[0][bx].upper);
        ++count[0][bx];
        bin[1][by].lower = _mm_min_ps(lo, bin[1][by].lower);
        bin[1][by].upper = _mm_max_ps(hi, bin[1][by].upper);
        ++count[1][by];
        bin[2][bz].lower = _mm_min_ps(lo, bin[2][bz].lower);
        bin[2][bz].upper = _mm_max_ps(hi, bin[2][bz].upper);
        ++count[2][bz];
        if (occupied) {
            occupied[0] |= 1u << bx;
            occupied[1] |= 1u << by;
            occupied[2] |= 1u << bz;
        }
    }

    // Bins the primitives; sets the bits of `occupied` that occupied() would
    // (for a few primitives, cheaper than reading every count afterwards).
    template <typename Ref>
    void add(const Ref* refs, uint32_t size, const BinMapping& mapping, uint32_t (&occupied)[3]) {
        if (size <= 16) {
            occupied[0] = occupied[1] = occupied[2] = 0;
            for (uint32_t i = 0; i < size; ++i) add(refs[i], mapping, occupied);
            return;
        }
        for (uint32_t i = 0; i < size; ++i) add(refs[i], mapping);
        for (int axis = 0; axis < 3; ++axis) occupied[axis] = this->occupied(axis);
    }

    // Bit b set where bin b on `axis` holds a primitive.
    uint32_t occupied(int axis) const {
        uint32_t mask = 0;
        for (uint32_t b = 0; b < kMaxBins; b += 4) {
            const __m128i counts = _mm_loadu_si128(reinterpret_cast<const __m128i*>(&count[axis][b]));
            const __m128i empty = _mm_cmpeq_epi32(counts, _mm_setzero_si128());
            mask |= uint32_t(_mm_movemask_ps(_mm_castsi128_ps(empty)) ^ 0xf) << b;
        }
        return mask;
    }

    // Resets the bins that occupied() lists, which leaves all reset.
    void clear(const uint32_t (&occupied)[3]) {
        const __m128 inf = _mm_set1_ps(kInfinity), minus_inf = _mm_set1_ps(-kInfinity);
        for (int axis = 0; axis < 3; ++axis) {
            for (uint32_t rest = occupied[axis]; rest != 0; rest &= rest - 1) {
                const auto b = uint32_t(std::countr_zero(rest));
                bin[axis][b].lower = inf;
                bin[axis][b].upper = minus_inf;
                count[axis][b] = 0;
            }
        }
    }

    // The union of the occupied bins in [begin, end) on `axis`.
    Box4 box(int axis, uint32_t occupied, uint32_t begin, uint32_t end) const {
        Box4 box;
        const uint32_t in_range = occupied & (end < 32 ? (1u << end) - 1 : ~0u) & ~((1u << begin) - 1);
        for (uint32_t rest = in_range; rest != 0; rest &= rest - 1) {
            const auto b = uint32_t(std::countr_zero(rest));
            box.extend(bin[axis][b].lower, bin[axis][b].upper);
        }
        return box;
    }

    uint32_t count_below(int axis, uint32_t bin) const {
        uint32_t total = 0;
        for (uint32_t b = 0; b < bin; ++b) total += count[axis][b];
        return total;
    }
};

// A thread's bins, reset, for the nodes it builds one after the other.
struct ScratchBins {
    BinSet bins;

    ScratchBins() { bins.reset(); }
};

struct Split {
    int axis = -1;           // -1: no axis separates the centroids
    uint32_t first_right_bin = 0;
    float cost = kInfinity;  // sum over both sides of box area times primitive cost
};

struct Range {
    uint32_t begin;
    uint32_t end;
    uint32_t size() const { return end - begin; }
};

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
                middle = partition_blocked(in, mapping, split, block_bins, left_centroids, right_centroids);
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

    // Moves the primitives left of the split before the others, within the
    // range; returns where the right ones begin. Without branches on the side
    // a primitive goes to, which no predictor guesses: every primitive is
    // swapped with the first right one so far, which moves it there when it
    // belongs left and leaves both in place, in effect, when not.
    static uint32_t partition_in_place(Ref* refs, Range range, const BinMapping& mapping, const Split& split,
                                       Box4& left_centroids, Box4& right_centroids) {
        const int axis = split.axis;
        const auto bin = float(split.first_right_bin);
        const __m128 inf = _mm_set1_ps(kInfinity), minus_inf = _mm_set1_ps(-kInfinity);
        uint32_t first_right = range.begin;
        for (uint32_t i = range.begin; i < range.end; ++i) {
            const Ref ref = refs[i];
            const bool left = mapping.below(ref.centroid(axis), axis, bin);
            const __m128 c = ref.centroid4();
            const __m128 is_left = _mm_castsi128_ps(_mm_set1_epi32(-int32_t(left)));
            // inf where the centroid does not count, which no min or max takes.
            left_centroids.lower = _mm_min_ps(_mm_or_ps(_mm_and_ps(is_left, c), _mm_andnot_ps(is_left, inf)),
                                              left_centroids.lower);
            left_centroids.upper = _mm_max_ps(_mm_or_ps(_mm_and_ps(is_left, c), _mm_andnot_ps(is_left, minus_inf)),
                                              left_centroids.upper);
            right_centroids.lower = _mm_min_ps(_mm_or_ps(_mm_andnot_ps(is_left, c), _mm_and_ps(is_left, inf)),
                                               right_centroids.lower);
            right_centroids.upper = _mm_max_ps(_mm_or_ps(_mm_andnot_ps(is_left, c), _mm_and_ps(is_left, minus_inf)),
                                               right_centroids.upper);
            refs[i] = refs[first_right];
            refs[first_right] = ref;
            first_right += left;
        }
        return first_right;
    }

    // Copies the range into the other buffer, the left primitives first, each
    // side in its old order, block by block on as many threads as are spare.
    uint32_t partition_blocked(const NodeInput& in, const BinMapping& mapping, const Split& split,
                               const std::vector<BinSet>& block_bins, Box4& left_centroids,
                               Box4& right_centroids) {
        const Range range = in.range;
        const auto block_count = uint32_t(block_bins.size());
        struct BlockOut {
            uint32_t left;   // where the block's left primitives go
            uint32_t right;  // and its right ones
            Box4 left_centroids;
            Box4 right_centroids;
        };
        std::vector<BlockOut> out(block_count);
        uint32_t left_total = 0;
        for (uint32_t b = 0; b < block_count; ++b) {
            out[b].left = range.begin + left_total;
            left_total += block_bins[b].count_below(split.axis, split.first_right_bin);
        }
        const uint32_t middle = range.begin + left_total;
        for (uint32_t b = 0; b < block_count; ++b)
            out[b].right = middle + (b * kBlockSize - (out[b].left - range.begin));
        const Ref* src = refs_[in.buffer].get();
        Ref* dst = refs_[1 - in.buffer].get();
        const int axis = split.axis;
        const auto bin = float(split.first_right_bin);
        executor_.parallel_for(block_count, [&](uint32_t block) {
            const uint32_t begin = range.begin + block * kBlockSize;
            const uint32_t end = std::min(range.end, begin + kBlockSize);
            BlockOut& o = out[block];
            uint32_t l = o.left, r = o.right;
            for (uint32_t i = begin; i < end; ++i) {
                const Ref& ref = src[i];
                if (mapping.below(ref.centroid(axis), axis, bin)) {
                    o.left_centroids.extend(ref.centroid4());
                    dst[l++] = ref;
                } else {
                    o.right_centroids.extend(ref.centroid4());
                    dst[r++] = ref;
                }
            }
        });
        for (const BlockOut& o : out) {
            left_centroids.extend(o.left_centroids);
            right_centroids.extend(o.right_centroids);
        }
        return middle;
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

bool same_float(float a, float b) { return std::bit_cast<uint32_t>(a) == std::bit_cast<uint32_t>(b); }

// Fills the references for primitives [begin, end), with their bounds and
// centroid bounds; returns false if some centroid is not its box's centre (then
// CenteredRef cannot stand for it).
template <typename Ref>
bool fill_refs(Ref* refs, std::span<const Bounds3> prim_bounds, std::span<const vec3> centroids, uint32_t begin,
               uint32_t end, Box4& bounds, Box4& centroid_bounds) {
    bool centered = true;
    for (uint32_t i = begin; i < end; ++i) {
        const Bounds3& b = prim_bounds[i];
        const vec3 c = centroids[i];
        Ref& ref = refs[i];
        ref.lower[0] = b.min.x, ref.lower[1] = b.min.y, ref.lower[2] = b.min.z;
        ref.upper[0] = b.max.x, ref.upper[1] = b.max.y, ref.upper[2] = b.max.z;
        ref.id = i;
        ref.unused = 0;
        if constexpr (std::is_same_v<Ref, StoredCentroidRef>) {
            ref.center[0] = c.x, ref.center[1] = c.y, ref.center[2] = c.z, ref.center[3] = 0.0f;
        } else {
            const vec3 center = b.center();
            centered = centered && same_float(c.x, center.x) && same_float(c.y, center.y) && same_float(c.z, center.z);
        }
        bounds.extend(ref.lower4(), ref.upper4());
        centroid_bounds.extend(ref.centroid4());
    }
    return centered;
}

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
