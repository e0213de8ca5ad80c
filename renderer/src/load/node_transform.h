// A node's transform as glTF splits it (translation, rotation, scale), and the
// partial ones that glTF animation channels and rt.NodeMotion give: each part
// they leave out comes from the node's own transform.
#pragma once

#include <optional>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include "util/math.h"

namespace rt {

using dquat = glm::dquat;

// T * R * S, applied to column vectors.
struct NodeTransform {
    dvec3 translation{0.0};
    dquat rotation{1.0, 0.0, 0.0, 0.0};  // unit length; glm's order is (w, x, y, z)
    dvec3 scale{1.0};

    dmat4 matrix() const {
        return glm::scale(glm::translate(dmat4(1.0), translation) * glm::mat4_cast(rotation), scale);
    }
};

struct NodeTransformParts {
    std::optional<dvec3> translation;
    std::optional<dquat> rotation;  // unit length
    std::optional<dvec3> scale;

    bool empty() const { return !translation && !rotation && !scale; }
    bool complete() const { return translation && rotation && scale; }

    NodeTransform over(const NodeTransform& base) const {
        return {translation.value_or(base.translation), rotation.value_or(base.rotation), scale.value_or(base.scale)};
    }
};

// What transforms normals along with the linear part `m` of a transform: its
// inverse transpose times |det m|, which is the cofactor matrix with the
// determinant's sign folded in, defined even for a singular `m`. Transformed
// normals need renormalising.
inline glm::dmat3 normal_matrix(const glm::dmat3& m) {
    const glm::dmat3 cofactor(glm::cross(m[1], m[2]), glm::cross(m[2], m[0]), glm::cross(m[0], m[1]));
    return glm::determinant(m) < 0.0 ? -cofactor : cofactor;
}

}  // namespace rt
