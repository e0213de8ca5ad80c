#include "image/aov.h"

#include <algorithm>
#include <cctype>
#include <stdexcept>

namespace rt {
namespace {

std::string valid_names() {
    std::string names;
    for (AuxOutput output : kAuxOutputs) names += (names.empty() ? "" : ", ") + aux_name(output);
    return names;
}

}  // namespace

std::string aux_name(AuxOutput output) {
    std::string name = AuxOutput_Name(output);
    std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return name;
}

AuxOutput parse_aux_output(std::string_view name) {
    std::string upper(name);
    std::transform(upper.begin(), upper.end(), upper.begin(), [](unsigned char c) { return char(std::toupper(c)); });
    AuxOutput output;
    if (!AuxOutput_Parse(upper, &output) || output == AUX_OUTPUT_UNSPECIFIED)
        throw std::invalid_argument("unknown auxiliary output '" + std::string(name) + "' (expected one of: " +
                                    valid_names() + ")");
    return output;
}

AuxOutput aux_output_from_value(int value) {
    if (!AuxOutput_IsValid(value) || value == AUX_OUTPUT_UNSPECIFIED)
        throw std::invalid_argument("unknown auxiliary output " + std::to_string(value) + " (expected rt.AuxOutput " +
                                    std::to_string(int(DEPTH)) + " to " + std::to_string(int(ALPHA)) + ")");
    return AuxOutput(value);
}

uint32_t aux_channel_count(AuxOutput output) { return uint32_t(aux_channel_names(output).size()); }

std::vector<std::string> aux_channel_names(AuxOutput output) {
    switch (output) {
        case DEPTH: return {"depth.Z"};
        case NORMAL: return {"normal.X", "normal.Y", "normal.Z"};
        case ALBEDO: return {"albedo.R", "albedo.G", "albedo.B"};
        case BVH_COST: return {"bvh_cost.nodes", "bvh_cost.triangles"};
        case ALPHA: return {"A"};  // the colour's alpha, as EXR viewers read it
        default: break;
    }
    throw std::invalid_argument("aux_channel_names(): " + std::to_string(int(output)) + " is no auxiliary output");
}

AuxLayers AuxLayers::from(size_t index) const {
    return {depth ? depth + index : nullptr, normal ? normal + 3 * index : nullptr,
            albedo ? albedo + 3 * index : nullptr, bvh_cost ? bvh_cost + 2 * index : nullptr,
            alpha ? alpha + index : nullptr};
}

void AuxLayers::store(size_t index, const AuxSample& sample) const {
    if (depth) depth[index] = sample.depth;
    if (normal) std::copy_n(&sample.normal.x, 3, normal + 3 * index);
    if (albedo) std::copy_n(&sample.albedo.x, 3, albedo + 3 * index);
    if (alpha) alpha[index] = sample.alpha;
    if (bvh_cost) {
        bvh_cost[2 * index] = sample.cost.nodes_visited;
        bvh_cost[2 * index + 1] = sample.cost.triangles_tested;
    }
}

void AuxPixel::add(const AuxSample& sample) {
    if (count_++ == 0) {
        sum_ = sample;  // a lone sample stays exactly itself (sums would turn -0 into +0)
        return;
    }
    sum_.depth += sample.depth;
    sum_.normal += sample.normal;
    sum_.albedo += sample.albedo;
    sum_.alpha += sample.alpha;
    sum_.cost.nodes_visited += sample.cost.nodes_visited;
    sum_.cost.triangles_tested += sample.cost.triangles_tested;
}

AuxSample AuxPixel::mean() const {
    AuxSample mean = sum_;
    if (count_ > 1) {
        const float scale = 1.0f / float(count_);
        mean.depth *= scale;
        mean.normal *= scale;
        mean.albedo *= scale;
        mean.alpha *= scale;
    }
    return mean;
}

AuxImage::AuxImage(uint32_t w, uint32_t h, const std::vector<AuxOutput>& outputs) : width(w), height(h) {
    const size_t pixels = size_t(w) * h;
    for (AuxOutput output : outputs) {
        const size_t count = pixels * aux_channel_count(output);  // which refuses unknown outputs
        with_layer(output, [&](auto& values) { values.assign(count, 0); });
    }
}

bool AuxImage::has(AuxOutput output) const {
    switch (output) {
        case DEPTH: return !depth.empty();
        case NORMAL: return !normal.empty();
        case ALBEDO: return !albedo.empty();
        case BVH_COST: return !bvh_cost.empty();
        case ALPHA: return !alpha.empty();
        default: return false;
    }
}

std::vector<AuxOutput> AuxImage::outputs() const {
    std::vector<AuxOutput> held;
    for (AuxOutput output : kAuxOutputs)
        if (has(output)) held.push_back(output);
    return held;
}

AuxLayers AuxImage::layers() {
    const auto data = [](auto& values) { return values.empty() ? nullptr : values.data(); };
    return {data(depth), data(normal), data(albedo), data(bvh_cost), data(alpha)};
}

float AuxImage::channel(AuxOutput output, size_t pixel, uint32_t c) const {
    switch (output) {
        case DEPTH: return depth[pixel];
        case NORMAL: return normal[3 * pixel + c];
        case ALBEDO: return albedo[3 * pixel + c];
        case ALPHA: return alpha[pixel];
        default: return float(bvh_cost[2 * pixel + c]);
    }
}

}  // namespace rt
