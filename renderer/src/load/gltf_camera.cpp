#include "load/gltf_camera.h"

#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "load/scene_files.h"
#include "util/math.h"

namespace rt {
namespace {

// Out of float's range, a value becomes infinite for the limits to refuse.
float to_float(double v) { return std::abs(v) < 1e30 ? float(v) : std::numeric_limits<float>::infinity(); }

std::string number(double v) {
    std::ostringstream out;
    out << v;
    return out.str();
}

void read_orthographic(const tinygltf::OrthographicCamera& ortho, const std::string& name, Camera& camera) {
    const std::string field = name + ".orthographic.";
    const auto finite = [&](const char* key, double v) {
        if (!std::isfinite(v)) throw std::invalid_argument(field + key + ": must be a finite number");
    };
    finite("xmag", ortho.xmag);
    finite("ymag", ortho.ymag);
    finite("znear", ortho.znear);
    finite("zfar", ortho.zfar);
    // The specification forbids zero and advises against negative magnifications
    // (a mirrored image): refused rather than guessed at.
    if (!(ortho.ymag > 0.0))
        throw std::invalid_argument(field + "ymag: " + number(ortho.ymag) + " must be above 0");
    if (!(ortho.xmag > 0.0))
        throw std::invalid_argument(field + "xmag: " + number(ortho.xmag) + " must be above 0");
    if (ortho.znear < 0.0)
        throw std::invalid_argument(field + "znear: " + number(ortho.znear) + " must not be negative");
    if (!(ortho.zfar > ortho.znear))
        throw std::invalid_argument(field + "zfar: " + number(ortho.zfar) + " must be above znear");
    camera.set_projection(ORTHOGRAPHIC);
    camera.set_ortho_height(to_float(2.0 * ortho.ymag));
}

}  // namespace

void read_gltf_projection(const tinygltf::Camera& source, const std::string& name, Camera& camera) {
    if (source.type == "orthographic") return read_orthographic(source.orthographic, name, camera);
    if (source.type != "perspective")
        throw std::invalid_argument(name + ".type: " + in_quotes(source.type) + " is neither perspective nor orthographic");
    camera.set_fov_y(to_float(glm::degrees(source.perspective.yfov)));
}

}  // namespace rt
