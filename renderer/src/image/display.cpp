#include "image/display.h"

#include <algorithm>
#include <array>
#include <bit>
#include <limits>
#include <stdexcept>
#include <string>

#include "util/proto_limits.h"

namespace rt {
namespace {

// srgb8 by table. A float's top 16 bits (sign, exponent, 7 bits of mantissa)
// pick a bucket of floats, and srgb8 of the bucket's least float is where its
// codes start; thresholds_[k], the least float srgb8 rounds to k or more,
// decides whether the value has passed into the next code. Both are found by
// asking srgb8 itself, so the table reproduces its rounding exactly as long as
// srgb8 never decreases, which the tests check over a dense sweep and around
// every threshold. No bucket holds two thresholds: the curve is steepest just
// above the linear segment (0.0031308, about 3300 codes per unit), where a
// bucket spans 1.5e-5 (0.05 codes), and a bucket below 1 spans at most 0.004
// where the curve climbs at most 170 codes per unit (0.66 codes).
class Srgb8Table {
  public:
    Srgb8Table() {
        thresholds_[0] = 0;
        thresholds_.back() = std::numeric_limits<int32_t>::max();
        for (int code = 1; code <= 255; ++code) {
            int32_t lo = 0, hi = kOneBits;  // srgb8 of lo's float is below code, of hi's not
            while (hi - lo > 1) {
                const int32_t mid = lo + (hi - lo) / 2;
                (srgb8(std::bit_cast<float>(mid)) >= code ? hi : lo) = mid;
            }
            thresholds_[size_t(code)] = hi;
        }
        for (uint32_t bucket = 0; bucket < starts_.size(); ++bucket)
            starts_[bucket] = srgb8(std::bit_cast<float>(bucket << kBucketShift));
    }

    // srgb8 of a value already in [0, 1], on its bits (floats from +0 up order
    // as their bits do) and without branches: an image's codes are not predictable.
    uint8_t operator()(float unit) const {
        const int32_t bits = std::bit_cast<int32_t>(unit);
        const uint32_t code = starts_[uint32_t(bits) >> kBucketShift];
        return uint8_t(code + (bits >= thresholds_[code + 1]));
    }

  private:
    static constexpr int32_t kOneBits = 0x3f800000;  // 1.0f
    static constexpr int kBucketShift = 16;

    std::array<uint8_t, (kOneBits >> kBucketShift) + 1> starts_;  // 16 KiB
    std::array<int32_t, 257> thresholds_;                         // bits; [256] is never reached
};

const Srgb8Table& srgb8_table() {
    static const Srgb8Table table;
    return table;
}

// Narkowicz 2015, "ACES Filmic Tone Mapping Curve": a rational fit of the ACES
// reference rendering transform. Negative input would climb back towards 1,
// so it is black (NaN too). The fit passes 1 at x = 7.24 and is clipped there:
// capping x at 100 changes nothing and keeps x^2 from overflowing to inf / inf.
float aces(float x) {
    x = std::min(x > 0.0f ? x : 0.0f, 100.0f);
    return std::min(x * (2.51f * x + 0.03f) / (x * (2.43f * x + 0.59f) + 0.14f), 1.0f);
}

template <ToneMap curve>
vec3 apply_curve(vec3 c) {
    if constexpr (curve == REINHARD) {
        const float l = luminance(c);
        return l > 0.0f ? c * (1.0f / (1.0f + l)) : c;
    } else if constexpr (curve == ACES) {
        return {aces(c.x), aces(c.y), aces(c.z)};
    } else {
        return c;
    }
}

// Exposure, the curve and srgb8's clamp to [0, 1] (NaN to 0) over a run of
// values, in flat loops the compiler vectorises where the curve allows.
template <ToneMap curve>
void expose_and_map(const float* rgb, size_t values, float scale, float* mapped) {
    if constexpr (curve == REINHARD) {
        for (size_t i = 0; i < values; i += 3) {
            const vec3 c = apply_curve<REINHARD>(vec3(rgb[i], rgb[i + 1], rgb[i + 2]) * scale);
            mapped[i] = c.x;
            mapped[i + 1] = c.y;
            mapped[i + 2] = c.z;
        }
    } else {
        for (size_t i = 0; i < values; ++i) mapped[i] = curve == ACES ? aces(rgb[i] * scale) : rgb[i] * scale;
    }
    for (size_t i = 0; i < values; ++i) {
        const float v = mapped[i] > 0.0f ? mapped[i] : 0.0f;
        mapped[i] = v < 1.0f ? v : 1.0f;
    }
}

template <ToneMap curve>
void encode_pixels(const float* rgb, size_t pixels, float scale, uint8_t* out, size_t stride) {
    const Srgb8Table& table = srgb8_table();
    constexpr size_t kRun = 512;  // pixels mapped at a time: the buffer stays in the L1 cache
    float mapped[3 * kRun];
    for (size_t first = 0; first < pixels; first += kRun) {
        const size_t n = std::min(kRun, pixels - first);
        expose_and_map<curve>(rgb + 3 * first, 3 * n, scale, mapped);
        uint8_t* o = out + stride * first;
        for (size_t p = 0; p < n; ++p, o += stride) {
            for (size_t c = 0; c < 3; ++c) o[c] = table(mapped[3 * p + c]);
            if (stride == 4) o[3] = 255;
        }
    }
}

}  // namespace

DisplayTransform DisplayTransform::from(const RenderSettings& settings) {
    RenderSettings filled = settings;
    apply_limits(filled, "settings");
    return {filled.exposure(), filled.tone_map()};
}

vec3 tone_map(vec3 rgb, ToneMap curve) {
    switch (curve) {
        case REINHARD: return apply_curve<REINHARD>(rgb);
        case ACES: return apply_curve<ACES>(rgb);
        default: return apply_curve<CLIP>(rgb);
    }
}

float linear_to_srgb(float linear) {
    const float v = std::clamp(std::isnan(linear) ? 0.0f : linear, 0.0f, 1.0f);
    return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

void encode_srgb8(std::span<const float> rgb, const DisplayTransform& display, std::span<uint8_t> out) {
    const size_t pixels = rgb.size() / 3;
    const size_t stride = out.size() == 3 * pixels ? 3 : out.size() == 4 * pixels ? 4 : 0;
    if (rgb.size() % 3 != 0 || stride == 0)
        throw std::invalid_argument("encode_srgb8(): " + std::to_string(rgb.size()) + " floats of RGB into " +
                                    std::to_string(out.size()) + " bytes fit neither RGB8 nor RGBA8");
    // exp2(0) is exactly 1: the default transform hands srgb8's table every value unchanged.
    const float scale = std::exp2(display.exposure);
    switch (display.tone_map) {
        case REINHARD: encode_pixels<REINHARD>(rgb.data(), pixels, scale, out.data(), stride); break;
        case ACES: encode_pixels<ACES>(rgb.data(), pixels, scale, out.data(), stride); break;
        default: encode_pixels<CLIP>(rgb.data(), pixels, scale, out.data(), stride); break;
    }
}

}  // namespace rt
