// Where a pixel's camera samples land: offsets from the pixel's centre drawn
// from the reconstruction filter (filter importance sampling, so every sample
// weighs the same and a pixel is the plain mean of its own samples, never
// splatted into its neighbours, which may belong to another tile), or the
// 2020 report's regular grid of sub-pixel centres.
#pragma once

#include <cstdint>

#include "util/math.h"
#include "rt/render.pb.h"
#include "integrator/sampler.h"

namespace rt {

// The filters' shapes (rt.PixelFilter): a tent of radius 1 in each axis, and a
// Gaussian of standard deviation 0.5 cut off at radius 1.5 (pbrt-v4's
// defaults; the cut drops 1% of its weight).
inline constexpr float kTentRadius = 1.0f;
inline constexpr float kGaussianSigma = 0.5f;
inline constexpr float kGaussianRadius = 1.5f;

// An offset in pixels distributed like `filter` (BOX, TENT or GAUSSIAN), from u
// in [0,1)^2; stratified u give stratified offsets.
vec2 sample_filter(PixelFilter filter, vec2 u);

class FilmSampler {
  public:
    // Throws std::invalid_argument naming the setting when GRID is given a
    // samples_per_pixel that is not a square, or adaptive sampling (a grid
    // visited row by row cannot stop early without favouring its top rows).
    explicit FilmSampler(const RenderSettings& settings);

    // Where pixel sample `sampler.sample()` lies, relative to the pixel's
    // centre, when the pixel takes several (a lone sample takes the centre).
    vec2 offset(const PixelSampler& sampler) const;

  private:
    PixelFilter filter_;
    uint32_t grid_side_ = 1;
};

}  // namespace rt
