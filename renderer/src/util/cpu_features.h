// Which SIMD kernels this CPU runs. The library is compiled for baseline
// x86-64, so one binary runs on any of them (a cluster worker, a container
// built elsewhere); the ray query kernels exist once per instruction set and
// are picked at run time, as Embree picks its ISA.
#pragma once

#include <cstddef>

namespace rt {

enum class SimdPath {
    generic,  // SSE2, which every x86-64 has
    avx2,     // AVX2 with BMI1/2, FMA-free: Haswell (2013) and Zen on
    avx512,   // AVX-512 F/VL/BW/DQ besides: Skylake-SP (2017) and Zen 4 on
};

// Narrowest first.
inline constexpr SimdPath kSimdPaths[] = {SimdPath::generic, SimdPath::avx2, SimdPath::avx512};

// The widest path the CPU and OS support, unless RT_SIMD names a narrower
// one ("generic", "avx2" or "avx512"). An unknown name, or a path the CPU lacks, is an
// error thrown on first use; decided once per process.
SimdPath simd_path();
const char* to_string(SimdPath path);
inline const char* simd_path_name() { return to_string(simd_path()); }

bool cpu_supports(SimdPath path);

// The CPU's level-2 cache per core, as the OS reports it (1 MiB when it
// does not); read once per process.
size_t l2_cache_bytes();

}  // namespace rt
