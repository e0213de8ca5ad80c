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

// A packet's intervals (PacketIntervals) in four-lane registers, for a
// block's four triangles.
struct TriangleCull {
    BlockLanes near_origin[3], near_inv[3], far_origin[3], far_inv[3];
    bool negative[3];  // the rays run towards -axis: their near planes are the upper ones

    explicit TriangleCull(const bvh::PacketIntervals& iv) {
        for (int axis = 0; axis < 3; ++axis) {
            near_origin[axis] = lanes_splat<BlockLanes>(iv.near_origin[axis]);
            near_inv[axis] = lanes_splat<BlockLanes>(iv.near_inv[axis]);
            far_origin[axis] = lanes_splat<BlockLanes>(iv.far_origin[axis]);
            far_inv[axis] = lanes_splat<BlockLanes>(iv.far_inv[axis]);
            negative[axis] = iv.near_row[axis] >= 3 * bvh::kWideWidth;
        }
    }

    // Bit i: some ray the intervals bound may enter triangle i's box.
    uint32_t entered(const TriangleBlock& block) const {
        BlockLanes enter = lanes_splat<BlockLanes>(0.0f);
        BlockLanes exit = lanes_splat<BlockLanes>(kInfinity);
        for (int axis = 0; axis < 3; ++axis) {
            const BlockLanes a = lanes_load<BlockLanes>(block.v[0][axis]),
                             b = lanes_load<BlockLanes>(block.v[1][axis]),
                             c = lanes_load<BlockLanes>(block.v[2][axis]);
            const BlockLanes low = lanes_min(a, lanes_min(b, c)), high = lanes_max(a, lanes_max(b, c));
            const BlockLanes t_near = ((negative[axis] ? high : low) - near_origin[axis]) * near_inv[axis];
            const BlockLanes t_far = ((negative[axis] ? low : high) - far_origin[axis]) * far_inv[axis];
            enter = t_near > enter ? t_near : enter;
            exit = t_far < exit ? t_far : exit;
        }
        return lanes_bits(enter <= exit);
    }
};
