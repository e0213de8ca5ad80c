// One triangle against a register of a packet's rays (8 or 16) at once: the watertight test
// (triangle.h) with the SIMD lanes over rays instead of over triangles, as
// Embree's packet kernels test one triangle against a whole packet. Lane by
// lane it performs the scalar test's float operations in the same order, and
// hands the lanes where an edge function is exactly zero to the scalar test,
// so each ray's verdict, t, u and v equal its single-ray test's bit for bit.
//
// The rays must share their shear axes (kx, ky, kz): the vertex coordinates
// then enter every lane from the same rows. A camera's 4 x 4 pixel block
// almost always does; PacketShear says when a packet does not.
//
// Compiled once per SIMD path after packet_lanes.inl,
// inside the ISA namespace.

// Each ray's shear constants (WatertightRay's), structure of arrays, when
// every ray of the packet shears along the same axes.
struct PacketShear {
    const bvh::PacketRays& p;
    bool shared;  // every ray has the axes below
    int kx, ky, kz;
    alignas(64) float sx[bvh::kPacketSize];
    alignas(64) float sy[bvh::kPacketSize];
    alignas(64) float sz[bvh::kPacketSize];

    explicit PacketShear(const bvh::PacketRays& packet) : p(packet) {
        const WatertightRay first(ray_at(0));
        kx = first.kx, ky = first.ky, kz = first.kz;
        // WatertightRay's choice of kz (max_dimension), and its swap of kx
        // and ky for a negative d[kz], lane by lane.
        const bool first_negative = p.direction[kz][0] < 0.0f;
        shared = true;
        for (uint32_t lane = 0; lane < bvh::kPacketSize; lane += kRayLanes) {
            const RayLanes x = lanes_abs(lanes_load<RayLanes>(p.direction[0] + lane)),
                              y = lanes_abs(lanes_load<RayLanes>(p.direction[1] + lane)),
                              z = lanes_abs(lanes_load<RayLanes>(p.direction[2] + lane));
            const RayMask x_over_y = x > y, x_largest = x_over_y & (x > z), y_largest = ~x_over_y & (y > z);
            const RayMask largest = kz == 0 ? x_largest : kz == 1 ? y_largest : ~(x_largest | y_largest);
            const RayLanes dz = lanes_load<RayLanes>(p.direction[kz] + lane);
            const RayMask negative = dz < lanes_splat<RayLanes>(0.0f);
            shared = shared && lanes_bits(largest & (first_negative ? negative : ~negative)) == kRayLaneBits;
            lanes_store(sx + lane, lanes_load<RayLanes>(p.direction[kx] + lane) / dz);
            lanes_store(sy + lane, lanes_load<RayLanes>(p.direction[ky] + lane) / dz);
            lanes_store(sz + lane, lanes_splat<RayLanes>(1.0f) / dz);
        }
    }

    Ray ray_at(uint32_t i) const {
        Ray r;
        r.origin = {p.origin[0][i], p.origin[1][i], p.origin[2][i]};
        r.direction = {p.direction[0][i], p.direction[1][i], p.direction[2][i]};
        return r;
    }

    // Ray i's WatertightRay, as its single-ray query makes it.
    WatertightRay ray(uint32_t i) const {
        if (!shared) return WatertightRay(ray_at(i));
        WatertightRay r;
        r.origin = ray_at(i).origin;
        r.kx = kx, r.ky = ky, r.kz = kz;
        r.sx = sx[i], r.sy = sy[i], r.sz = sz[i];
        return r;
    }
};

struct RaysHits {
    RayLanes t, u, v;
};

// A triangle's vertices as every lane sees them: one triangle for all rays,
// or, in a moving scene, each ray's own, the triangle at its time.
struct SharedTriangle {
    vec3 p[3];
    RayLanes coordinate(int k, int axis) const { return lanes_splat<RayLanes>(p[k][axis]); }
    vec3 vertex(int k, uint32_t) const { return p[k]; }
};
struct LaneTriangles {
    RayLanes c[3][3];  // [vertex][axis]
    RayLanes coordinate(int k, int axis) const { return c[k][axis]; }
    vec3 vertex(int k, uint32_t lane) const { return {c[k][0][lane], c[k][1][lane], c[k][2][lane]}; }
};

