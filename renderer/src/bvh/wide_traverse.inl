// Front-to-back traversal of the eight-wide BVH for closest-hit and any-hit
// queries, compiled once per SIMD path: the including file defines
// `wide_box_test<kMoving>(node, box_ray, t_max, t_entry, close, time)` for its
// instruction set, the EntryDistances it fills and the HitKeys that read
// them, and includes this inside its ISA namespace (as Embree compiles its
// kernels once per ISA, in namespace embree::isa). What the leaves hold is
// the caller's business: it passes the leaf test.
//
// A closest-hit query takes the children a ray enters nearest first; the
// others wait on a stack with their entry distance, and are dropped when
// popped if a hit nearer than that has been found meanwhile. Distances equal
// but for their three lowest bits go to the lower slot (push_sorted), so
// every path visits the same nodes in the same order.

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

// Pushes the children whose keys `keys` yields (count of them, two or more)
// farthest first, and returns the nearest. A key is the entry distance's bit
// pattern with its slot in the low three bits (bvh::entry_key), as Embree's
// AVX-512 traversal orders children: distances >= +0 sort as their bits do,
// the slot breaks ties, and the key alone says which child it is and, to
// within three bits that only round it down, where the ray enters it.
// Up to four children are ordered by branch-free compare and swaps, more by
// insertion. Against the 64-bit keys (distance, slot) read back from memory
// and the network for three only, 1T against rtcIntersect1 on the Xeon, 3
// rounds: camera rays on dragon_4 1.00 -> 1.03, dragon_3 0.99 -> 1.01;
// diffuse rays 0.85 -> 0.86 and 0.85 -> 0.87.
template <typename HitKeys>
[[gnu::always_inline]] inline bvh::ChildRef push_sorted(const bvh::WideNode& node, uint32_t count, HitKeys& keys,
                                                        WidePending* stack, uint32_t& stack_size) {
    const auto push = [&](uint32_t key) { stack[stack_size++] = {node.child[key & 7u].bits, bvh::entry_distance(key)}; };
    const auto order = [](uint32_t& near, uint32_t& far) {  // near <= far after
        const uint32_t a = near, b = far;
        near = a < b ? a : b;
        far = a < b ? b : a;
    };
    uint32_t a = keys.next(), b = keys.next();
    order(a, b);
    if (count == 2) {
        push(b);
        return node.child[a & 7u];
    }
    uint32_t c = keys.next();
    order(b, c), order(a, b);
    if (count == 3) {
        push(c), push(b);
        return node.child[a & 7u];
    }
    uint32_t d = keys.next();
    order(c, d), order(b, c), order(a, b);
    if (count == 4) {
        push(d), push(c), push(b);
        return node.child[a & 7u];
    }
    uint32_t sorted[bvh::kWideWidth] = {d, c, b, a};  // descending: the nearest last
    for (uint32_t n = 4; n < count; ++n) {
        const uint32_t key = keys.next();
        uint32_t i = n;
        for (; i > 0 && sorted[i - 1] < key; --i) sorted[i] = sorted[i - 1];
        sorted[i] = key;
    }
    for (uint32_t i = 0; i + 1 < count; ++i) push(sorted[i]);
    return node.child[sorted[count - 1] & 7u];
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
            EntryDistances t_entry;
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
                    // (1.02-1.08) over 3 runs, the other queries alike; in a
                    // tree the cache holds, not at all (WideBvh::fetch_ahead).
                    if (bvh.fetch_ahead)
                        for (uint32_t rest = hits; rest != 0; rest &= rest - 1)
                            prefetch_child(bvh, node.child[__builtin_ctz(rest)], prefetch_leaf);
                    HitKeys keys(t_entry, hits);
                    current = push_sorted(node, uint32_t(__builtin_popcount(hits)), keys, stack, stack_size);
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
