#include "bvh/collapse_plan.h"

#include <emmintrin.h>

#include <algorithm>
#include <array>
#include <thread>

#include "bvh/fork_join_executor.h"

namespace rt::bvh {
namespace {

// C(n, s) for s = 1 to 8, at [s - 1]; written and read 16 bytes at a time
// (loads that straddle two earlier stores wait for both to retire, which
// had the plan stall on every node).
struct alignas(16) SlotCosts {
    float c[kWideWidth];

    __m128 lo() const { return _mm_load_ps(c); }
    __m128 hi() const { return _mm_load_ps(c + 4); }
    void set(__m128 lo, __m128 hi) {
        _mm_store_ps(c, lo);
        _mm_store_ps(c + 4, hi);
    }
};

// Below this many binary nodes a subtree is planned on the thread that reached it.
constexpr uint32_t kMinParallelNodes = 4096;

// Eight lanes in two registers moved up by one lane, `fill` into lane 0
// (SSE2 has no shift across registers).
void shift_up(__m128& lo, __m128& hi, __m128 fill) {
    const __m128 carry = _mm_shuffle_ps(lo, lo, _MM_SHUFFLE(3, 3, 3, 3));
    hi = _mm_move_ss(_mm_shuffle_ps(hi, hi, _MM_SHUFFLE(2, 1, 0, 0)), carry);
    lo = _mm_move_ss(_mm_shuffle_ps(lo, lo, _MM_SHUFFLE(2, 1, 0, 0)), fill);
}

// D(n, s) for s = 2 to 8 at lane s - 2 (lane 7 means nothing), and the left
// share that gives it, the smallest among equals. All seven shares k at once
// per lane: C(right, s - k) is lane s - 2 of the right costs moved up by k - 1,
// +inf moved in where s - k < 1, so that no such share is ever taken.
struct Distribution {
    __m128 cost_lo, cost_hi;
    __m128i share_lo, share_hi;
};

Distribution distribute(const SlotCosts& left, const SlotCosts& right) {
    const __m128 inf = _mm_set1_ps(kInfinity);
    __m128 r_lo = right.lo(), r_hi = right.hi();
    // Share 1 first, so that a lane whose every sum is NaN still names a share.
    __m128 l = _mm_set1_ps(left.c[0]);
    Distribution d{_mm_add_ps(l, r_lo), _mm_add_ps(l, r_hi), _mm_set1_epi32(1), _mm_set1_epi32(1)};
    for (int k = 2; k < int(kWideWidth); ++k) {
        shift_up(r_lo, r_hi, inf);
        l = _mm_set1_ps(left.c[k - 1]);
        const __m128 c_lo = _mm_add_ps(l, r_lo), c_hi = _mm_add_ps(l, r_hi);
        const __m128i less_lo = _mm_castps_si128(_mm_cmplt_ps(c_lo, d.cost_lo));
        const __m128i less_hi = _mm_castps_si128(_mm_cmplt_ps(c_hi, d.cost_hi));
        d.cost_lo = _mm_min_ps(c_lo, d.cost_lo);  // c < best ? c : best, as the masks
        d.cost_hi = _mm_min_ps(c_hi, d.cost_hi);
        const __m128i kk = _mm_set1_epi32(k);
        d.share_lo = _mm_or_si128(_mm_and_si128(less_lo, kk), _mm_andnot_si128(less_lo, d.share_lo));
        d.share_hi = _mm_or_si128(_mm_and_si128(less_hi, kk), _mm_andnot_si128(less_hi, d.share_hi));
    }
    return d;
}

// C(n, s) = min(C(n, s - 1), D(n, s)) for s = 2 to 8, from C(n, 1) = `one`:
// a running minimum over [one, D(n, 2), ..., D(n, 8)], in three steps of
// moving up by 1, 2 and 4 lanes. `split` gets the lanes s - 2 where D(n, s)
// is below C(n, s - 1): the slot counts that split the node.
void slot_costs(const Distribution& d, float one, SlotCosts& out, __m128i& split_lo, __m128i& split_hi) {
    const __m128 inf = _mm_set1_ps(kInfinity);
    __m128 lo = d.cost_lo, hi = d.cost_hi;
    shift_up(lo, hi, _mm_set1_ps(one));
    __m128 a = lo, b = hi;
    shift_up(a, b, inf);
    lo = _mm_min_ps(a, lo), hi = _mm_min_ps(b, hi);
    a = _mm_movelh_ps(inf, lo), b = _mm_shuffle_ps(lo, hi, _MM_SHUFFLE(1, 0, 3, 2));
    lo = _mm_min_ps(a, lo), hi = _mm_min_ps(b, hi);
    hi = _mm_min_ps(lo, hi);
    out.set(lo, hi);
    // Fewer slots among equals: fewer boxes to store and test.
    split_lo = _mm_castps_si128(_mm_cmplt_ps(d.cost_lo, lo));
    split_hi = _mm_castps_si128(_mm_cmplt_ps(d.cost_hi, hi));
}

}  // namespace

// The recursion of the plan: each call plans one subtree, post order, and
// returns its slot costs; only the choices are kept per node.
class CollapsePlan::Planner {
  public:
    Planner(CollapsePlan& plan, const Bvh& binary, const CollapseOptions& options, detail::ForkJoinExecutor& executor)
        : plan_(plan), binary_(binary), options_(options), executor_(executor),
          max_leaf_(std::min(options.max_leaf_prims, kBlockWidth * kMaxLeafBlocks)) {}

