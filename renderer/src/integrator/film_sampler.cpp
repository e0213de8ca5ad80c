#include "integrator/film_sampler.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace rt {
namespace {

// Inverse of the tent's cumulative distribution, in units of its radius.
float sample_tent(float u) {
    return u < 0.5f ? std::sqrt(2.0f * u) - 1.0f : 1.0f - std::sqrt(2.0f - 2.0f * u);
}

// Polar: the radius from the inverse cumulative distribution of a Gaussian's
// radius (Rayleigh) cut at kGaussianRadius, the angle uniform.
vec2 sample_gaussian(vec2 u) {
    const float two_sigma2 = 2.0f * kGaussianSigma * kGaussianSigma;
    const float kept = -std::expm1(-kGaussianRadius * kGaussianRadius / two_sigma2);  // 1 - e^(-R^2 / 2 sigma^2)
    // log, not log1p: 1 - u kept only rounds to 1 for u below 1e-7, where the
    // radius is 1e-4 pixels either way, and logf costs a fraction of log1pf
    // (which was 9% of a 16-sample render of the Cornell box).
    const float r = std::sqrt(-two_sigma2 * std::log(1.0f - u.x * kept));
    const float phi = 2.0f * kPi * u.y;
    return {r * std::cos(phi), r * std::sin(phi)};
}

}  // namespace

vec2 sample_filter(PixelFilter filter, vec2 u) {
    switch (filter) {
        case BOX: return u - 0.5f;
        case TENT: return kTentRadius * vec2(sample_tent(u.x), sample_tent(u.y));
        case GAUSSIAN: return sample_gaussian(u);
        default: break;
    }
    throw std::invalid_argument("sample_filter(): " + PixelFilter_Name(filter) + " is not sampled");
}

FilmSampler::FilmSampler(const RenderSettings& settings) : filter_(settings.pixel_filter()) {
    if (filter_ != GRID) return;
    const uint32_t samples = settings.samples_per_pixel();
    grid_side_ = uint32_t(std::lround(std::sqrt(double(samples))));
    if (grid_side_ * grid_side_ != samples)
        throw std::invalid_argument("settings.samples_per_pixel: GRID takes a square number of samples (4, 9, 16, ...), "
                                    "not " + std::to_string(samples));
    if (settings.adaptive_threshold() > 0.0f)
        throw std::invalid_argument("settings.adaptive_threshold: adaptive sampling needs a filter whose samples can "
                                    "stop at any count; GRID visits its sub-pixels in a fixed order");
}

vec2 FilmSampler::offset(const PixelSampler& sampler) const {
    if (filter_ == GRID) {
        const uint32_t i = sampler.sample();
        return (vec2(float(i % grid_side_), float(i / grid_side_)) + 0.5f) / float(grid_side_) - 0.5f;
    }
    return sample_filter(filter_, sampler.film());
}

}  // namespace rt
