// Node culling for a packet of segments that converge: shadow rays from a
// tile's hit points towards one light. They neither share an origin nor a
// direction, so the interval test (packet_rays.h) bounds them poorly, but
// every one of them lies in a thin pyramid with its apex at the light: a box
// wholly outside one of the pyramid's planes holds no part of any of them.
// One plane test per node and plane serves the whole packet (frustum culling,
// as in Reshetov et al.'s "Multi-Level Ray Tracing Algorithm", 2005); each
// ray then meets a leaf only when its own box test says it enters (the
// packet traversal's rays_entering), so the answers are the single rays'.
//
// Compiled once per SIMD path inside its ISA namespace, after
// packet_lanes.inl.

struct PacketFrustum {
    static constexpr int kPlanes = 6;
    // Inward normals: a point x of some segment has
    // normal . (x - apex) >= threshold.
    float normal[kPlanes][3];
    float threshold[kPlanes];
    // Per plane and axis, the row of a node whose plane maximises
    // normal . x over a box: the upper one where the normal is positive.
    uint32_t row[kPlanes][3];
    float apex[3];
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
// wider pyramid culls too little to pay for itself.
inline constexpr float kMaxFrustumSlope = 0.02f;

// The pyramid around the segments origin + [0, t_max] direction of the
// packet's rays (every lane: those past count copy ray 0). False when some
// t_max is infinite, or the segments do not converge on a point well apart
// from their origins.
inline bool make_frustum(PacketFrustum& f, const bvh::PacketRays& p) {
    vec3 end[bvh::kPacketSize], origin[bvh::kPacketSize];
    vec3 apex(0.0f), origins(0.0f);
    for (uint32_t i = 0; i < bvh::kPacketSize; ++i) {
        if (!(p.t_max[i] < kInfinity)) return false;
        origin[i] = vec3(p.origin[0][i], p.origin[1][i], p.origin[2][i]);
        end[i] = origin[i] + p.t_max[i] * vec3(p.direction[0][i], p.direction[1][i], p.direction[2][i]);
        apex += end[i];
        origins += origin[i];
    }
    apex /= float(bvh::kPacketSize);
    origins /= float(bvh::kPacketSize);
    // Each segment lies within `radius` of the one from its origin to the
    // apex: the ends are within it of the apex.
    float radius = 0.0f, reach = 0.0f;
    for (uint32_t i = 0; i < bvh::kPacketSize; ++i) {
        radius = std::max(radius, glm::length(end[i] - apex));
        reach = std::max(reach, glm::length(origin[i] - apex));
    }
    // Room for the rounding of the ends, the apex and the planes, which are
    // all relative to the coordinates.
    radius += 1e-6f * (max_component(glm::abs(apex)) + reach) + 1e-30f;
    const vec3 c = glm::normalize(origins - apex);  // from the apex towards the origins
    if (!std::isfinite(c.x + c.y + c.z)) return false;
    vec3 u, v;
    orthonormal_basis(c, u, v);
    float su_low = kInfinity, su_high = -kInfinity, sv_low = kInfinity, sv_high = -kInfinity, far = 0.0f;
    for (uint32_t i = 0; i < bvh::kPacketSize; ++i) {
        const vec3 g = origin[i] - apex;
        const float along = glm::dot(g, c);
        if (!(along > 2.0f * radius)) return false;
        const float su = glm::dot(g, u) / along, sv = glm::dot(g, v) / along;
        su_low = std::min(su_low, su), su_high = std::max(su_high, su);
        sv_low = std::min(sv_low, sv), sv_high = std::max(sv_high, sv);
        far = std::max(far, along);
    }
    if (!(std::max({-su_low, su_high, -sv_low, sv_high}) <= kMaxFrustumSlope)) return false;
    // A margin for the slopes' rounding.
    constexpr float kSlopeMargin = 1e-5f;
    su_low -= kSlopeMargin, sv_low -= kSlopeMargin, su_high += kSlopeMargin, sv_high += kSlopeMargin;
    const vec3 normals[PacketFrustum::kPlanes] = {u - su_low * c, su_high * c - u, v - sv_low * c,
                                                  sv_high * c - v, c, -c};
    for (int j = 0; j < PacketFrustum::kPlanes; ++j) {
        for (int axis = 0; axis < 3; ++axis) {
            f.normal[j][axis] = normals[j][axis];
            const bool upper = normals[j][axis] > 0.0f;
            f.row[j][axis] = uint32_t(axis) * bvh::kWideWidth + (upper ? 3 * bvh::kWideWidth : 0);
        }
        f.threshold[j] = -radius * glm::length(normals[j]);
    }
    // The far side: nothing of a segment lies beyond its origin.
    f.threshold[5] -= far;
    for (int axis = 0; axis < 3; ++axis) f.apex[axis] = apex[axis];
    return true;
}

// Bit i: child i's box may hold part of some segment of the packet.
[[gnu::always_inline]] inline uint32_t frustum_box_test(const bvh::WideNode& node, const PacketFrustum& f) {
    const float* rows = node.lower[0];
    // An empty slot's inverted box would give inf - inf on a plane parallel
    // to an axis.
    PacketMask inside = lanes_load(node.lower[0]) <= lanes_load(node.upper[0]);
    for (int j = 0; j < PacketFrustum::kPlanes; ++j) {
        PacketLanes dot = lanes_splat(0.0f), magnitude = lanes_splat(0.0f);
        for (int axis = 0; axis < 3; ++axis) {
            const PacketLanes term =
                (lanes_load(rows + f.row[j][axis]) - lanes_splat(f.apex[axis])) * lanes_splat(f.normal[j][axis]);
            dot += term;
            magnitude += lanes_abs(term);
        }
        // The sum's rounding is a few ulps of the terms' magnitudes: a box
        // is outside only past a margin well above it.
        inside &= dot + lanes_splat(1e-5f) * magnitude >= lanes_splat(f.threshold[j]);
    }
    return lanes_bits(inside);
}
