// Our side of the packet figures: a renderer tile's 4 x 4 block of rays as
// one Accelerator packet query (geometry/accel.h), its active lanes gathered
// into consecutive rays first, as a tile's shading loop hands them over.
// Answers go to the packet's lanes (lane_hits[lane], lane_blocked[lane]),
// as they go to a tile's buffer in the renderer; inactive lanes are left.
#pragma once

#include <array>

#include "geometry/accel.h"
#include "rays.h"

namespace rt::bench {

// The packet's active rays, in lane order. Left uninitialised until written,
// as the renderer's tile keeps its rays and hits (integrator/render.cpp):
// Ray's and Hit's member defaults would be stored only to be overwritten.
struct GatheredPacket {
    union Rays {
        Ray at[kPacketWidth];
        Rays() {}
    } rays;
    std::array<uint32_t, kPacketWidth> lane;
    uint32_t count = 0;

    GatheredPacket(const Ray* all, const Packet& packet) {
        for (uint32_t l = 0; l < kPacketWidth; ++l)
            if (packet[l] != kInactiveLane) {
                rays.at[count] = all[packet[l]];
                lane[count++] = l;
            }
    }
};

// The packet's rays (indices into `rays`).
inline void trace_tile_ours(const Accelerator& accel, const Ray* rays, const Packet& packet, Hit* lane_hits) {
    const GatheredPacket gathered(rays, packet);
    union Hits {
        Hit at[kPacketWidth];
        Hits() {}
    } found;
    accel.intersect(std::span(gathered.rays.at, gathered.count), std::span(found.at, gathered.count));
    for (uint32_t i = 0; i < gathered.count; ++i) lane_hits[gathered.lane[i]] = found.at[i];
}

inline void occluded_tile_ours(const Accelerator& accel, const Ray* rays, const Packet& packet, char* lane_blocked) {
    const GatheredPacket gathered(rays, packet);
    std::array<float, kPacketWidth> visibility;
    accel.visibility(std::span(gathered.rays.at, gathered.count), std::span(visibility.data(), gathered.count));
    for (uint32_t i = 0; i < gathered.count; ++i) lane_blocked[gathered.lane[i]] = visibility[i] == 0.0f;
}

}  // namespace rt::bench
