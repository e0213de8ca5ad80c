// Validation before timing: our answers against Embree's on every ray, and
// where the two differ, against brute force (geometry/brute_force.h), which
// says whether ours is wrong (or Embree's: its default Moeller-Trumbore test is
// not watertight, ours is).
#pragma once

#include <cstddef>
#include <vector>

#include "geometry/scene.h"
#include "util/ray.h"

namespace rt::bench {

struct Check {
    size_t rays = 0;
    size_t mismatches = 0;   // rays where our answer differs from Embree's
    size_t checked = 0;      // of those, how many brute force tested
    size_t stride = 1;       // every stride-th mismatch was tested
    size_t ours_wrong = 0;   // of the tested, where ours differs from brute force
};

// Brute force costs a test of every primitive per ray: on a big mesh only
// every stride-th mismatch is tested, stride chosen so that at most
// max(kMinChecked, kBruteForceBudget / primitives) rays are, and never more
// than kMaxChecked. Deterministic, so a rerun tests the same rays.
inline constexpr double kBruteForceBudget = 4e8;  // triangle tests per query kind
inline constexpr size_t kMinChecked = 200, kMaxChecked = 20000;

size_t max_checked(const Scene& scene);

bool same_hit(const Hit& ours, const Hit& embree);

Check check_closest(const Scene& scene, const std::vector<Ray>& rays, const std::vector<Hit>& ours,
                    const std::vector<Hit>& embree, unsigned threads);
Check check_occluded(const Scene& scene, const std::vector<Ray>& rays, const std::vector<char>& ours,
                     const std::vector<char>& embree, unsigned threads);

}  // namespace rt::bench
