// What glTF and OBJ cannot say about a scene: analytic spheres, spherical lights,
// the background, named cameras, nodes that move. Read from the sidecar `<scene>.rt.json`
// or a glTF `extras.rt` object, both the JSON form of rt.SceneExtras
// (proto/rt/scene.proto), and validated against that schema's limits.
//
// Kept apart from scene.h so that protobuf headers stay out of the renderer's
// hot code; loader.cpp adds what is read here to the scene.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "geometry/material.h"
#include "geometry/scene.h"
#include "util/math.h"
#include "load/node_transform.h"

namespace rt {

// A sidecar's content in the scene's terms.
struct SceneAdditions {
    struct ShadedSphere {
        vec3 center{0.0f};
        float radius = 0.0f;
        Material material;
    };
    // An rt.NodeMotion, for the format loaders to apply: they know the nodes.
    struct Motion {
        std::string node;
        std::string source;  // where it was read, e.g. "cornell.rt.json: extras.motions[0]"
        NodeTransformParts close;
    };
    std::vector<ShadedSphere> spheres;
    std::vector<Light> lights;
    std::optional<Background> background;
    std::vector<SceneCamera> cameras;
    std::vector<Motion> motions;
};

// Parses `json` as rt.SceneExtras: unknown fields, values outside the schema's
// limits, non-finite numbers, unnamed motions and zero quaternions throw
// std::invalid_argument whose message starts with `source` (e.g.
// "cornell.rt.json: extras") and names the field.
SceneAdditions read_scene_extras(std::string_view json, const std::string& source);

}  // namespace rt
