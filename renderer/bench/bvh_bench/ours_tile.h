// Our side of the packet figures: what a renderer tile's 4 x 4 block of rays
// costs us. Today that is one Accelerator query per active lane; a coherent
// tile traversal replaces the bodies of these two functions, and the bench
// checks and times whatever they do against rtcIntersect16 / rtcOccluded16.
#pragma once

#include "geometry/accel.h"
#include "rays.h"

namespace rt::bench {

// The packet's rays (indices into `rays`), answers written at the same indices.
inline void trace_tile_ours(const Accelerator& accel, const Ray* rays, const Packet& packet, Hit* hits) {
    for (uint32_t ray : packet)
        if (ray != kInactiveLane) {
            hits[ray] = Hit{};
            accel.intersect(rays[ray], hits[ray]);
        }
}

inline void occluded_tile_ours(const Accelerator& accel, const Ray* rays, const Packet& packet, char* blocked) {
    for (uint32_t ray : packet)
        if (ray != kInactiveLane) blocked[ray] = accel.occluded(rays[ray]);
}

}  // namespace rt::bench