    // `end`: one past the last of the node's descendants, which the depth-first
    // layout of the binned builder's trees keeps together from its left child
    // on; it only sizes the subtrees for the choice to plan them in parallel,
    // which changes nothing of the plan.
    SlotCosts plan(uint32_t node, uint32_t end) {
        const Node& n = binary_.nodes[node];
        const float area = n.bounds().surface_area();
        SlotCosts c;
        if (n.is_leaf()) {
            plan_.prims_[node] = n.prim_count;
            plan_.first_[node] = n.first_prim();
            plan_.choice_[node] = kLeafBit;
            const __m128 cost = _mm_set1_ps(area * options_.block_cost * blocks(n.prim_count));
            c.set(cost, cost);
            return c;
        }
        const uint32_t l = n.left_child(), r = l + 1;
        const uint32_t left_end = binary_.nodes[r].is_leaf() ? end : binary_.nodes[r].left_child();
        SlotCosts left, right;
        if (std::min(left_end - l, end - left_end) >= kMinParallelNodes) {
            executor_.run([&] { left = plan(l, left_end); }, [&] { right = plan(r, end); });
        } else {
            left = plan(l, left_end);
            right = plan(r, end);
        }
        const uint32_t prims = plan_.prims_[node] = plan_.prims_[l] + plan_.prims_[r];
        plan_.first_[node] = plan_.first_[l];
        const Distribution d = distribute(left, right);
        alignas(16) float d_cost[8];
        _mm_store_ps(d_cost + 4, d.cost_hi);
        const float wide = area * options_.node_cost + d_cost[kWideWidth - 2];
        const float leaf = area * options_.block_cost * blocks(prims);
        // A leaf among equals: one box test where a node would add its own.
        const bool as_leaf = prims <= max_leaf_ && !(wide < leaf);
        if (node == 0) root_wide_cost_ = wide;
        __m128i split_lo, split_hi;
        slot_costs(d, as_leaf ? leaf : wide, c, split_lo, split_hi);
        alignas(16) int32_t share[8];
        _mm_store_si128(reinterpret_cast<__m128i*>(share), _mm_and_si128(split_lo, d.share_lo));
        _mm_store_si128(reinterpret_cast<__m128i*>(share + 4), _mm_and_si128(split_hi, d.share_hi));
        alignas(16) int32_t wide_share[4];
        _mm_store_si128(reinterpret_cast<__m128i*>(wide_share), d.share_hi);
        uint32_t choice = uint32_t(wide_share[kWideWidth - 6]) << kWideShift | uint32_t(as_leaf) * kLeafBit;
        for (uint32_t s = 2; s <= kWideWidth; ++s) choice |= uint32_t(share[s - 2]) << (3 * (s - 2));
        plan_.choice_[node] = choice;
        return c;
    }

    // The root's cost as a wide node, which it always is.
    float root_wide_cost() const { return root_wide_cost_; }

  private:
    static float blocks(uint32_t prims) { return float((prims + kBlockWidth - 1) / kBlockWidth); }

    CollapsePlan& plan_;
    const Bvh& binary_;
    const CollapseOptions& options_;
    detail::ForkJoinExecutor& executor_;
    uint32_t max_leaf_;
    float root_wide_cost_ = 0.0f;
};

CollapsePlan::CollapsePlan(const Bvh& binary, const CollapseOptions& options) {
    const auto count = uint32_t(binary.nodes.size());
    if (count == 0) return;
    prims_.reset(new uint32_t[count]);
    first_.reset(new uint32_t[count]);
    choice_.reset(new uint32_t[count]);
    const unsigned threads = options.threads != 0 ? options.threads : std::thread::hardware_concurrency();
    detail::ForkJoinExecutor executor(threads);
    Planner planner(*this, binary, options, executor);
    planner.plan(0, count);
    const float area = binary.nodes[0].bounds().surface_area();
    if (!binary.nodes[0].is_leaf() && area > 0.0f) root_cost_ = double(planner.root_wide_cost()) / area;
}

}  // namespace rt::bvh
