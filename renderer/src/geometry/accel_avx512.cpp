// The ray query kernels for CPUs with AVX-512: the AVX2 kernels' text, with
// the packet kernels' rays sixteen to a register (bvh/packet_lanes.inl), as
// Embree's AVX-512 kernels take its 16-ray packets; the eight child boxes of
// a node still fill one YMM register. As in accel_avx2.cpp, only the
// functions after the target pragma are compiled for AVX-512, all in
// rt::avx512, and simd_path() calls them only on CPUs that have it.
#include "geometry/accel_kernel_headers.h"

#pragma GCC push_options
#pragma GCC target("avx512f,avx512vl,avx512bw,avx512dq,avx2,bmi,bmi2,popcnt")

namespace rt::avx512 {

inline constexpr SimdPath kSimdPath = SimdPath::avx512;
#include "geometry/accel_avx_kernels.inl"

}  // namespace rt::avx512

#pragma GCC pop_options
