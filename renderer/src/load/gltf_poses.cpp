#include "load/gltf_poses.h"

#include <cmath>
#include <set>
#include <unordered_map>

#include <glm/gtc/type_ptr.hpp>

#include "load/gltf_accessor.h"
#include "load/loader.h"
#include "load/scene_files.h"

namespace rt {
namespace {

std::string at(const char* array, size_t index) { return std::string(array) + "[" + std::to_string(index) + "]"; }

bool all_finite(const std::vector<double>& values) {
    for (double v : values)
        if (!std::isfinite(v)) return false;
    return true;
}

// The first and the last keyframe value of one animation sampler's output.
struct EndValues {
    glm::dvec4 first;
    glm::dvec4 last;
};

// Those of `sampler`, its output read as `type` (VEC3, with w = 0, or VEC4),
// after checking its keyframe times and its output's size; `what` names it.
EndValues read_end_values(const tinygltf::Model& model, const tinygltf::AnimationSampler& sampler,
                          const std::string& what, int type) {
    const GltfAccessor input(model, sampler.input, what + " input", TINYGLTF_TYPE_SCALAR,
                             {TINYGLTF_COMPONENT_TYPE_FLOAT});
    const size_t keys = input.count();
    if (keys == 0) throw SceneError(input.what() + " has no keyframes");
    for (size_t k = 0; k < keys; ++k) {
        const float time = input.float_at(k);
        if (!std::isfinite(time))
            throw SceneError(input.what() + " keyframe time " + std::to_string(k) + " is not finite");
        if (k > 0 && !(time > input.float_at(k - 1)))
            throw SceneError(input.what() + " keyframe times do not increase at element " + std::to_string(k));
    }
    // A cubic spline keeps an in-tangent, the value and an out-tangent per keyframe.
    size_t stride = 1, offset = 0;
    if (sampler.interpolation == "CUBICSPLINE") stride = 3, offset = 1;
    else if (sampler.interpolation != "LINEAR" && sampler.interpolation != "STEP")
        throw SceneError(what + " has unknown interpolation " + in_quotes(sampler.interpolation));
    const GltfAccessor output(model, sampler.output, what + " output", type, {TINYGLTF_COMPONENT_TYPE_FLOAT});
    if (output.count() != stride * keys)
        throw SceneError(output.what() + " has " + std::to_string(output.count()) + " elements for " +
                         std::to_string(keys) + " keyframes, expected " + std::to_string(stride * keys));
    const auto value = [&](size_t key) {
        const size_t element = stride * key + offset;
        const glm::vec4 v =
            type == TINYGLTF_TYPE_VEC4 ? output.vec4_at(element) : glm::vec4(output.vec3_at(element), 0.0f);
        if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z) || !std::isfinite(v.w))
            throw SceneError(output.what() + " element " + std::to_string(element) + " is not finite");
        return glm::dvec4(v);
    };
    return {value(0), value(keys - 1)};
}

}  // namespace

GltfPoses::GltfPoses(const tinygltf::Model& model, const std::string& scene_name,
                     std::span<const SceneAdditions::Motion> motions, std::vector<std::string>& warnings)
    : model_(model), name_(scene_name) {
    const bool animated = !model.animations.empty() && !model.animations[0].channels.empty();
    if (!animated && motions.empty()) return;
    open_.resize(model.nodes.size());
    close_.resize(model.nodes.size());
    if (animated) read_first_animation(warnings);

    std::unordered_map<std::string, std::vector<size_t>> nodes_by_name;
    for (size_t i = 0; i < model.nodes.size(); ++i) nodes_by_name[model.nodes[i].name].push_back(i);
    std::vector<char> moved(model.nodes.size(), 0);
    for (const SceneAdditions::Motion& motion : motions) {
        const auto named = nodes_by_name.find(motion.node);
        add_motion(motion, named == nodes_by_name.end() ? std::vector<size_t>{} : named->second, moved);
    }
}

void GltfPoses::fail(const std::string& problem) const { throw SceneError(name_ + ": " + problem); }

void GltfPoses::add_motion(const SceneAdditions::Motion& motion, const std::vector<size_t>& named,
                           std::vector<char>& moved) {
    const auto refuse = [&](const std::string& problem) { throw SceneError(motion.source + ": " + problem); };
    const std::string node = "node " + in_quotes(motion.node);
    if (named.empty()) refuse("the scene " + name_ + " has no " + node);
    // Each node's transform is relative to its own parent: one motion cannot suit two nodes.
    if (named.size() > 1)
        refuse(std::to_string(named.size()) + " nodes of " + name_ + " are named " + in_quotes(motion.node) +
               ": a motion needs a name only one node has");
    const size_t index = named.front();
    if (moved[index]) refuse(node + " has a motion already");
    moved[index] = 1;
    if (!model_.nodes[index].matrix.empty() && !motion.close.complete())
        refuse(node + " is placed by a matrix: its motion must give translation, rotation and scale");
    close_[index] = motion.close;
}

