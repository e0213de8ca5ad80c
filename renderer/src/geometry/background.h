// What camera, reflection and refraction rays see when they miss everything:
// linear RGB radiance by the direction they leave in. It lives beside the scene
// (not in integrator/) because the scene owns its default background and the
// loaders set it.
#pragma once

#include <algorithm>
#include <optional>
#include <string>

#include "rt/render.pb.h"
#include "util/math.h"

namespace rt {

// A vertical gradient over the height of a unit direction, y in world space
// (+Y up, as glTF has it): `bottom` straight down (y = -1), `horizon` level
// (y = 0), `top` straight up (y = +1), linear in y in between. A solid colour
// has the three equal; a two-colour ramp from bottom to top has the horizon
// at their mean, which makes it linear in y over the whole sphere. Being a
// function of y alone, it is the same from every point: the background is at
// infinity.
struct Background {
    vec3 bottom{0.0f};
    vec3 horizon{0.0f};
    vec3 top{0.0f};

    Background() = default;
    // A solid colour; implicit so that a colour can stand wherever a
    // background is asked for.
    Background(vec3 color) : bottom(color), horizon(color), top(color) {}
    Background(vec3 bottom_, vec3 horizon_, vec3 top_) : bottom(bottom_), horizon(horizon_), top(top_) {}
    static Background ramp(vec3 bottom, vec3 top) { return {bottom, 0.5f * (bottom + top), top}; }

    bool solid() const { return bottom == horizon && horizon == top; }
    bool black() const { return solid() && top == vec3(0.0f); }

    // `direction` unit length, as every ray the renderer makes has it.
    vec3 operator()(vec3 direction) const {
        const float y = std::clamp(direction.y, -1.0f, 1.0f);
        return y >= 0.0f ? horizon + (top - horizon) * y : horizon + (bottom - horizon) * -y;
    }

    friend bool operator==(const Background&, const Background&) = default;
};

// A background from the schema's two ways of giving one (RenderSettings and
// SceneExtras both have them, their limits already applied): a solid colour
// (`color`, 3 values) or a BackgroundGradient. Neither: nullopt. Both: throws
// std::invalid_argument naming `path` (e.g. "settings.background_gradient").
std::optional<Background> background_from(const google::protobuf::RepeatedField<float>& color,
                                          const BackgroundGradient* gradient, const std::string& path);

}  // namespace rt
