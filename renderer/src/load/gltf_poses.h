// Where each glTF node stands when the shutter opens and when it closes. A
// node keeps its own (rest) transform, unless
// - the model's first animation moves it. The shutter opens at the animation's
//   first keyframe time and closes at its last; a channel holds its first value
//   until its own first keyframe and its last from its last keyframe on, so at
//   those two times every channel gives its first and its last keyframe value,
//   whatever its interpolation (LINEAR, STEP and CUBICSPLINE alike). What a
//   channel does in between is not followed: vertices travel in straight lines
//   from one pose to the other;
// - an rt.NodeMotion names it: the motion is its transform at shutter close,
//   the parts it leaves out being the rest transform's. It wins over the
//   animation, whose pose at close that node then ignores.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "load/node_transform.h"
#include "load/scene_extras.h"
#include "load/third_party.h"

namespace rt {

class GltfPoses {
  public:
    // Throws SceneError for an animation that cannot be followed (prefixed with
    // `scene_name`) and for a motion that names no node or one of several of
    // that name (prefixed with the motion's source). What the animation does
    // that is ignored goes to `warnings`. The model must outlive this.
    GltfPoses(const tinygltf::Model& model, const std::string& scene_name,
              std::span<const SceneAdditions::Motion> motions, std::vector<std::string>& warnings);

    // False when no node moves: then every node's close transform is its open one.
    bool moving() const { return !close_.empty(); }

    struct Local {
        dmat4 open;
        dmat4 close;
    };
    // The local transforms of nodes[index], checked: throws SceneError naming
    // `what` for one that is not finite or whose rotation is not a rotation.
    Local local(size_t index, const std::string& what) const;

  private:
    [[noreturn]] void fail(const std::string& problem) const;
    void read_first_animation(std::vector<std::string>& warnings);
    void add_motion(const SceneAdditions::Motion& motion, const std::vector<size_t>& named, std::vector<char>& moved);
    NodeTransform rest(const tinygltf::Node& node, const std::string& what) const;

    const tinygltf::Model& model_;
    const std::string& name_;
    // Per node when anything moves, else empty: what the animation sets at
    // open, and what it or a motion sets at close.
    std::vector<NodeTransformParts> open_;
    std::vector<NodeTransformParts> close_;
};

}  // namespace rt