void GltfPoses::read_first_animation(std::vector<std::string>& warnings) {
    const tinygltf::Animation& animation = model_.animations[0];
    if (model_.animations.size() > 1)
        warnings.push_back(name_ + ": only the first of " + std::to_string(model_.animations.size()) +
                           " animations moves nodes");
    // Each sampler is read once as VEC3 and once as VEC4 at most, however
    // many channels share it (a hostile file may make it serve both kinds).
    std::vector<std::optional<EndValues>> read(2 * animation.samplers.size());
    const auto end_values = [&](size_t index, int type) -> const EndValues& {
        std::optional<EndValues>& cached = read[2 * index + (type == TINYGLTF_TYPE_VEC4)];
        if (!cached)
            cached = read_end_values(model_, animation.samplers[index],
                                     name_ + ": " + at("animations[0].samplers", index), type);
        return *cached;
    };

    std::set<std::pair<int, std::string>> animated;
    for (size_t c = 0; c < animation.channels.size(); ++c) {
        const tinygltf::AnimationChannel& channel = animation.channels[c];
        const std::string what = at("animations[0].channels", c);
        const std::string& path = channel.target_path;
        const bool rotation = path == "rotation";
        if (path != "translation" && path != "scale" && !rotation) {
            warnings.push_back(name_ + ": " + what + " animates " + in_quotes(path) +
                               ", which is not supported: ignored");
            continue;
        }
        const int node = channel.target_node;
        if (node < 0 || size_t(node) >= model_.nodes.size())
            fail(what + ".target.node refers to node " + std::to_string(node) + ", which does not exist");
        if (channel.sampler < 0 || size_t(channel.sampler) >= animation.samplers.size())
            fail(what + ".sampler refers to sampler " + std::to_string(channel.sampler) + ", which does not exist");
        const std::string target = at("nodes", size_t(node)) + "." + path;
        if (!animated.insert({node, path}).second) fail(what + " animates " + target + " a second time");
        if (!model_.nodes[size_t(node)].matrix.empty())
            fail(what + " animates " + at("nodes", size_t(node)) +
                 ", which is placed by a matrix: only translation, rotation and scale can be animated");

        const EndValues& values =
            end_values(size_t(channel.sampler), rotation ? TINYGLTF_TYPE_VEC4 : TINYGLTF_TYPE_VEC3);
        NodeTransformParts& open = open_[size_t(node)];
        NodeTransformParts& close = close_[size_t(node)];
        if (rotation) {
            // glTF's order is x, y, z, w.
            const auto as_rotation = [&](glm::dvec4 v) {
                const auto q = try_normalize(dquat(v.w, v.x, v.y, v.z));
                if (!q) fail(what + " turns " + at("nodes", size_t(node)) + " by a zero quaternion");
                return *q;
            };
            open.rotation = as_rotation(values.first);
            close.rotation = as_rotation(values.last);
        } else {
            std::optional<dvec3>& open_part = path == "scale" ? open.scale : open.translation;
            std::optional<dvec3>& close_part = path == "scale" ? close.scale : close.translation;
            open_part = dvec3(values.first);
            close_part = dvec3(values.last);
        }
    }
}

NodeTransform GltfPoses::rest(const tinygltf::Node& node, const std::string& what) const {
    const auto check = [&](const std::vector<double>& values, size_t size, const char* field) {
        if (!values.empty() && values.size() != size)
            fail(what + "." + field + " has " + std::to_string(values.size()) + " values, expected " +
                 std::to_string(size));
        if (!all_finite(values)) fail(what + "." + field + " is not finite");
    };
    check(node.translation, 3, "translation");
    check(node.rotation, 4, "rotation");
    check(node.scale, 3, "scale");
    NodeTransform rest;
    if (!node.translation.empty()) rest.translation = glm::make_vec3(node.translation.data());
    if (!node.rotation.empty()) {
        const auto& r = node.rotation;
        const auto q = try_normalize(dquat(r[3], r[0], r[1], r[2]));  // glTF stores x, y, z, w
        if (!q) fail(what + ".rotation is not a rotation");
        rest.rotation = *q;
    }
    if (!node.scale.empty()) rest.scale = glm::make_vec3(node.scale.data());
    return rest;
}

GltfPoses::Local GltfPoses::local(size_t index, const std::string& what) const {
    const tinygltf::Node& node = model_.nodes[index];
    if (!node.matrix.empty()) {
        if (node.matrix.size() != 16)
            fail(what + ".matrix has " + std::to_string(node.matrix.size()) + " values, expected 16");
        if (!all_finite(node.matrix)) fail(what + ".matrix is not finite");
        const dmat4 matrix = glm::make_mat4(node.matrix.data());  // column-major, as glTF
        // Only a complete motion reaches a matrix node (add_motion).
        return {matrix, moving() && !close_[index].empty() ? close_[index].over({}).matrix() : matrix};
    }
    const NodeTransform transform = rest(node, what);
    if (!moving()) {
        const dmat4 matrix = transform.matrix();
        return {matrix, matrix};
    }
    return {open_[index].over(transform).matrix(), close_[index].over(transform).matrix()};
}

}  // namespace rt
