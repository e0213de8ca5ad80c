#include "util/cpu_features.h"

#include <unistd.h>

#include <cstdlib>
#include <stdexcept>
#include <string>

namespace rt {
namespace {

SimdPath choose_path() {
    const char* forced = std::getenv("RT_SIMD");
    if (forced == nullptr || *forced == '\0') {
        SimdPath widest = SimdPath::generic;
        for (SimdPath path : kSimdPaths)
            if (cpu_supports(path)) widest = path;
        return widest;
    }
    for (SimdPath path : kSimdPaths) {
        if (std::string(forced) != to_string(path)) continue;
        if (!cpu_supports(path))
            throw std::runtime_error(std::string("RT_SIMD=") + forced + ": this CPU does not support it");
        return path;
    }
    throw std::runtime_error(std::string("RT_SIMD=") + forced + ": unknown SIMD path (use generic, avx2 or avx512)");
}

}  // namespace

bool cpu_supports(SimdPath path) {
    switch (path) {
        case SimdPath::generic: return true;
        // GCC's checks include the OS's saving of the YMM registers (XGETBV).
        case SimdPath::avx2:
            return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("bmi") &&
                   __builtin_cpu_supports("bmi2") && __builtin_cpu_supports("popcnt");
        // GCC's check of AVX-512 includes the OS's saving of the ZMM and mask registers.
        case SimdPath::avx512:
            return cpu_supports(SimdPath::avx2) && __builtin_cpu_supports("avx512f") &&
                   __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512bw") &&
                   __builtin_cpu_supports("avx512dq");
    }
    return false;
}

const char* to_string(SimdPath path) {
    switch (path) {
        case SimdPath::generic: return "generic";
        case SimdPath::avx2: return "avx2";
        case SimdPath::avx512: return "avx512";
    }
    return "unknown";
}

SimdPath simd_path() {
    static const SimdPath path = choose_path();
    return path;
}

size_t l2_cache_bytes() {
    static const size_t bytes = [] {
        const long reported = sysconf(_SC_LEVEL2_CACHE_SIZE);
        return reported > 0 ? size_t(reported) : size_t(1) << 20;
    }();
    return bytes;
}

}  // namespace rt
