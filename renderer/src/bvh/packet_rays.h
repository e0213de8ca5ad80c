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
    // accepts for closest hits: 1.5 and 4 traced the 4 x 4 camera rays of the
    // dragons alike. Shadow packets take any spread: the intervals only cull
    // the children each ray then tests on its own, and a loose cull still
    // beat the box of the segments. On a light's samples from one point
    // (bvh_bench's soft shadows, 1T against Embree-16): bunny 1.13 -> 1.19,
    // dragon_3 1.11 -> 1.17, teapot 0.70 -> 0.76.
    static constexpr float kMaxSpread = 2.0f;

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
    // triangles are taken at it), and the earliest and latest of them.
    alignas(64) float time[kPacketSize];
    float time_low, time_high;
    // Bounds of all the rays, when load_packet finds that they bound them.
    PacketIntervals intervals;
};

}  // namespace rt::bvh
