#include "load/scene_extras.h"

#include <cmath>
#include <stdexcept>

#include "util/proto_limits.h"
#include "rt/scene.pb.h"

namespace rt {
namespace {

// A repeated field of count 3 (checked by the schema's limits), or `fallback`
// when absent.
vec3 vector_or(const google::protobuf::RepeatedField<float>& values, vec3 fallback) {
    return values.size() == 3 ? vec3(values[0], values[1], values[2]) : fallback;
}

SceneAdditions::Motion read_motion(const NodeMotion& motion, const std::string& source) {
    if (motion.node().empty()) throw std::invalid_argument(source + ".node: names no node");
    SceneAdditions::Motion out{motion.node(), source, {}};
    const auto& t = motion.translation();
    if (t.size() == 3) out.close.translation = dvec3(t[0], t[1], t[2]);
    if (motion.rotation_size() == 4) {
        // glTF's order: x, y, z, w. Rounded input is made a rotation again.
        const auto& r = motion.rotation();
        const std::optional<dquat> q = try_normalize(dquat(r[3], r[0], r[1], r[2]));
        if (!q) throw std::invalid_argument(source + ".rotation: is not a rotation (a zero quaternion)");
        out.close.rotation = *q;
    }
    const auto& s = motion.scale();
    if (s.size() == 3) out.close.scale = dvec3(s[0], s[1], s[2]);
    return out;
}

float radians(float degrees) { return degrees * (kPi / 180.0f); }

// Point and spot lights need a position, spot and directional ones a
// direction (or glTF's -Z); only point lights have a radius.
Light read_light(const LightSpec& spec, const std::string& name) {
    Light light;
    light.name = name;
    light.kind = spec.kind();
    light.intensity = vector_or(spec.color(), vec3(1.0f)) * spec.intensity();
    if (!is_finite(light.intensity)) throw std::invalid_argument(name + ": color times intensity is not finite");
    if (spec.kind() != DIRECTIONAL && spec.position_size() != 3)
        throw std::invalid_argument(name + ".position: is required for a point or spot light");
    light.position = vector_or(spec.position(), vec3(0.0f));
    if (spec.radius() > 0.0f && spec.kind() != POINT)
        throw std::invalid_argument(name + ".radius: only point lights have one");
    const std::optional<vec3> direction = try_normalize(vector_or(spec.direction(), vec3(0.0f, 0.0f, -1.0f)));
    if (!direction) throw std::invalid_argument(name + ".direction: is zero or not finite");
    light.direction = *direction;
    light.radius = spec.radius();
    light.range = spec.kind() == DIRECTIONAL ? 0.0f : spec.range();
    if (spec.kind() == SPOT) {
        if (!(spec.inner_cone_angle() < spec.outer_cone_angle()))
            throw std::invalid_argument(name + ".inner_cone_angle: must be below outer_cone_angle");
        light.cos_inner = std::cos(radians(spec.inner_cone_angle()));
        light.cos_outer = std::cos(radians(spec.outer_cone_angle()));
    }
    if (spec.kind() == DIRECTIONAL) light.angular_diameter = radians(spec.angular_diameter());
    return light;
}

}  // namespace

SceneAdditions read_scene_extras(std::string_view json, const std::string& source) {
    SceneExtras extras;
    parse_json_message(json, extras, source);
    // Absent messages are not checked by the limits: a sphere without a material
    // gets the schema's default one, and a camera must be given in full.
    for (int i = 0; i < extras.spheres_size(); ++i)
        if (!extras.spheres(i).has_material())
            apply_limits(*extras.mutable_spheres(i)->mutable_material(),
                         source + ".spheres[" + std::to_string(i) + "].material");
    for (int i = 0; i < extras.cameras_size(); ++i)
        if (!extras.cameras(i).has_camera())
            apply_limits(*extras.mutable_cameras(i)->mutable_camera(),
                         source + ".cameras[" + std::to_string(i) + "].camera");

    SceneAdditions additions;
    const Material defaults;
    for (int i = 0; i < extras.spheres_size(); ++i) {
        const auto& sphere = extras.spheres(i);
        const auto& phong = sphere.material();
        Material material;
        material.name = source + ".spheres[" + std::to_string(i) + "]";
        material.diffuse = vector_or(phong.diffuse(), defaults.diffuse);
        material.specular = vector_or(phong.specular(), defaults.specular);
        material.shininess = phong.shininess();
        material.reflectance = vector_or(phong.reflectance(), defaults.reflectance);
        additions.spheres.push_back(
            {vector_or(sphere.center(), vec3(0.0f)), sphere.radius(), std::move(material)});
    }
    for (int i = 0; i < extras.lights_size(); ++i)
        additions.lights.push_back(read_light(extras.lights(i), source + ".lights[" + std::to_string(i) + "]"));
    additions.background = background_from(
        extras.background(), extras.has_background_gradient() ? &extras.background_gradient() : nullptr,
        source + ".background_gradient");
    for (int i = 0; i < extras.cameras_size(); ++i) {
        const auto& camera = extras.cameras(i);
        const std::string name =
            camera.name().empty() ? source + ".cameras[" + std::to_string(i) + "]" : camera.name();
        // Refused here, not first when the camera renders.
        if (camera.camera().projection() == ORTHOGRAPHIC && !camera.camera().has_ortho_height())
            throw std::invalid_argument(source + ".cameras[" + std::to_string(i) +
                                        "].camera.ortho_height: is required for an ORTHOGRAPHIC camera");
        additions.cameras.push_back({name, camera.camera()});
    }
    for (int i = 0; i < extras.motions_size(); ++i)
        additions.motions.push_back(read_motion(extras.motions(i), source + ".motions[" + std::to_string(i) + "]"));
    return additions;
}

}  // namespace rt
