// Auxiliary outputs (AOVs), what the job service calls rt.AuxOutput: per pixel,
// besides colour, the depth at the primary hit, the normal and albedo of the
// surface the pixel shows (past mirrors and glass: the denoiser's guides) and
// its coverage (alpha), averaged over the pixel's samples, and the BVH
// traversal cost of every ray the pixel traced. A render computes them only for
// the layers it is asked for, so the colour path never pays for them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "geometry/accel.h"
#include "util/math.h"
#include "rt/job.pb.h"

namespace rt {

// Every layer, in the order of the proto enum: the order they are stored and written in.
inline constexpr AuxOutput kAuxOutputs[] = {DEPTH, NORMAL, ALBEDO, BVH_COST, ALPHA};

// The proto name in lower case ("depth", "bvh_cost"): what the CLI and rtcore take.
std::string aux_name(AuxOutput output);

// The layer a name (in any case) stands for; throws std::invalid_argument listing the valid names.
AuxOutput parse_aux_output(std::string_view name);

// The layer a proto enum value stands for; throws std::invalid_argument for 0 or unknown values.
AuxOutput aux_output_from_value(int value);

// Values per pixel, and their channel names in an EXR ("depth.Z", "normal.X", ...).
uint32_t aux_channel_count(AuxOutput output);
std::vector<std::string> aux_channel_names(AuxOutput output);

// What the integrator reports about one pixel. A primary ray that hits nothing
// leaves depth, normal and albedo at zero.
struct AuxSample {
    float depth = 0.0f;   // distance along the primary ray to its first hit
    vec3 normal{0.0f};    // shading normal of the surface shown, facing its ray, as shading used it
    vec3 albedo{0.0f};    // diffuse colour there, its texture applied, tinted by mirrors and glass before it
    TraversalStats cost;  // summed over the primary, reflection and shadow rays
    float alpha = 0.0f;   // 1 where the camera ray met a surface or a light, 0 where it saw the background
};

// A pixel's samples together: depth, normal and albedo averaged, as colour is
// (as pbrt-v4's G-buffer film does, so a denoiser sees them filtered alike);
// costs summed, as they count the work of every ray of the pixel.
class AuxPixel {
  public:
    void add(const AuxSample& sample);
    AuxSample mean() const;

  private:
    AuxSample sum_;
    uint32_t count_ = 0;
};

// Where a render writes each layer, pixel after pixel as it writes colour. A
// null pointer is a layer nobody asked for.
struct AuxLayers {
    float* depth = nullptr;        // 1 value per pixel
    float* normal = nullptr;       // 3
    float* albedo = nullptr;       // 3
    uint32_t* bvh_cost = nullptr;  // 2: nodes visited, triangles tested
    float* alpha = nullptr;        // 1

    bool empty() const { return !depth && !normal && !albedo && !bvh_cost && !alpha; }

    // The same layers starting at pixel `index`.
    AuxLayers from(size_t index) const;

    // Writes `sample` at pixel `index` into every layer asked for.
    void store(size_t index, const AuxSample& sample) const;
};

// The layers of an image or tile, each allocated only when asked for.
struct AuxImage {
    uint32_t width = 0;
    uint32_t height = 0;
    std::vector<float> depth, normal, albedo;
    std::vector<uint32_t> bvh_cost;
    std::vector<float> alpha;

    AuxImage() = default;
    AuxImage(uint32_t width, uint32_t height, const std::vector<AuxOutput>& outputs);

    bool has(AuxOutput output) const;
    // The layers held, in the order of kAuxOutputs.
    std::vector<AuxOutput> outputs() const;
    AuxLayers layers();
    // One channel of one pixel, as a float (counts are exact below 2^24).
    float channel(AuxOutput output, size_t pixel, uint32_t channel) const;

    // Calls f with the values of layer `output`, aux_channel_count(output) per
    // pixel: a std::vector<float> for depth, normal, albedo and alpha, of
    // uint32_t for the BVH cost.
    template <class F>
    void with_layer(AuxOutput output, F&& f) {
        switch (output) {
            case DEPTH: f(depth); break;
            case NORMAL: f(normal); break;
            case ALBEDO: f(albedo); break;
            case ALPHA: f(alpha); break;
            default: f(bvh_cost); break;
        }
    }
    template <class F>
    void with_layer(AuxOutput output, F&& f) const {
        const_cast<AuxImage*>(this)->with_layer(output, [&](const auto& values) { f(values); });
    }
};

}  // namespace rt
