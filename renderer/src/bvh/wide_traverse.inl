// Front-to-back traversal of the eight-wide BVH for closest-hit and any-hit
// queries, compiled once per SIMD path: the including file defines
// `wide_box_test<kMoving>(node, box_ray, t_max, t_entry, close, time)` for its
// instruction set and
// includes this inside its ISA namespace (as Embree compiles its kernels once
// per ISA, in namespace embree::isa). What the leaves hold is the caller's
// business: it passes the leaf test.
//
// A closest-hit query takes the children a ray enters nearest first; the
// others wait on a stack with their entry distance, and are dropped when
// popped if a hit nearer than that has been found meanwhile. Ties go to the
// lower slot, so every path visits the same nodes in the same order.

// Sees what a traversal tests. The plain queries' observer does nothing and
// compiles away.
//   visit_node(i):  wide node i's eight child boxes are tested
//   visit_leaf(id): a leaf's primitives are tested (WideBvh::leaf_id)
// Raw bits rather than a ChildRef, whose default initialiser would have the
// whole stack written for every ray.
struct WidePending {
    uint32_t ref;
    float t_entry;
};

// A child put aside is fetched while the ray goes on: a node's four cache
// lines here, a leaf's primitives by the caller's prefetch_leaf(ref). On
// incoherent rays the traversal waits on memory more than it computes.
template <typename PrefetchLeaf>
[[gnu::always_inline]] inline void prefetch_child(const bvh::WideBvh& bvh, bvh::ChildRef ref, PrefetchLeaf& prefetch_leaf) {
    if (ref.is_leaf()) {
        prefetch_leaf(ref);
        return;
    }
    const char* p = reinterpret_cast<const char*>(&bvh.nodes[ref.node()]);
    for (size_t line = 0; line < sizeof(bvh::WideNode); line += 64) __builtin_prefetch(p + line);
    // A moving tree's box motion, which its box test reads too.
    if (!bvh.motion.empty()) {
        const char* motion = reinterpret_cast<const char*>(&bvh.motion[ref.node()]);
        for (size_t line = 0; line < sizeof(bvh::WideBoxes); line += 64) __builtin_prefetch(motion + line);
    }
}

// Pushes the children in `hits` (two or more) farthest first, and returns the nearest.
[[gnu::always_inline]] inline bvh::ChildRef push_sorted(const bvh::WideNode& node, uint32_t hits,
                                                        const float* t_entry, WidePending* stack,
                                                        uint32_t& stack_size) {
    // Entry distances are >= +0, so their bit patterns sort as the distances do;
    // the slot in the low bits breaks ties.
    const auto key_of = [&](uint32_t slot) {
        uint32_t bits;
        __builtin_memcpy(&bits, &t_entry[slot], sizeof bits);
        return uint64_t(bits) << 32 | slot;
    };
    // Two children: one comparison, as Embree's BVH8 traversal orders a
    // pair, instead of the sorting loop (diffuse rays 4-10% faster).
    if (const uint32_t rest = hits & (hits - 1); (rest & (rest - 1)) == 0) {
        const uint32_t a = uint32_t(__builtin_ctz(hits)), b = uint32_t(__builtin_ctz(rest));
        const bool a_nearer = key_of(a) < key_of(b);
        const uint32_t near = a_nearer ? a : b, far = a_nearer ? b : a;
        stack[stack_size++] = {node.child[far].bits, t_entry[far]};
        return node.child[near];
    }
    // Three children: three branch-free compare and swaps, as Embree sorts a
    // few children; more: insertion. Incoherent rays make the insertion's
    // branches unpredictable. 1T against rtcIntersect1, 4 rounds: diffuse
    // rays on dragon_3 1.01 -> 1.04, dragon_2 1.03 -> 1.06, dragon_1 1.05 ->
    // 1.06, dragon_4 1.02 -> 1.02; camera rays alike (dragon_3 1.27 -> 1.27).
    // The network for four children as well lost camera rays 3-5% (dragon_4
    // 1.33 -> 1.27), whose branches the insertion predicted well.
    uint64_t keys[bvh::kWideWidth];
    uint32_t count = 0;
    const auto order = [&](uint32_t i, uint32_t j) {  // keys[i] >= keys[j] after
        const uint64_t a = keys[i], b = keys[j];
        keys[i] = a > b ? a : b;
        keys[j] = a > b ? b : a;
    };
    if (__builtin_popcount(hits) == 3) {
        for (; hits != 0; hits &= hits - 1) keys[count++] = key_of(uint32_t(__builtin_ctz(hits)));
        order(0, 1), order(1, 2), order(0, 1);
    } else {
        for (; hits != 0; hits &= hits - 1) {
            const uint64_t key = key_of(uint32_t(__builtin_ctz(hits)));
            // Insertion into descending order: the nearest ends up last.
            uint32_t i = count++;
            for (; i > 0 && keys[i - 1] < key; --i) keys[i] = keys[i - 1];
            keys[i] = key;
        }
    }
    for (uint32_t i = 0; i + 1 < count; ++i) {
        const uint32_t slot = uint32_t(keys[i]);
        stack[stack_size++] = {node.child[slot].bits, t_entry[slot]};
    }
    return node.child[uint32_t(keys[count - 1])];
}

