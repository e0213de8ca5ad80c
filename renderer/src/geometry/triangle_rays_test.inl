// One triangle against a register of a packet's rays (8 or 16) at once: the watertight test
// (triangle.h) with the SIMD lanes over rays instead of over triangles, as
// Embree's packet kernels test one triangle against a whole packet. Lane by
// lane it performs the scalar test's float operations in the same order, and
// hands the lanes where an edge function is exactly zero to the scalar test,
// so each ray's verdict, t, u and v equal its single-ray test's bit for bit.
//
// A test's rays share their shear axes (kx, ky, kz): the vertex coordinates
// then enter every lane from the same rows. A camera's 4 x 4 pixel block
// almost always does; shadow rays towards a light seen at about 45 degrees
// split between two, and each class takes its own tests.
//
// Compiled once per SIMD path after packet_lanes.inl,
// inside the ISA namespace.

// The rays that shear along the same axes: WatertightRay's kz, the
// direction's largest axis, and kx and ky, swapped for a negative d[kz].
struct ShearClass {
    int kx, ky, kz;
    uint32_t rays;
};

// Each ray's shear (WatertightRay's), structure of arrays, and its class.
struct PacketShear {
    const bvh::PacketRays& p;
    // Up to six classes (three axes, two signs), in no particular order.
    ShearClass classes[6];
    uint32_t class_count = 0;
    alignas(64) float sx[bvh::kPacketSize];
    alignas(64) float sy[bvh::kPacketSize];
    alignas(64) float sz[bvh::kPacketSize];

    // WatertightRay's choice of axes (max_dimension's comparisons) and its
    // shear, lane by lane: the same divisions, so the same numbers.
    explicit PacketShear(const bvh::PacketRays& packet) : p(packet) {
        uint32_t by_axes[3][2] = {};  // [kz][d[kz] < 0]: the rays
        for (uint32_t first = 0; first < bvh::kPacketSize; first += kRayLanes) {
            const RayLanes dx = lanes_load<RayLanes>(p.direction[0] + first),
                           dy = lanes_load<RayLanes>(p.direction[1] + first),
                           dz = lanes_load<RayLanes>(p.direction[2] + first);
            const RayLanes x = lanes_abs(dx), y = lanes_abs(dy), z = lanes_abs(dz);
            const RayMask x_over_y = x > y, on_x = x_over_y & (x > z), on_y = ~x_over_y & (y > z);
            const RayLanes d_kz = on_x ? dx : on_y ? dy : dz;
            const RayMask negative = d_kz < lanes_splat<RayLanes>(0.0f);
            // kx and ky follow kz cyclically (x: y, z; y: z, x; z: x, y),
            // swapped where d[kz] < 0.
            const RayLanes next = on_x ? dy : on_y ? dz : dx, after = on_x ? dz : on_y ? dx : dy;
            lanes_store(sx + first, (negative ? after : next) / d_kz);
            lanes_store(sy + first, (negative ? next : after) / d_kz);
            // 1 / d[kz] is the reciprocal load_packet divided already.
            const RayLanes inv_x = lanes_load<RayLanes>(p.inv_direction[0] + first),
                           inv_y = lanes_load<RayLanes>(p.inv_direction[1] + first),
                           inv_z = lanes_load<RayLanes>(p.inv_direction[2] + first);
            lanes_store(sz + first, on_x ? inv_x : on_y ? inv_y : inv_z);
            const uint32_t x_bits = lanes_bits(on_x), y_bits = lanes_bits(on_y);
            const uint32_t axis_bits[3] = {x_bits, y_bits, ~(x_bits | y_bits) & kRayLaneBits};
            const uint32_t negative_bits = lanes_bits(negative);
            for (int axis = 0; axis < 3; ++axis) {
                by_axes[axis][0] |= (axis_bits[axis] & ~negative_bits) << first;
                by_axes[axis][1] |= (axis_bits[axis] & negative_bits) << first;
            }
        }
        const uint32_t lanes = (1u << p.count) - 1;
        for (int kz = 0; kz < 3; ++kz)
            for (int negative = 0; negative < 2; ++negative) {
                const uint32_t rays = by_axes[kz][negative] & lanes;
                if (rays == 0) continue;
                const int next = (kz + 1) % 3, after = (next + 1) % 3;
                classes[class_count++] = {negative ? after : next, negative ? next : after, kz, rays};
            }
    }

    // Ray i's WatertightRay, as its single-ray query makes it.
    WatertightRay ray(uint32_t i) const {
        WatertightRay r;
        r.origin = {p.origin[0][i], p.origin[1][i], p.origin[2][i]};
        const ShearClass* c = classes;
        while (!(c->rays >> i & 1)) ++c;
        r.kx = c->kx, r.ky = c->ky, r.kz = c->kz;
        r.sx = sx[i], r.sy = sy[i], r.sz = sz[i];
        return r;
    }
};

struct RaysHits {
    RayLanes t, u, v;
};

