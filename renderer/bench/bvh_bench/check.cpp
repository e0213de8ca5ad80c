#include "check.h"

#include <algorithm>
#include <atomic>
#include <cmath>

#include "geometry/brute_force.h"
#include "timing.h"

namespace rt::bench {
namespace {

// Tests every stride-th of `mismatches` with `ours_wrong(i)` on `threads` threads.
template <typename OursWrong>
void test_sample(const Scene& scene, const std::vector<size_t>& mismatches, unsigned threads, Check& check,
                 OursWrong&& ours_wrong) {
    check.mismatches = mismatches.size();
    const size_t cap = max_checked(scene);
    check.stride = std::max<size_t>(1, (mismatches.size() + cap - 1) / cap);
    std::vector<size_t> sample;
    for (size_t k = 0; k < mismatches.size(); k += check.stride) sample.push_back(mismatches[k]);
    std::atomic<size_t> wrong{0};
    parallel_for(sample.size(), threads, [&](size_t k) { wrong += ours_wrong(sample[k]); }, 1);
    check.checked = sample.size();
    check.ours_wrong = wrong;
}

}  // namespace

size_t max_checked(const Scene& scene) {
    const double primitives = double(std::max<size_t>(1, scene.triangles.size() + scene.spheres.size()));
    return std::clamp(size_t(kBruteForceBudget / primitives), kMinChecked, kMaxChecked);
}

bool same_hit(const Hit& ours, const Hit& embree) {
    if (ours.found() != embree.found()) return false;
    return !ours.found() || std::abs(ours.t - embree.t) <= 1e-4f * std::max(1.0f, ours.t);
}

Check check_closest(const Scene& scene, const std::vector<Ray>& rays, const std::vector<Hit>& ours,
                    const std::vector<Hit>& embree, unsigned threads) {
    Check check;
    check.rays = rays.size();
    std::vector<size_t> mismatches;
    for (size_t i = 0; i < rays.size(); ++i)
        if (!same_hit(ours[i], embree[i])) mismatches.push_back(i);
    test_sample(scene, mismatches, threads, check,
                [&](size_t i) { return !same_hit(ours[i], brute_force_hit(scene, rays[i])); });
    return check;
}

Check check_occluded(const Scene& scene, const std::vector<Ray>& rays, const std::vector<char>& ours,
                     const std::vector<char>& embree, unsigned threads) {
    Check check;
    check.rays = rays.size();
    std::vector<size_t> mismatches;
    for (size_t i = 0; i < rays.size(); ++i)
        if (ours[i] != embree[i]) mismatches.push_back(i);
    test_sample(scene, mismatches, threads, check,
                [&](size_t i) { return bool(ours[i]) != brute_force_hit(scene, rays[i]).found(); });
    return check;
}

}  // namespace rt::bench
