#include "geometry/background.h"

#include <stdexcept>

namespace rt {
namespace {

vec3 color_of(const google::protobuf::RepeatedField<float>& v) { return vec3(v[0], v[1], v[2]); }

}  // namespace

std::optional<Background> background_from(const google::protobuf::RepeatedField<float>& color,
                                          const BackgroundGradient* gradient, const std::string& path) {
    // Counts and ranges are the schema's limits, applied before this.
    if (gradient && color.size() == 3)
        throw std::invalid_argument(path + ": give background or background_gradient, not both");
    if (color.size() == 3) return Background(color_of(color));
    if (!gradient) return std::nullopt;
    if (gradient->bottom_size() != 3 || gradient->top_size() != 3)
        throw std::invalid_argument(path + ": needs bottom and top, 3 values each");
    const vec3 bottom = color_of(gradient->bottom()), top = color_of(gradient->top());
    if (gradient->horizon_size() != 3) return Background::ramp(bottom, top);
    return Background(bottom, color_of(gradient->horizon()), top);
}

}  // namespace rt
