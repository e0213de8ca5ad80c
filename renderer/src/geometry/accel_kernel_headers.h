// What the ray query kernels (accel_generic.cpp, accel_avx2.cpp,
// accel_avx512.cpp) include before their kernel text. Each of those files
// includes this above its target pragma, so that the standard library, GLM
// and the scalar and SSE2 tests keep the baseline instruction set.
// (immintrin.h: packet_lanes.inl names intrinsics that only the wider paths
// instantiate.)
#pragma once

// The kernels make a ray's shear constants lazily (accel_kernels.inl,
// LazyShear), behind a flag GCC does not follow through the inlined
// traversal: it warns of reads that the flag rules out (GCC bug 80635, the
// same false positive as for std::optional). The tests' brute-force
// comparisons would catch a real one.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

#include <immintrin.h>

#include <new>
#include <type_traits>
#include <utility>

#include "bvh/packet_rays.h"
#include "bvh/traverse.h"
#include "bvh/wide_box_test.h"
#include "geometry/accel_data.h"
#include "geometry/sphere.h"
#include "geometry/surface_material.h"
#include "geometry/triangle_block_test.h"
#include "util/cpu_features.h"
