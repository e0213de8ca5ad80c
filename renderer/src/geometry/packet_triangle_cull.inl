// The triangles of a leaf that a closest-hit packet passes beside, found
// before their tests: the interval test (bvh/packet_traverse.inl's
// packet_box_test) on each triangle's own box, a block's four at once.
// Compiled once per SIMD path after packet_lanes.inl, inside the ISA
// namespace. The box holds its triangle, so no ray that meets a triangle is
// culled, and every answer stays its single-ray query's.
//
// A leaf's box holds all its triangles, and a packet that enters it may pass
// beside most of them: the Cornell box's leaves hold parts of walls far
// apart, and its camera packets ran 9.6 triangle tests in 2.4 leaves, 6.9
// of them against triangles whose boxes no ray of the packet entered. On a
// mesh a packet's footprint spans much of a leaf's few small triangles:
// there the test culled a quarter to a half of them and cost more than it
// saved. So it runs only in leaves that are wide as the packet sees them
// (wide_leaf, packet_traverse.inl). 1T (2T) against Embree-16, camera
// packets: the Cornell box 0.97 -> 1.07 (0.95 -> 0.99), with the sphere
// light 0.97 -> 1.08 (0.96 -> 1.03); the meshes within 3% either way
// (donut 1.12 -> 1.09, dragon_1 1.25 -> 1.23). Culling every block of
// three triangles or more took the bunny from 1.12 to 1.07 and dragon_3
// from 1.15 to 1.08.

typedef float BlockLanes __attribute__((vector_size(4 * bvh::kBlockWidth)));

// Bit i: some ray the intervals bound may enter triangle i's box: the node
// test's interval slabs (interval_entry) on the block's four triangle boxes.
[[gnu::always_inline]] inline uint32_t triangles_entered(const TriangleBlock& block, const bvh::PacketIntervals& iv) {
    BlockLanes exit;
    const BlockLanes enter = interval_entry<BlockLanes>(
        iv, kInfinity,
        [&](int axis, BlockLanes& near, BlockLanes& far) __attribute__((always_inline)) {
            const BlockLanes a = lanes_load<BlockLanes>(block.v[0][axis]),
                             b = lanes_load<BlockLanes>(block.v[1][axis]),
                             c = lanes_load<BlockLanes>(block.v[2][axis]);
            const BlockLanes lower = lanes_min(a, lanes_min(b, c)), upper = lanes_max(a, lanes_max(b, c));
            const bool negative = iv.near_row[axis] >= 3 * bvh::kWideWidth;  // near planes the upper ones
            near = negative ? upper : lower;
            far = negative ? lower : upper;
        },
        exit);
    return lanes_bits(enter <= exit);
}
