// Node culling for a packet of segments that meet at one end: shadow rays
// from a tile's hit points towards one light, or from one point towards the
// samples of an area light. The first neither share an origin nor a
// direction, and the second may straddle an axis, so the interval test
// (packet_rays.h) bounds them poorly or not at all, but every one of them lies
// in a thin pyramid with its apex where they meet: a box wholly outside one
// of the pyramid's planes holds no part of any of them.
// One plane test per node and plane serves the whole packet (frustum culling,
// as in Reshetov et al.'s "Multi-Level Ray Tracing Algorithm", 2005); each
// ray then meets a leaf only when its own box test says it enters (the
// packet traversal's rays_entering), so the answers are the single rays'.
//
// Compiled once per SIMD path inside its ISA namespace, after
// packet_lanes.inl.

struct PacketFrustum {
    static constexpr int kPlanes = 6;
    // Inward normals: a point x of some segment has normal . x >= limit,
    // with room for the rounding of the product anywhere in the tree.
    float normal[kPlanes][3];
    float limit[kPlanes];
    // Per plane and axis, the row of a node whose plane maximises
    // normal . x over a box: the upper one where the normal is positive.
    uint32_t row[kPlanes][3];
};

// Unit vectors u, v that make an orthonormal basis with unit c (Duff et al.,
// "Building an Orthonormal Basis, Revisited", 2017).
inline void orthonormal_basis(vec3 c, vec3& u, vec3& v) {
    const float sign = std::copysign(1.0f, c.z);
    const float a = -1.0f / (sign + c.z);
    const float b = c.x * c.y * a;
    u = vec3(1.0f + sign * c.x * c.x * a, sign * b, -sign * c.x);
    v = vec3(b, sign + c.y * c.y * a, -c.y);
}

// Slopes of the pyramid's sides past which a packet goes ray by ray: a
// wider pyramid culls too little to pay for itself. Rays that converge on a
// light from a tile's hits: at 0.05 the dragon's shadow packets ran 10-20%
// slower than at 0.02. Rays that diverge from one point to a light's samples
// (bvh_bench's soft shadows): 0.2 served the Cornell box's sphere light
// (0.39 -> 0.57 of Embree-16), and at 0.4 dragon_3's ran at 0.44 against 0.73.
inline constexpr float kMaxFrustumSlope = 0.02f;
inline constexpr float kMaxDivergeSlope = 0.2f;

