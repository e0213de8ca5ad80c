// The per-pixel sample stream (sampler.h) and the filters' offsets
// (film_sampler.h): stratification, uniformity over pixels, independence of
// dimensions, and each filter's distribution (chi-square, as Mitsuba tests its pdfs).
#include <cmath>
#include <functional>
#include <vector>

#include <gtest/gtest.h>

#include "integrator/film_sampler.h"
#include "integrator/sampler.h"

namespace rt {
namespace {

// Whether `points` put exactly one point in each elementary interval of area
// 1 / points.size() (points.size() = 2^m): a (0, m, 2)-net in base 2.
bool is_net(const std::vector<vec2>& points, uint32_t m) {
    for (uint32_t p = 0; p <= m; ++p) {
        const uint32_t nx = 1u << p, ny = 1u << (m - p);
        std::vector<int> cells(size_t(nx) * ny, 0);
        for (vec2 u : points) ++cells[size_t(u.y * float(ny)) * nx + size_t(u.x * float(nx))];
        for (int c : cells)
            if (c != 1) return false;
    }
    return true;
}

TEST(Sampler, EveryAlignedPowerOfTwoBlockIsANet) {
    for (uint32_t seed : {0u, 1u, 0xdeadbeefu, 12345u}) {
        for (uint32_t m = 0; m <= 8; ++m) {
            for (uint32_t block : {0u, 1u, 7u}) {
                std::vector<vec2> points;
                for (uint32_t i = 0; i < (1u << m); ++i) points.push_back(scrambled_sobol_2d((block << m) + i, seed));
                EXPECT_TRUE(is_net(points, m)) << "seed " << seed << ", 2^" << m << " points, block " << block;
            }
        }
    }
}

// A pixel's samples together stratify a light's dimension: with 4 shadow rays
// per pixel sample, the first 16 pixel samples' 64 points form a net, and so
// do each pixel sample's own 4.
TEST(Sampler, PixelSamplesShareALightDimensionWithoutRepeatingEachOther) {
    std::vector<vec2> all;
    for (uint32_t s = 0; s < 16; ++s) {
        std::vector<vec2> own;
        for (uint32_t i = 0; i < 4; ++i) own.push_back(PixelSampler(99, s).get_2d(3, i, 4));
        EXPECT_TRUE(is_net(own, 2)) << "pixel sample " << s;
        all.insert(all.end(), own.begin(), own.end());
    }
    EXPECT_TRUE(is_net(all, 6));
    // Another bounce is another dimension.
    EXPECT_NE(PixelSampler(99, 0).get_2d(3, 0, 4), PixelSampler(99, 0).bounce(1).get_2d(3, 0, 4));
}

// Point 0 over many pixels is uniform in [0,1)^2, so one sample per pixel is
// an unbiased estimate.
TEST(Sampler, FirstPointsAreUniformOverPixels) {
    constexpr int kSide = 8, kPixels = 64 * 1024;
    std::vector<int> cells(kSide * kSide, 0);
    for (uint32_t pixel = 0; pixel < uint32_t(kPixels); ++pixel) {
        const vec2 u = PixelSampler(mix_bits(pixel), 0).get_2d(0, 0, 1);
        ++cells[int(u.y * kSide) * kSide + int(u.x * kSide)];
    }
    double chi2 = 0.0;
    const double expected = double(kPixels) / (kSide * kSide);
    for (int c : cells) chi2 += (c - expected) * (c - expected) / expected;
    EXPECT_LT(chi2, 110.0);  // 63 degrees of freedom: p = 0.0002
}

// Within a pixel, the film's points and a light's follow their sequences in
// unrelated orders: without the per-dimension shuffle of the index, sample i
// would take point i of both, and their coordinates would correlate near 1.
TEST(Sampler, DimensionsOfAPixelAreUncorrelated) {
    constexpr int kSamples = 1024;
    for (uint32_t key : {1u, 77u, 0xabcdefu}) {
        double sa = 0.0, sb = 0.0, sab = 0.0, saa = 0.0, sbb = 0.0;
        for (uint32_t i = 0; i < uint32_t(kSamples); ++i) {
            const PixelSampler sampler(key, i);
            const double a = sampler.film().x, b = sampler.get_2d(0, 0, 1).x;
            sa += a, sb += b, sab += a * b, saa += a * a, sbb += b * b;
        }
        const double n = kSamples;
        const double correlation =
            (sab / n - sa / n * sb / n) / std::sqrt((saa / n - sa / n * sa / n) * (sbb / n - sb / n * sb / n));
        EXPECT_LT(std::abs(correlation), 4.0 / std::sqrt(n)) << "pixel key " << key;
    }
}

// The density of each filter over a cell, integrated numerically.
double filter_density(PixelFilter filter, double x, double y) {
    switch (filter) {
        case BOX: return std::abs(x) < 0.5 && std::abs(y) < 0.5 ? 1.0 : 0.0;
        case TENT: return std::max(0.0, 1.0 - std::abs(x)) * std::max(0.0, 1.0 - std::abs(y));
        default: {
            const double r2 = x * x + y * y, s2 = double(kGaussianSigma) * kGaussianSigma;
            return r2 < double(kGaussianRadius) * kGaussianRadius ? std::exp(-r2 / (2.0 * s2)) : 0.0;
        }
    }
}

// Chi-square of 2^16 stratified offsets against the filter's shape on a grid
// over its support, cells with few expected samples pooled.
TEST(FilmSampler, OffsetsFollowEachFiltersShape) {
    for (PixelFilter filter : {BOX, TENT, GAUSSIAN}) {
        const double radius = filter == BOX ? 0.5 : filter == TENT ? kTentRadius : kGaussianRadius;
        constexpr int kCells = 12, kSub = 16;
        constexpr uint32_t kSamples = 1u << 16;
        std::vector<double> expected(kCells * kCells, 0.0);
        double total = 0.0;
        for (int j = 0; j < kCells * kSub; ++j) {
            for (int i = 0; i < kCells * kSub; ++i) {
                const double x = -radius + 2.0 * radius * (i + 0.5) / (kCells * kSub);
                const double y = -radius + 2.0 * radius * (j + 0.5) / (kCells * kSub);
                const double f = filter_density(filter, x, y);
                expected[(j / kSub) * kCells + i / kSub] += f;
                total += f;
            }
        }
        std::vector<int> observed(kCells * kCells, 0);
        for (uint32_t k = 0; k < kSamples; ++k) {
            // Independent pixels' first points: the distribution, not the stratification, is under test.
            const vec2 o = sample_filter(filter, PixelSampler(mix_bits(k), 0).film());
            ASSERT_LE(glm::max(std::abs(o.x), std::abs(o.y)), radius) << PixelFilter_Name(filter);
            const int i = std::min(kCells - 1, int((o.x + radius) / (2.0 * radius) * kCells));
            const int j = std::min(kCells - 1, int((o.y + radius) / (2.0 * radius) * kCells));
            ++observed[j * kCells + i];
        }
        double chi2 = 0.0, pooled_expected = 0.0, pooled_observed = 0.0;
        int dof = -1;
        for (int c = 0; c < kCells * kCells; ++c) {
            const double e = expected[c] / total * kSamples;
            if (e < 5.0) {
                pooled_expected += e;
                pooled_observed += observed[c];
                continue;
            }
            chi2 += (observed[c] - e) * (observed[c] - e) / e;
            ++dof;
        }
        if (pooled_expected > 0.0) {
            chi2 += (pooled_observed - pooled_expected) * (pooled_observed - pooled_expected) /
                    std::max(pooled_expected, 1.0);
            ++dof;
        }
        // Mean + 5 standard deviations of chi-square with `dof` degrees of freedom.
        EXPECT_LT(chi2, dof + 5.0 * std::sqrt(2.0 * dof)) << PixelFilter_Name(filter) << ", " << dof << " dof";
    }
}

}  // namespace
}  // namespace rt
