// Spherical lights: the radiance they emit, and the points on them that shadow
// rays aim at (the 2020 report's section 5, with an estimator that converges to
// the truth).
#pragma once

#include "util/math.h"
#include "rt/render.pb.h"
#include "geometry/scene.h"

namespace rt {

// What every point of a spherical light emits in every direction: L = I / (pi
// r^2). A sphere of uniform radiance L at distance d subtends a cone with
// sin^2(theta_max) = r^2 / d^2 and, wherever it is wholly above the horizon,
// gives the irradiance E = pi L sin^2(theta_max) cos(beta) = I cos(beta) / d^2
// (beta between the normal and the direction to its centre): the point light of
// the same intensity, which is what `intensity` promises (scene.h).
// In double: r^2 underflows in float for radii below 1e-19, where the
// intensity of a light scaled with its scene does too, and 0 / 0 is NaN.
inline vec3 sphere_light_radiance(const Light& light) {
    const double radius = light.radius;
    return vec3(dvec3(light.intensity) / (double(kPi) * radius * radius));
}

// A point on a spherical light for a shadow ray, and what it carries.
struct SphereLightSample {
    vec3 point;   // on the light's surface, where the shadow ray ends
    vec3 wi;      // unit direction from the shaded point towards it
    vec3 weight;  // radiance over the probability density of wi (per steradian)
};

// The samples of one spherical light seen from one shaded point outside it:
// what all its shadow rays from there share is computed once.
class SphereLightSampler {
  public:
    SphereLightSampler(const Light& light, LightSampling method, vec3 p);

    // A sample drawn from u in [0,1)^2. False when it carries nothing: with
    // SPHERE, a point on the far side.
    bool sample(vec2 u, SphereLightSample& sample) const;

  private:
    bool sample_cone(vec2 u, SphereLightSample& sample) const;
    bool sample_area(vec2 u, SphereLightSample& sample) const;

    const Light& light_;
    LightSampling method_;
    vec3 p_;
    vec3 radiance_;
    // CONE: the frame around the direction to the centre, the cone's extent,
    // and radiance over the uniform density 1 / solid angle.
    vec3 axis_{0.0f}, b1_{0.0f}, b2_{0.0f};
    float sin_max_ = 0.0f, sin2_max_ = 0.0f, one_minus_cos_max_ = 0.0f;
    bool small_cone_ = false;
    vec3 cone_weight_{0.0f};
};

}  // namespace rt
