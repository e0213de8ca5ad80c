// A packet of up to 16 coherent rays (a renderer tile's 4 x 4 pixels) as the
// packet traversal (packet_traverse.inl) sees it: each ray's own box-test
// constants, as WideBoxRay has them, and intervals that bound them all.
//
// The interval test is Boulos et al.'s "Geometric and Arithmetic Culling
// Methods for Entire Ray Packets" (2006): a node is entered when the
// interval extension of the slab test says some ray of the packet may enter
// it, so one test per node serves the whole packet, as Embree's packet
// kernels serve 16 rays with one node fetch, but with one SIMD test instead of
// sixteen. It is conservative only when every ray runs the same way along each
// axis, with a finite reciprocal: load_packet() (packet_setup.inl) refuses
// other packets, which go ray by ray.
#pragma once

#include <cstdint>

#include "bvh/wide_node.h"
#include "util/ray.h"

namespace rt::bvh {

inline constexpr uint32_t kPacketSize = 16;

// Intervals that bound a set of rays which run the same way along each axis
// (the interval test, packet_traverse.inl's packet_box_test).
struct PacketIntervals {
    // Shared by every ray: the row of a node each axis' entry plane sits in.
    uint32_t near_row[3];
    uint32_t far_row[3];
    // Per axis: the origin that gives the smallest entry distance and the one
    // that gives the largest exit; the reciprocal of least magnitude, which
    // gives the smallest entry distance, and the one of most, scaled by
    // kExitScale as WideBoxRay::inv_exit is, which gives the largest exit.
    float near_origin[3], far_origin[3];
    float near_inv[3], far_inv[3];
};

struct PacketRays {
    // The largest ratio of the reciprocals along one axis that load_packet()
    // accepts for closest hits. The 4 x 4 camera blocks beside the view's
    // centre lines spread 7 (pixel centres 0.5 to 3.5 from the line): at 2
    // they went ray by ray, 0.8% of bvh_bench's camera packets, and the
    // Cornell box's camera packets went from 0.84 to 0.88 of Embree-16 at 8
    // (1T), the dragons' alike; with no limit the bunny's lost 1-2%.
    // Shadow packets take any spread: the intervals only cull the children
    // each ray then tests on its own, and a loose cull still beat the box of
    // the segments. On a light's samples from one point (bvh_bench's soft
    // shadows, 1T against Embree-16): bunny 1.13 -> 1.19, dragon_3 1.11 ->
    // 1.17, teapot 0.70 -> 0.76.
    static constexpr float kMaxSpread = 8.0f;
    // The same for shadow rays run backwards from the light they meet at
    // (reverse_segments): the limit its hard-shadow figures were measured at.
    static constexpr float kMaxReversedSpread = 2.0f;

    uint32_t count = 0;
    // Each ray, and its WideBoxRay constants, structure of arrays; lanes
    // past `count` copy ray 0, so that every lane computes on numbers.
    alignas(64) float origin[3][kPacketSize];
    alignas(64) float direction[3][kPacketSize];
    alignas(64) float inv_direction[3][kPacketSize];
    alignas(64) float t_max[kPacketSize];
    // Where each ray still enters boxes and tests triangles: t_max, and past
    // it by bvh::tie_reach once a closest-hit query has found a triangle.
    alignas(64) float t_cull[kPacketSize];
    // Each ray's moment in the shutter interval (a moving tree's boxes and
    // triangles are taken at it), and for a moving tree the earliest and
    // latest of them (load_time_range).
    alignas(64) float time[kPacketSize];
    float time_low, time_high;
    // Every ray starts at the same point, bit for bit (a pinhole camera's
    // rays, a light's samples from one hit): a triangle's vertices are then
    // moved to it once for all of them (triangle_rays_test.inl).
    bool shared_origin = false;
    // Bounds of all the rays, when load_packet finds that they bound them.
    PacketIntervals intervals;
};

}  // namespace rt::bvh