// Bit i set: ray first + i hits the triangle with 0 < t < t_cull[i]; hits.t/u/v
// lane i then hold its hit. `rays` (kRayLanes bits) says which lanes to test; the
// others answer nothing. `tri`: a SharedTriangle or LaneTriangles.
template <typename Triangle>
[[gnu::always_inline]] inline uint32_t intersect_triangle_rays(const bvh::PacketRays& p, const PacketShear& s,
                                                               uint32_t first, uint32_t rays, const Triangle& tri,
                                                               RaysHits& hits) {
    const RayLanes ox = lanes_load<RayLanes>(p.origin[s.kx] + first), oy = lanes_load<RayLanes>(p.origin[s.ky] + first),
                      oz = lanes_load<RayLanes>(p.origin[s.kz] + first);
    const RayLanes sx = lanes_load<RayLanes>(s.sx + first), sy = lanes_load<RayLanes>(s.sy + first);
    const RayLanes a_z = tri.coordinate(0, s.kz) - oz, b_z = tri.coordinate(1, s.kz) - oz,
                   c_z = tri.coordinate(2, s.kz) - oz;
    const RayLanes ax = (tri.coordinate(0, s.kx) - ox) - sx * a_z;
    const RayLanes ay = (tri.coordinate(0, s.ky) - oy) - sy * a_z;
    const RayLanes bx = (tri.coordinate(1, s.kx) - ox) - sx * b_z;
    const RayLanes by = (tri.coordinate(1, s.ky) - oy) - sy * b_z;
    const RayLanes cx = (tri.coordinate(2, s.kx) - ox) - sx * c_z;
    const RayLanes cy = (tri.coordinate(2, s.ky) - oy) - sy * c_z;

    const RayLanes e0 = cx * by - cy * bx;
    const RayLanes e1 = ax * cy - ay * cx;
    const RayLanes e2 = bx * ay - by * ax;

    const RayLanes zero = lanes_splat<RayLanes>(0.0f);
    const uint32_t exact_zero = lane_bits(lanes_eq(e0, zero) | lanes_eq(e1, zero) | lanes_eq(e2, zero)) & rays;
    const LaneBits negative = lanes_lt(e0, zero) | lanes_lt(e1, zero) | lanes_lt(e2, zero);
    const LaneBits positive = lanes_gt(e0, zero) | lanes_gt(e1, zero) | lanes_gt(e2, zero);
    const RayLanes det = (e0 + e1) + e2;
    LaneBits reject = (negative & positive) | lanes_eq(det, zero);
    // Most rays that reach a leaf miss most of its triangles: leave before
    // the division and the error bound.
    const uint32_t candidates = ~lane_bits(reject) & rays & ~exact_zero;
    uint32_t hit_lanes = 0;
    if (candidates != 0) {
        const RayLanes sz = lanes_load<RayLanes>(s.sz + first);
        const RayLanes t_max = lanes_load<RayLanes>(p.t_cull + first);
        const RayLanes az = sz * a_z, bz = sz * b_z, cz = sz * c_z;
        const RayLanes t_scaled = (e0 * az + e1 * bz) + e2 * cz;
        const RayLanes t_max_det = t_max * det;
        const LaneBits det_negative = lanes_lt(det, zero);
        const LaneBits out_if_negative = lanes_ge(t_scaled, zero) | lanes_lt(t_scaled, t_max_det);
        const LaneBits out_if_positive = lanes_le(t_scaled, zero) | lanes_gt(t_scaled, t_max_det);
        reject |= (det_negative & out_if_negative) | (~det_negative & out_if_positive);

        const RayLanes inv_det = lanes_splat<RayLanes>(1.0f) / det;
        const RayLanes t = t_scaled * inv_det;
        hit_lanes = lane_bits(~reject & lanes_lt(t, t_max)) & candidates;
        if (hit_lanes != 0) {
            // The conservative bound on t's rounding error (pbrt-v4, section 6.8.6).
            const RayLanes max_zt = lanes_abs_max(az, bz, cz);
            const RayLanes max_xt = lanes_abs_max(ax, bx, cx);
            const RayLanes max_yt = lanes_abs_max(ay, by, cy);
            const RayLanes gamma2 = lanes_splat<RayLanes>(gamma_bound(2)),
                           gamma3 = lanes_splat<RayLanes>(gamma_bound(3)),
                           gamma5 = lanes_splat<RayLanes>(gamma_bound(5));
            const RayLanes delta_z = gamma3 * max_zt;
            const RayLanes delta_x = gamma5 * (max_xt + max_zt);
            const RayLanes delta_y = gamma5 * (max_yt + max_zt);
            const RayLanes delta_e =
                lanes_splat<RayLanes>(2.0f) * ((gamma2 * max_xt * max_yt + delta_y * max_xt) + delta_x * max_yt);
            const RayLanes max_e = lanes_abs_max(e0, e1, e2);
            const RayLanes delta_t =
                3.0f * ((gamma3 * max_e * max_zt + delta_e * max_zt) + delta_z * max_e) * lanes_abs(inv_det);
            hit_lanes &= ~lane_bits(lanes_le(t, delta_t));
            hits.t = t;
            hits.u = e1 * inv_det;
            hits.v = e2 * inv_det;
        }
    }
    // Rare: an edge function of exactly zero, decided in double by the scalar test.
    for (uint32_t lanes = exact_zero; lanes != 0; lanes &= lanes - 1) {
        const uint32_t lane = uint32_t(__builtin_ctz(lanes));
        TriangleHit hit;
        if (!intersect_triangle(s.ray(first + lane), tri.vertex(0, lane), tri.vertex(1, lane), tri.vertex(2, lane),
                                p.t_cull[first + lane], hit))
            continue;
        hits.t[lane] = hit.t, hits.u[lane] = hit.u, hits.v[lane] = hit.v;
        hit_lanes |= 1u << lane;
    }
    return hit_lanes;
}
