// A pixel's running estimate (the mean of its samples and how far that mean may
// still be from the truth) and the rule by which adaptive sampling stops it.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "util/math.h"

namespace rt {

class PixelEstimate {
  public:
    // Relative errors are taken of max(mean luminance, this): without a floor,
    // a nearly black pixel would spend every sample on noise nobody sees.
    static constexpr double kDarkFloor = 0.05;

    void add(vec3 c) {
        const double y = 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
        // Sums of luminance shifted by the first sample's: no cancellation
        // when the variance is small against the mean, and no division per sample.
        if (count_ == 0) shift_ = y;
        ++count_;
        sum_ += dvec3(c);
        shifted_sum_ += y - shift_;
        shifted_sum2_ += (y - shift_) * (y - shift_);
    }

    uint32_t count() const { return count_; }
    vec3 mean() const { return vec3(sum_ / double(count_)); }

    // The standard error of the mean luminance over the mean (or the floor). It
    // treats the samples as independent; stratified ones do better, most of all
    // on edges, which therefore get more samples than they strictly need.
    double relative_error() const {
        if (count_ < 2) return std::numeric_limits<double>::infinity();
        const double n = double(count_);
        const double variance = std::max(0.0, (shifted_sum2_ - shifted_sum_ * shifted_sum_ / n) / (n - 1.0));
        return std::sqrt(variance / n) / std::max(shift_ + shifted_sum_ / n, kDarkFloor);
    }

  private:
    uint32_t count_ = 0;
    dvec3 sum_{0.0};
    double shift_ = 0.0;
    double shifted_sum_ = 0.0;
    double shifted_sum2_ = 0.0;
};

// Adaptive sampling (adaptive_threshold > 0) lets a pixel stop after a whole
// batch once its relative error is at most the threshold, but never before a
// minimum: no error estimate sees what no sample has hit yet (a sliver of a
// bright light, an edge in the filter's tail), so the minimum grows as the
// threshold tightens, as Blender Cycles' automatic one does (16 / t^0.3),
// rounded up to a power of two: a complete stratified set of the pixel.
class StoppingRule {
  public:
    static constexpr uint32_t kBatch = 8;

    StoppingRule(float threshold, uint32_t max_samples) : threshold_(threshold) {
        if (threshold_ <= 0.0f) return;
        const double automatic = 16.0 / std::pow(double(threshold_), 0.3);
        while (min_samples_ < automatic) min_samples_ *= 2;
        min_samples_ = std::min(min_samples_, max_samples);
    }

    uint32_t min_samples() const { return min_samples_; }

    bool done(const PixelEstimate& estimate) const {
        const uint32_t n = estimate.count();
        return threshold_ > 0.0f && n >= min_samples_ && n % kBatch == 0 &&
               estimate.relative_error() <= threshold_;
    }

  private:
    float threshold_;
    uint32_t min_samples_ = kBatch;
};

}  // namespace rt
