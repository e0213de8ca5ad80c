// The ray query kernels for CPUs with AVX2: one register holds a plane row of
// all eight child boxes. Only the functions defined after the target pragma
// are compiled for AVX2, and they all live in rt::avx2; the headers above it
// (the standard library, GLM, the scalar and SSE2 tests) keep the baseline
// instruction set, so the linker never merges an AVX2 copy of a shared inline
// function into code that runs on any x86-64. simd_path() calls these only on
// CPUs that have AVX2.
#include "geometry/accel_kernel_headers.h"

#pragma GCC push_options
#pragma GCC target("avx2,bmi,bmi2,popcnt")

namespace rt::avx2 {

inline constexpr SimdPath kSimdPath = SimdPath::avx2;
#include "geometry/accel_avx_kernels.inl"

}  // namespace rt::avx2

#pragma GCC pop_options
