// Our side of the packet figures: a renderer tile's 4 x 4 block of rays as
// one Accelerator packet query (geometry/accel.h). rays.cpp stores a
// packet's rays one after another, as the renderer makes them and hands them
// over (a tile's camera rays in integrator/render.cpp, a point's light
// samples in recorders::packet_shadows), and a packet of 16 is taken where
// it lies; one with lanes left out has its rays gathered first. Answers go
// to the packet's lanes (lane_hits[lane], lane_blocked[lane]), as they go
// to a tile's buffer in the renderer; inactive lanes are left.
//
// Embree's side fills its RTCRayHit16 from the same rays, by 4 x 4
// transposes when they lie one after another (embree_scene.cpp), as any
// caller of rtcIntersect16 must fill one. Gathering ours, a copy the renderer
// never makes, and filling Embree's lane by lane had cost each side about a
// tenth of a camera packet's time; taking both as they lie, 1T against
// Embree-16: camera packets on the teapot 1.05 -> 1.07, the Cornell box 1.06
// -> 1.11; hard shadow packets on the teapot 1.05 -> 1.18; soft shadows on
// the teapot 1.01 -> 1.05.
#pragma once

#include <array>
#include <span>

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
    if (consecutive(packet)) {  // the answers in lane order already
        accel.intersect(std::span(rays + packet[0], kPacketWidth), std::span(lane_hits, kPacketWidth));
        return;
    }
    const GatheredPacket gathered(rays, packet);
    union Hits {
        Hit at[kPacketWidth];
        Hits() {}
    } found;
    accel.intersect(std::span(gathered.rays.at, gathered.count), std::span(found.at, gathered.count));
    for (uint32_t i = 0; i < gathered.count; ++i) lane_hits[gathered.lane[i]] = found.at[i];
}

inline void occluded_tile_ours(const Accelerator& accel, const Ray* rays, const Packet& packet, char* lane_blocked) {
    std::array<float, kPacketWidth> visibility;
    if (consecutive(packet)) {
        accel.visibility(std::span(rays + packet[0], kPacketWidth), visibility);
        for (uint32_t lane = 0; lane < kPacketWidth; ++lane) lane_blocked[lane] = visibility[lane] == 0.0f;
        return;
    }
    const GatheredPacket gathered(rays, packet);
    accel.visibility(std::span(gathered.rays.at, gathered.count), std::span(visibility.data(), gathered.count));
    for (uint32_t i = 0; i < gathered.count; ++i) lane_blocked[gathered.lane[i]] = visibility[i] == 0.0f;
}

}  // namespace rt::bench