// A triangle's vertices as every lane sees them: one triangle for all rays,
// or, in a moving scene, each ray's own, the triangle at its time.
// The shear's axes vary from packet to packet, so coordinates are read by
// index from the block's rows: a vec3's operator[] took a compare and branch
// per coordinate.
struct SharedTriangle {
    const float* v;  // a block's v[0][0] + its lane: vertex k's `axis` coordinate at (3k + axis) rows on
    [[gnu::always_inline]] float at(int k, int axis) const { return v[(3 * k + axis) * bvh::kBlockWidth]; }
    [[gnu::always_inline]] RayLanes coordinate(int k, int axis) const { return lanes_splat<RayLanes>(at(k, axis)); }
    vec3 vertex(int k, uint32_t) const { return {at(k, 0), at(k, 1), at(k, 2)}; }
};
struct LaneTriangles {
    RayLanes c[3][3];  // [vertex][axis]
    [[gnu::always_inline]] RayLanes coordinate(int k, int axis) const { return c[k][axis]; }
    vec3 vertex(int k, uint32_t lane) const { return {c[k][0][lane], c[k][1][lane], c[k][2][lane]}; }
};

// Bit i set: ray first + i hits the triangle with 0 < t < t_cull[i]; hits.t/u/v
// lane i then hold its hit. `rays` (kRayLanes bits, all of class `axes`) says
// which lanes to test; the others answer nothing. `tri`: a SharedTriangle or
// LaneTriangles.
// kSharedOrigin: every ray starts at the same point (PacketRays::shared_origin),
// and the triangle is one for all lanes: each vertex coordinate less the
// origin is then one subtraction, not one per lane.
template <bool kSharedOrigin, typename Triangle>
[[gnu::always_inline]] inline uint32_t intersect_triangle_rays(const bvh::PacketRays& p, const PacketShear& s,
                                                               ShearClass axes, uint32_t first, uint32_t rays,
                                                               const Triangle& tri, RaysHits& hits) {
    static_assert(!kSharedOrigin || std::is_same_v<Triangle, SharedTriangle>);
    const int kx = axes.kx, ky = axes.ky, kz = axes.kz;
    // Vertex k's coordinate along `axis`, relative to each ray's origin.
    // (GCC's own attribute: the standard one does not reach a lambda's operator().)
    const auto from_origin = [&](int k, int axis) __attribute__((always_inline)) {
        if constexpr (kSharedOrigin)
            return lanes_splat<RayLanes>(tri.at(k, axis) - p.origin[axis][0]);
        else
            return tri.coordinate(k, axis) - lanes_load<RayLanes>(p.origin[axis] + first);
    };
    const RayLanes sx = lanes_load<RayLanes>(s.sx + first), sy = lanes_load<RayLanes>(s.sy + first);
    const RayLanes a_z = from_origin(0, kz), b_z = from_origin(1, kz), c_z = from_origin(2, kz);
    const RayLanes ax = from_origin(0, kx) - sx * a_z;
    const RayLanes ay = from_origin(0, ky) - sy * a_z;
    const RayLanes bx = from_origin(1, kx) - sx * b_z;
    const RayLanes by = from_origin(1, ky) - sy * b_z;
    const RayLanes cx = from_origin(2, kx) - sx * c_z;
    const RayLanes cy = from_origin(2, ky) - sy * c_z;

    const RayLanes e0 = cx * by - cy * bx;
    const RayLanes e1 = ax * cy - ay * cx;
    const RayLanes e2 = bx * ay - by * ax;

    const RayLanes zero = lanes_splat<RayLanes>(0.0f);
    const uint32_t exact_zero = lane_bits(lanes_eq(e0, zero) | lanes_eq(e1, zero) | lanes_eq(e2, zero)) & rays;
    // Some edge function below 0 and some above: their sign bits differ,
    // one bitwise operation for all three where six comparisons stood. The
    // lanes where one is 0 (of either sign) go to the scalar test below.
    const RayMask s0 = lanes_bitcast<RayMask>(e0), s1 = lanes_bitcast<RayMask>(e1), s2 = lanes_bitcast<RayMask>(e2);
    LaneBits reject = lanes_sign_bits((s0 | s1 | s2) & ~(s0 & s1 & s2));
    // Most rays that reach a leaf miss most of its triangles: leave before
    // det, the division and the error bound.
    const uint32_t candidates = ~lane_bits(reject) & rays & ~exact_zero;
    uint32_t hit_lanes = 0;
    if (candidates != 0) {
        // Not 0 for any candidate (intersect_block says why).
        const RayLanes det = (e0 + e1) + e2;
        const RayLanes sz = lanes_load<RayLanes>(s.sz + first);
        const RayLanes t_max = lanes_load<RayLanes>(p.t_cull + first);
        const RayLanes az = sz * a_z, bz = sz * b_z, cz = sz * c_z;
        const RayLanes t_scaled = (e0 * az + e1 * bz) + e2 * cz;
        // 0 < t_scaled / det < t_max, as t_scaled and t_max * det with det's
        // sign taken off both (det is not 0 here): negation is exact, so the
        // comparisons are the scalar test's two cases, bit for bit.
        const RayMask det_sign = lanes_bitcast<RayMask>(det) & int32_t(0x80000000);
        const RayLanes t_unsigned = lanes_bitcast<RayLanes>(lanes_bitcast<RayMask>(t_scaled) ^ det_sign);
        const RayLanes t_max_unsigned = lanes_bitcast<RayLanes>(lanes_bitcast<RayMask>(t_max * det) ^ det_sign);
        reject |= lanes_le(t_unsigned, zero) | lanes_gt(t_unsigned, t_max_unsigned);

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
