#include "geometry/scene.h"

namespace rt {

Bounds3 Scene::bounds() const {
    Bounds3 b;
    for (const vec3& p : positions) b.extend(p);
    for (const vec3& p : positions_close) b.extend(p);
    for (const Sphere& s : spheres) {
        b.extend(s.center - vec3(s.radius));
        b.extend(s.center + vec3(s.radius));
    }
    return b;
}

}  // namespace rt
