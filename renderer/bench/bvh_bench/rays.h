// The rays both sides trace, made once per scene so that ours and Embree see
// exactly the same ones: camera rays, shadow and diffuse bounce rays from
// where those hit, random rays through the scene's box, and the grouping of
// camera and shadow rays into 16-ray packets of 4 x 4 pixels, the way a
// renderer's tile would hand them to a packet tracer.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "geometry/accel.h"
#include "geometry/scene.h"
#include "util/ray.h"

namespace rt::bench {

inline constexpr uint32_t kPacketSide = 4;
inline constexpr uint32_t kPacketWidth = kPacketSide * kPacketSide;
inline constexpr uint32_t kInactiveLane = 0xffffffffu;

// The ray each lane of a packet traces (an index into its ray list), or
// kInactiveLane: lane y * 4 + x is pixel (x, y) of the 4 x 4 block.
using Packet = std::array<uint32_t, kPacketWidth>;

// Whether every lane is active and its ray follows the one before: rays one
// after another, as a renderer makes a tile's rays. Both peers take such a
// packet's rays as they lie (ours_tile.h, embree_scene.cpp).
inline bool consecutive(const Packet& packet) {
    if (packet[0] == kInactiveLane) return false;
    for (uint32_t lane = 1; lane < kPacketWidth; ++lane)
        if (packet[lane] != packet[0] + lane) return false;
    return true;
}

struct RaySet {
    // One ray per pixel of a size x size image, block after block of 4 x 4
    // pixels (each block row by row), so primary_packets[b] is rays 16b..16b+15
    // when size is a multiple of 4.
    std::vector<Ray> primary;
    std::vector<Packet> primary_packets;
    // From each primary hit towards the first light (or a point above the
    // scene); the packets are the primary blocks, lanes without a hit inactive.
    std::vector<Ray> shadow;
    std::vector<Packet> shadow_packets;
    // From every 16th primary hit, 16 rays towards points on a sphere about
    // the first light (its radius, or 2 % of the scene's largest extent), one
    // packet per hit: a spherical light's samples as the integrator traces them.
    std::vector<Ray> soft_shadow;
    std::vector<Packet> soft_shadow_packets;
    // Origins uniform in the scene's box grown by 10 % of its extent on every
    // side, directions uniform on the sphere, no t_max: rays no camera makes,
    // the worst case for any tree.
    std::vector<Ray> random;
    // From each primary hit, a cosine-weighted direction about the shading
    // normal on the side the camera ray came from: a path tracer's first bounce.
    std::vector<Ray> diffuse;
};

// Fixed seeds: the same scene and size give the same rays on every run.
// Camera rays are traced with `accel` on `threads` threads to find the hits.
RaySet make_rays(const Scene& scene, const Accelerator& accel, uint32_t size, size_t random_count,
                 unsigned threads);

}  // namespace rt::bench
