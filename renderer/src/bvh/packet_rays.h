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
// axis, with a finite reciprocal: from_rays() refuses other packets, which go
// ray by ray.
#pragma once

#include <cmath>
#include <cstdint>

#include "bvh/wide_node.h"
#include "util/ray.h"

namespace rt::bvh {

inline constexpr uint32_t kPacketSize = 16;

struct PacketRays {
    // The largest ratio of the reciprocals along one axis that from_rays()
    // accepts: 1.5 and 4 traced the 4 x 4 camera rays of the dragons alike.
    static constexpr float kMaxSpread = 2.0f;

    uint32_t count = 0;
    // Each ray's WideBoxRay constants, structure of arrays.
    alignas(32) float origin[3][kPacketSize];
    alignas(32) float inv_direction[3][kPacketSize];
    float t_max[kPacketSize];
    // Shared by every ray: the row of a node each axis' entry plane sits in.
    uint32_t near_row[3];
    uint32_t far_row[3];
    // Per axis: the origin that gives the smallest entry distance and the one
    // that gives the largest exit, and the reciprocals' range.
    float near_origin[3], far_origin[3];
    float inv_low[3], inv_high[3];

    // False when the interval test would not bound the rays, or not tightly:
    // they share neither their origin nor their direction, differ in some
    // direction sign, spread their reciprocals past kMaxSpread, or have one
    // that is infinite. Such packets go ray by ray.
    bool from_rays(const Ray* rays, uint32_t n) {
        // Rays from one point (a pinhole camera's) or along one direction (an
        // orthographic one's) make a cone or a beam the intervals bound
        // tightly. Rays from many points in many directions (shadow rays from
        // a tile's hits) do not: each axis' bounds then pair one ray's origin
        // with another's reciprocal, and on the full dragon such packets were
        // 2.5 times slower than their rays one by one.
        bool same_origin = true, same_direction = true;
        for (uint32_t i = 1; i < n; ++i) {
            same_origin = same_origin && rays[i].origin == rays[0].origin;
            same_direction = same_direction && rays[i].direction == rays[0].direction;
        }
        if (!same_origin && !same_direction) return false;
        count = n;
        for (int axis = 0; axis < 3; ++axis) {
            float o_low = kInfinity, o_high = -kInfinity;
            inv_low[axis] = kInfinity;
            inv_high[axis] = -kInfinity;
            for (uint32_t i = 0; i < n; ++i) {
                const float o = rays[i].origin[axis];
                const float inv = 1.0f / rays[i].direction[axis];
                if (!std::isfinite(inv) || inv == 0.0f || !std::isfinite(o)) return false;
                origin[axis][i] = o;
                inv_direction[axis][i] = inv;
                o_low = std::min(o_low, o);
                o_high = std::max(o_high, o);
                inv_low[axis] = std::min(inv_low[axis], inv);
                inv_high[axis] = std::max(inv_high[axis], inv);
            }
            const bool negative = inv_high[axis] < 0.0f;
            if (!negative && inv_low[axis] < 0.0f) return false;
            // The product's bounds grow with the reciprocals' spread: where a
            // direction component nears 0 it can span decades, and the packet
            // would enter every box along the other axes.
            const float spread = negative ? inv_low[axis] / inv_high[axis] : inv_high[axis] / inv_low[axis];
            if (!(spread <= kMaxSpread)) return false;
            constexpr uint32_t kUpper = 3 * kWideWidth;
            near_row[axis] = uint32_t(axis) * kWideWidth + (negative ? kUpper : 0);
            far_row[axis] = uint32_t(axis) * kWideWidth + (negative ? 0 : kUpper);
            // (plane - origin) * inv is increasing in the plane - origin
            // difference for positive reciprocals and decreasing for negative.
            near_origin[axis] = negative ? o_low : o_high;
            far_origin[axis] = negative ? o_high : o_low;
        }
        for (uint32_t i = 0; i < n; ++i) t_max[i] = rays[i].t_max;
        return true;
    }
};

}  // namespace rt::bvh
