// The sample meshes stand on a ground quad some thousand times the mesh's box
// in area. SAH cost is relative to the root's box, so with the quad in it
// every tree costs about 1 (the root) + 0.96 (the quad's leaf) + a few
// thousandths for the mesh itself, on both sides, and the comparison says
// nothing. The memory table therefore also compares the two trees built over
// the scene without that quad.
#pragma once

#include <optional>

#include "geometry/scene.h"

namespace rt::bench {

// The scene without its ground quad: at most two triangles whose boxes each
// have a quarter of the scene box's area or more, the rest together under a
// tenth of it. Nothing when the scene has no such quad (a Cornell box's walls
// are more than two).
std::optional<Scene> without_ground_quad(const Scene& scene);

}  // namespace rt::bench