// leaf_test(first_block, block_count, t_max) tests the leaf's primitives for
// hits with t < t_max (or a tie at t_max, bvh::tie_reach); for closest-hit
// queries it lowers t_max to the nearest hit it finds. It returns whether it
// found one. Returns whether any leaf test did.
// prefetch_leaf(leaf) starts fetching a leaf's primitives.
// kMoving: the tree has boxes at shutter close too, interpolated to ray.time.
template <bvh::Query query, bool kMoving, typename LeafTest, typename PrefetchLeaf, typename Observer>
[[gnu::always_inline]] inline bool traverse_wide(const bvh::WideBvh& bvh, const Ray& ray, LeafTest&& leaf_test,
                                                 PrefetchLeaf&& prefetch_leaf, Observer& observer,
                                                 bvh::ChildRef start = bvh::ChildRef::inner(0)) {
    if (bvh.empty()) return false;
    const bvh::WideBoxRay box_ray(ray);
    float t_max = ray.t_max;
    float reach = t_max;  // where boxes are still entered: tie_reach(t_max) once a hit is found
    WidePending stack[bvh::kWideStackSize];
    uint32_t stack_size = 0;
    bvh::ChildRef current = start;
    bool found = false;
    for (;;) {
        if (!current.is_leaf()) {
            const bvh::WideNode& node = bvh.nodes[current.node()];
            observer.visit_node(current.node());
            alignas(32) float t_entry[bvh::kWideWidth];
            const uint32_t hits = wide_box_test<kMoving>(node, box_ray, reach, t_entry,
                                                         kMoving ? &bvh.motion[current.node()] : nullptr, ray.time);
            if (hits != 0) {
                if ((hits & (hits - 1)) == 0) {
                    current = node.child[__builtin_ctz(hits)];
                } else if constexpr (query == bvh::Query::any_hit) {
                    // Any hit ends the query, so order buys little: take the
                    // children in slot order, as Embree's traverseAnyHit does.
                    current = node.child[__builtin_ctz(hits)];
                    for (uint32_t rest = hits & (hits - 1); rest != 0; rest &= rest - 1) {
                        const bvh::ChildRef child = node.child[__builtin_ctz(rest)];
                        prefetch_child(bvh, child, prefetch_leaf);
                        stack[stack_size++] = {child.bits, 0.0f};
                    }
                } else {
                    // Every child the ray enters is fetched before the sort,
                    // not as it is put aside: diffuse rays on dragon_1, 1T
                    // against rtcIntersect1, 1.02 (0.99-1.07) -> 1.08
                    // (1.02-1.08) over 3 runs, the other queries alike.
                    for (uint32_t rest = hits; rest != 0; rest &= rest - 1)
                        prefetch_child(bvh, node.child[__builtin_ctz(rest)], prefetch_leaf);
                    current = push_sorted(node, hits, t_entry, stack, stack_size);
                }
                continue;
            }
        } else {
            observer.visit_leaf(bvh.leaf_id(current));
            if (leaf_test(current.first_block(), current.block_count(), t_max)) {
                found = true;
                if constexpr (query == bvh::Query::any_hit) return true;
                reach = bvh::tie_reach(t_max);
            }
        }
        for (;;) {
            if (stack_size == 0) return found;
            const WidePending& next = stack[--stack_size];
            // An any-hit query's t_max never shrinks: whatever waits is still ahead.
            if (query == bvh::Query::any_hit || next.t_entry < reach) {
                current = bvh::ChildRef{next.ref};
                break;
            }
        }
    }
}
