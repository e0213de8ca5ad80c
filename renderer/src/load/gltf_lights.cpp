#include "load/gltf_lights.h"

#include <cmath>
#include <stdexcept>

#include <glm/gtc/type_ptr.hpp>

#include "load/format_loaders.h"
#include "load/scene_files.h"

namespace rt {
namespace {

// A number in [min, max] or `fallback` when absent.
double angle_or(const tinygltf::Value& object, const char* key, double fallback, double max, const std::string& name) {
    if (!object.IsObject() || !object.Has(key)) return fallback;
    const tinygltf::Value& value = object.Get(key);
    const double v = value.IsNumber() ? value.GetNumberAsDouble() : -1.0;
    if (!(v >= 0.0 && v <= max))
        throw std::invalid_argument(name + "." + key + " must be a number from 0 to " + std::to_string(max));
    return v;
}

}  // namespace

Light read_gltf_light(const tinygltf::Light& light, const std::string& name, const dmat4& world) {
    Light out;
    if (light.type == "point") out.kind = POINT;
    else if (light.type == "spot") out.kind = SPOT;
    else if (light.type == "directional") out.kind = DIRECTIONAL;
    else throw std::invalid_argument(name + " has unknown type " + in_quotes(light.type));
    if (!light.color.empty() && light.color.size() != 3)
        throw std::invalid_argument(name + ".color has " + std::to_string(light.color.size()) +
                                    " values, expected 3");
    const dvec3 color = light.color.empty() ? dvec3(1.0) : glm::make_vec3(light.color.data());
    const dvec3 intensity = color * light.intensity;
    if (!fits_float(intensity) || glm::any(glm::lessThan(color, dvec3(0.0))) || light.intensity < 0.0)
        throw std::invalid_argument(name + " has a colour or intensity that is negative or not finite");
    out.intensity = vec3(intensity);
    const dvec3 position(world[3]);
    if (!fits_float(position)) throw std::invalid_argument("the position of " + name + " is not finite");
    out.position = vec3(position);
    if (out.kind != POINT) {
        const std::optional<dvec3> direction = try_normalize(-dvec3(world[2]));
        if (!direction || !fits_float(*direction))
            throw std::invalid_argument("the node of " + name + " gives it no direction (a zero or non-finite scale)");
        out.direction = vec3(*direction);
    }
    if (out.kind != DIRECTIONAL) {
        if (!(light.range >= 0.0) || !fits_float(dvec3(light.range)))
            throw std::invalid_argument(name + ".range must be positive");
        out.range = float(light.range);
    }
    if (out.kind == SPOT) {
        const double outer = light.spot.outerConeAngle, inner = light.spot.innerConeAngle;
        if (!(outer > 0.0 && outer <= 0.5 * kPi + 1e-6) || !(inner >= 0.0 && inner < outer))
            throw std::invalid_argument(name + ".spot needs 0 <= innerConeAngle < outerConeAngle <= pi/2");
        out.cos_inner = float(std::cos(inner));
        out.cos_outer = float(std::cos(outer));
    }
    if (out.kind == DIRECTIONAL && light.extras.IsObject() && light.extras.Has("rt")) {
        const double degrees = angle_or(light.extras.Get("rt"), "angular_diameter", 0.0, 90.0, name + ".extras.rt");
        out.angular_diameter = float(degrees * kPi / 180.0);
    }
    return out;
}

}  // namespace rt