// The pyramid around the segments origin + [0, t_max] direction of the
// packet's rays (every lane: those past count copy ray 0), with its apex
// where they meet: at their shared origin (`diverge`: a point's samples of an
// area light) or about their ends (shadow rays from many points towards one
// light). False when some t_max is infinite, or the segments do not meet
// within kMaxFrustumSlope of a point well apart from their other ends.
// `scale`: AccelData::coordinate_scale. A register of rays at a time: ray by
// ray, with a square root and two divisions each, it took as long as the
// traversal.
inline bool make_frustum(PacketFrustum& f, const bvh::PacketRays& p, float scale, bool diverge) {
    const float max_slope = diverge ? kMaxDivergeSlope : kMaxFrustumSlope;
    constexpr uint32_t kGroups = bvh::kPacketSize / kRayLanes;
    // Each segment runs from a tip, near the apex, to a base.
    RayLanes tip[kGroups][3], base[kGroups][3];
    RayLanes tip_sum[3] = {}, base_sum[3] = {};
    for (uint32_t g = 0; g < kGroups; ++g) {
        const RayLanes t_max = lanes_load<RayLanes>(p.t_max + g * kRayLanes);
        if (lanes_bits(t_max < kInfinity) != kRayLaneBits) return false;
        for (int axis = 0; axis < 3; ++axis) {
            const RayLanes origin = lanes_load<RayLanes>(p.origin[axis] + g * kRayLanes);
            const RayLanes end = origin + t_max * lanes_load<RayLanes>(p.direction[axis] + g * kRayLanes);
            tip[g][axis] = diverge ? origin : end;
            base[g][axis] = diverge ? end : origin;
            tip_sum[axis] += tip[g][axis];
            base_sum[axis] += base[g][axis];
        }
    }
    vec3 apex, bases;
    for (int axis = 0; axis < 3; ++axis) {
        apex[axis] = lanes_sum(tip_sum[axis]) / float(bvh::kPacketSize);
        bases[axis] = lanes_sum(base_sum[axis]) / float(bvh::kPacketSize);
    }
    // Each segment lies within `radius` of the one from its base to the
    // apex: the tips are within it of the apex.
    RayLanes radius_squared = {}, reach_squared = {};
    for (uint32_t g = 0; g < kGroups; ++g) {
        RayLanes to_tip = {}, to_base = {};
        for (int axis = 0; axis < 3; ++axis) {
            const RayLanes t = tip[g][axis] - apex[axis], b = base[g][axis] - apex[axis];
            to_tip += t * t;
            to_base += b * b;
        }
        radius_squared = lanes_max(radius_squared, to_tip);
        reach_squared = lanes_max(reach_squared, to_base);
    }
    float radius = std::sqrt(lanes_high(radius_squared));
    const float reach = std::sqrt(lanes_high(reach_squared));
    // Room for the rounding of the ends, the apex and the planes, which are
    // all relative to the coordinates.
    radius += 1e-6f * (max_component(glm::abs(apex)) + reach) + 1e-30f;
    const vec3 c = glm::normalize(bases - apex);  // from the apex towards the bases
    if (!std::isfinite(c.x + c.y + c.z)) return false;
    vec3 u, v;
    orthonormal_basis(c, u, v);
    RayLanes su_low = lanes_splat<RayLanes>(kInfinity), su_high = -su_low, sv_low = su_low, sv_high = su_high;
    RayLanes far_along = {};
    for (uint32_t g = 0; g < kGroups; ++g) {
        RayLanes along = {}, along_u = {}, along_v = {};
        for (int axis = 0; axis < 3; ++axis) {
            const RayLanes to_base = base[g][axis] - apex[axis];
            along += to_base * c[axis];
            along_u += to_base * u[axis];
            along_v += to_base * v[axis];
        }
        // The tips' spread is a slope too, seen from the nearest base.
        if (lanes_bits(along * max_slope > radius) != kRayLaneBits) return false;
        // One division for both slopes; kSlopeMargin covers the extra rounding.
        const RayLanes inv_along = lanes_splat<RayLanes>(1.0f) / along;
        const RayLanes su = along_u * inv_along, sv = along_v * inv_along;
        su_low = lanes_min(su_low, su), su_high = lanes_max(su_high, su);
        sv_low = lanes_min(sv_low, sv), sv_high = lanes_max(sv_high, sv);
        far_along = lanes_max(far_along, along);
    }
    float su_min = lanes_low(su_low), su_max = lanes_high(su_high);
    float sv_min = lanes_low(sv_low), sv_max = lanes_high(sv_high);
    const float far = lanes_high(far_along);
    if (!(std::max({-su_min, su_max, -sv_min, sv_max}) <= max_slope)) return false;
    // A margin for the slopes' rounding.
    constexpr float kSlopeMargin = 1e-5f;
    su_min -= kSlopeMargin, sv_min -= kSlopeMargin, su_max += kSlopeMargin, sv_max += kSlopeMargin;
    const vec3 normals[PacketFrustum::kPlanes] = {u - su_min * c, su_max * c - u, v - sv_min * c,
                                                  sv_max * c - v, c, -c};
    // normal . (x - apex) >= threshold. A side normal is a unit vector minus
    // a slope s times one orthogonal to it, so its length is sqrt(1 + s^2),
    // at most 1 + s^2 / 2; 1e-4 more covers the basis' rounding.
    const float slopes[4] = {su_min, su_max, sv_min, sv_max};
    float thresholds[PacketFrustum::kPlanes];
    for (int j = 0; j < 4; ++j) thresholds[j] = -radius * (1.0001f + 0.5f * slopes[j] * slopes[j]);
    thresholds[4] = thresholds[5] = -radius * 1.0001f;
    // The far side: nothing of a segment lies beyond its base.
    thresholds[5] -= far;
    const float magnitude = scale + max_component(glm::abs(apex));
    for (int j = 0; j < PacketFrustum::kPlanes; ++j) {
        for (int axis = 0; axis < 3; ++axis) {
            f.normal[j][axis] = normals[j][axis];
            const bool upper = normals[j][axis] > 0.0f;
            f.row[j][axis] = uint32_t(axis) * bvh::kWideWidth + (upper ? 3 * bvh::kWideWidth : 0);
        }
        // A three-term product rounds by a few ulps of |normal|_1 times the
        // largest coordinate: a margin well above it.
        const float norm_1 = std::abs(normals[j].x) + std::abs(normals[j].y) + std::abs(normals[j].z);
        const float margin = 1e-5f * (norm_1 * magnitude + std::abs(thresholds[j]));
        f.limit[j] = (glm::dot(normals[j], apex) + thresholds[j]) - margin;
    }
    return true;
}

// Bit i: child i's box may hold part of some segment of the packet. `rows`:
// a node's plane rows (packet_box_test's), or a moving node's swept_rows.
[[gnu::always_inline]] inline uint32_t frustum_box_test(const float* rows, const PacketFrustum& f) {
    // An empty slot's inverted box would give 0 * inf on a plane parallel
    // to an axis, or infinities of both signs.
    NodeMask inside = lanes_load<NodeLanes>(rows) <= lanes_load<NodeLanes>(rows + 3 * bvh::kWideWidth);
    for (int j = 0; j < PacketFrustum::kPlanes; ++j) {
        const NodeLanes dot = (lanes_load<NodeLanes>(rows + f.row[j][0]) * f.normal[j][0] +
                               lanes_load<NodeLanes>(rows + f.row[j][1]) * f.normal[j][1]) +
                              lanes_load<NodeLanes>(rows + f.row[j][2]) * f.normal[j][2];
        inside &= dot >= f.limit[j];
    }
    return lanes_bits(inside);
}
