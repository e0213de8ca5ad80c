// The kernels of the AVX paths, one text for accel_avx2.cpp and
// accel_avx512.cpp: each includes this inside its ISA namespace, under its
// target pragma, after setting kSimdPath (bvh/packet_lanes.inl sizes its
// registers by it). The eight child boxes of a node fill one YMM register on
// both.

#include "bvh/wide_box_test_avx2.inl"
#include "geometry/triangle_block_test_avx2.inl"
#include "bvh/wide_traverse.inl"
#include "bvh/packet_lanes.inl"
#include "bvh/packet_setup.inl"
#include "bvh/packet_traverse.inl"
#include "bvh/packet_masked_traverse.inl"
#include "geometry/accel_kernels.inl"
