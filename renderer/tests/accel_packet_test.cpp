// Packet queries (Accelerator::intersect / visibility over spans): the same
// answers as the single-ray queries, ray for ray and bit for bit (t, u, v),
// on every SIMD path, whether a leaf tests a packet's rays one by one or
// eight rays against each triangle, for
// packets the interval traversal takes (camera cones, orthographic beams) and
// for those it hands back to single rays; through edges and vertices without
// leaks; against brute force on a sample mesh.
#include <gtest/gtest.h>

#include <random>

#include "geometry/accel.h"
#include "geometry/brute_force.h"
#include "geometry/spawn.h"
#include "geometry/surface.h"
#include "integrator/camera.h"
#include "integrator/default_camera.h"
#include "integrator/sampling.h"
#include "test_meshes.h"

namespace rt {
namespace {

using namespace rt::testing;

std::vector<SimdPath> paths() {
    std::vector<SimdPath> supported;
    for (SimdPath path : kSimdPaths)
        if (cpu_supports(path)) supported.push_back(path);
    return supported;
}

// A camera's 4 x 4 pixel blocks over a size x size image: each a packet.
std::vector<std::vector<Ray>> camera_packets(const Scene& scene, uint32_t size) {
    const ViewCamera camera(default_camera(scene), size, size);
    std::vector<std::vector<Ray>> packets;
    for (uint32_t by = 0; by < size; by += 4)
        for (uint32_t bx = 0; bx < size; bx += 4) {
            std::vector<Ray>& packet = packets.emplace_back();
            for (uint32_t y = by; y < by + 4; ++y)
                for (uint32_t x = bx; x < bx + 4; ++x) packet.push_back(camera.generate_ray(x + 0.5f, y + 0.5f));
        }
    return packets;
}

// Packets answer as their rays do one by one: the same triangle, distance
// and barycentrics, bit for bit, ties included (the lower triangle number
// wins at equal distances, whatever order the traversals take). Returns
// whether the packet traversal took them for closest hits; it takes any
// packet the intervals bound for visibility too.
bool expect_same_answers(const Accelerator& accel, const std::vector<Ray>& packet, const std::string& what) {
    std::vector<Hit> hits(packet.size());
    std::vector<float> visibility(packet.size());
    const bool as_packet = accel.intersect(packet, hits);
    const bool visibility_as_packet = accel.visibility(packet, visibility);
    if (as_packet) {
        EXPECT_TRUE(visibility_as_packet) << what;
    }
    for (size_t i = 0; i < packet.size(); ++i) {
        Hit single;
        const bool found = accel.intersect(packet[i], single);
        EXPECT_EQ(hits[i].found(), found) << what << " ray " << i;
        EXPECT_EQ(hits[i].primitive, single.primitive) << what << " ray " << i;
        EXPECT_EQ(hits[i].t, single.t) << what << " ray " << i;
        EXPECT_EQ(hits[i].u, single.u) << what << " ray " << i;
        EXPECT_EQ(hits[i].v, single.v) << what << " ray " << i;
        EXPECT_EQ(visibility[i], accel.visibility(packet[i])) << what << " ray " << i;
    }
    return as_packet;
}

TEST(AccelPacket, CameraPacketsAnswerAsSingleRays) {
    const Scene scene = sample_scene("bunny.glb");
    for (SimdPath path : paths()) {
        const Accelerator accel(scene, 1, path);
        size_t hit_rays = 0, as_packets = 0;
        const std::vector<std::vector<Ray>> packets = camera_packets(scene, 96);
        for (const std::vector<Ray>& packet : packets) {
            as_packets += expect_same_answers(accel, packet, to_string(path));
            for (const Ray& ray : packet) {
                Hit hit;
                hit_rays += accel.intersect(ray, hit);
            }
        }
        EXPECT_GT(hit_rays, 96u * 96u / 8) << "the bunny fills part of the view";
        // All but the packets straddling the view's centre lines.
        EXPECT_GT(as_packets, packets.size() * 9 / 10);
    }
}

TEST(AccelPacket, PacketsWhoseRaysShearAlongDifferentAxesAnswerAsSingleRays) {
    // Seen along the diagonal of x and y, the rays' largest direction axis,
    // along which the watertight test shears, flips across the view: the
    // packets on that line test each shear class's rays a triangle at a time.
    const Scene scene = sample_scene("bunny.glb");
    const Bounds3 box = scene.bounds();
    const vec3 eye = box.center() + 1.8f * glm::length(box.extent()) * glm::normalize(vec3(1.0f, 1.0f, 0.3f));
    Camera camera;
    for (float v : {eye.x, eye.y, eye.z}) camera.add_position(v);
    for (float v : {box.center().x, box.center().y, box.center().z}) camera.add_target(v);
    for (float v : {0.0f, 0.0f, 1.0f}) camera.add_up(v);
    camera.set_fov_y(40.0f);
    // 126 pixels wide: the flip falls inside a block, not between two.
    const ViewCamera view(camera, 126, 126);
    for (SimdPath path : paths()) {
        const Accelerator accel(scene, 1, path);
        size_t mixed = 0, mixed_as_packets = 0, mixed_hits = 0;
        for (uint32_t by = 0; by + 4 <= 126; by += 4)
            for (uint32_t bx = 0; bx + 4 <= 126; bx += 4) {
                std::vector<Ray> packet;
                for (uint32_t y = by; y < by + 4; ++y)
                    for (uint32_t x = bx; x < bx + 4; ++x) packet.push_back(view.generate_ray(x + 0.5f, y + 0.5f));
                bool on_x = false, on_y = false;
                for (const Ray& ray : packet) (max_dimension(glm::abs(ray.direction)) == 0 ? on_x : on_y) = true;
                if (!on_x || !on_y) continue;
                ++mixed;
                mixed_as_packets += expect_same_answers(accel, packet, to_string(path));
                for (const Ray& ray : packet) {
                    Hit hit;
                    mixed_hits += accel.intersect(ray, hit);
                }
            }
        EXPECT_GT(mixed, 20u) << "the diagonal crosses the view";
        EXPECT_GT(mixed_as_packets, mixed * 3 / 4) << to_string(path) << ": most are packets all the same";
        EXPECT_GT(mixed_hits, mixed * 4) << "and many of their rays hit the bunny";
    }
}

TEST(AccelPacket, PacketsAgreeWithBruteForceOnTheDragon) {
    const Scene scene = sample_scene("dragon_4.glb");
    const Accelerator accel(scene);
    size_t checked = 0;
    for (const std::vector<Ray>& packet : camera_packets(scene, 48)) {
        std::vector<Hit> hits(packet.size());
        accel.intersect(packet, hits);
        for (size_t i = 0; i < packet.size(); ++i) {
            const Hit expected = brute_force_hit(scene, packet[i]);
            ASSERT_EQ(hits[i].found(), expected.found()) << "ray " << checked;
            if (expected.found()) {
                EXPECT_EQ(hits[i].t, expected.t) << "ray " << checked;
            }
            ++checked;
        }
    }
    EXPECT_EQ(checked, 48u * 48u);
}

TEST(AccelPacket, OrthographicBeamsAndShortRaysAnswerAsSingleRays) {
    const Scene scene = icosphere(4);
    for (SimdPath path : paths()) {
        const Accelerator accel(scene, 1, path);
        for (float x0 = -1.2f; x0 < 1.2f; x0 += 0.3f) {
            std::vector<Ray> packet;
            for (int k = 0; k < 16; ++k) {
                const vec3 origin(x0 + 0.05f * float(k % 4), -0.9f + 0.11f * float(k), 3.0f);
                // Every other ray stops short of the sphere or just inside it.
                const float t_max = k % 3 == 0 ? 1.5f : k % 3 == 1 ? 2.2f : kInfinity;
                packet.push_back({origin, normalize(vec3(0.1f, 0.05f, -1.0f)), t_max});
            }
            EXPECT_TRUE(expect_same_answers(accel, packet, to_string(path))) << "a beam is a packet";
        }
    }
}

TEST(AccelPacket, IncoherentPacketsGoRayByRay) {
    // Random origins and directions of every sign: not a packet the interval
    // test bounds, so each ray is traced alone, with the same answers.
    const Scene scene = icosphere(3);
    const std::vector<Ray> rays = random_rays(scene, 16 * 20, 7);
    const Accelerator accel(scene);
    for (size_t first = 0; first < rays.size(); first += 16)
        EXPECT_FALSE(expect_same_answers(accel, std::vector<Ray>(rays.begin() + first, rays.begin() + first + 16),
                                         "random"));
    // Lone rays, and packets of any size up to 16.
    for (size_t n : {size_t(0), size_t(1), size_t(5), size_t(16)})
        expect_same_answers(accel, std::vector<Ray>(rays.begin(), rays.begin() + n), "size " + std::to_string(n));
}

TEST(AccelPacket, CameraPacketsThroughEdgesAndVerticesDoNotLeak) {
    // One packet per triangle from a point inside the closed mesh, aimed at
    // the triangle's corners and at points along its edges, which it shares.
    const Scene scene = icosphere(3);
    const vec3 inside(0.1f, -0.2f, 0.3f);
    for (SimdPath path : paths()) {
        const Accelerator accel(scene, 1, path);
        int leaks = 0, packets = 0;
        for (const uvec3& t : scene.triangles) {
            std::vector<Ray> packet;
            for (int k = 0; k < 3; ++k)
                for (float s : {0.0f, 0.25f, 0.5f, 0.75f, 1.0f / 3.0f})
                    packet.push_back({inside, glm::mix(scene.positions[t[k]], scene.positions[t[(k + 1) % 3]], s) - inside,
                                      kInfinity});
            std::vector<Hit> hits(packet.size());
            std::vector<float> visibility(packet.size());
            // The rays take one leaf together, eight against a triangle at a
            // time, and answer as their single rays: at a corner too, where
            // several leaves' triangles meet them at distances an ulp apart.
            expect_same_answers(accel, packet, to_string(path));
            packets += accel.intersect(packet, hits);
            accel.visibility(packet, visibility);
            for (size_t i = 0; i < packet.size(); ++i) leaks += !hits[i].found() + (visibility[i] != 0.0f);
        }
        EXPECT_EQ(leaks, 0) << to_string(path);
        // Triangles whose rays run both ways along some axis go ray by ray.
        EXPECT_GT(packets, int(scene.triangles.size()) / 3) << "many triangles' rays make packets";
    }
}

TEST(AccelPacket, CameraPacketsInLeavesWiderThanThemAnswerAsSingleRays) {
    // The Cornell box's leaves hold parts of walls far apart, each far wider
    // than a packet: a leaf's triangles whose own boxes no ray of the packet
    // enters are skipped (packet_triangle_cull.inl), and the answers must
    // not change for it.
    const Scene scene = sample_scene("cornell.obj");
    for (SimdPath path : paths()) {
        const Accelerator accel(scene, 1, path);
        size_t as_packets = 0;
        const std::vector<std::vector<Ray>> packets = camera_packets(scene, 64);
        for (const std::vector<Ray>& packet : packets)
            as_packets += expect_same_answers(accel, packet, to_string(path));
        EXPECT_GT(as_packets, packets.size() * 9 / 10) << to_string(path);
    }
}

TEST(AccelPacket, PacketsThroughTheEdgesOfFlatBoxesDoNotLeak) {
    // A flat grid seen from close above: its leaves are wide to the packets,
    // and each triangle's box is flat. Each packet is aimed at one square's
    // corners and at points along its edges and its diagonal, which its
    // triangles share with their neighbours: there the rays meet the boxes
    // at their rims, where a box test that lost a rounding error would cull
    // the triangle they hit.
    const Scene scene = grid(16);
    const vec3 eye(4.3f, 4.2f, 3.0f);
    for (SimdPath path : paths()) {
        const Accelerator accel(scene, 1, path);
        int leaks = 0, as_packets = 0, packets = 0;
        // The squares ahead of the eye along x and y, so that every ray of a
        // packet runs the same way along each axis.
        for (uint32_t y = 5; y < 10; ++y)
            for (uint32_t x = 5; x < 10; ++x) {
                std::vector<Ray> packet;
                for (float s : {0.0f, 0.25f, 0.5f, 1.0f / 3.0f, 1.0f}) {
                    for (const vec2 point : {vec2(s, 0.0f), vec2(0.0f, s), vec2(s, 1.0f), vec2(1.0f, s)})
                        packet.push_back({eye, vec3(float(x) + point.x, float(y) + point.y, 0.0f) - eye, kInfinity});
                    packet.push_back({eye, vec3(float(x) + s, float(y) + s, 0.0f) - eye, kInfinity});
                }
                packet.resize(16);
                std::vector<Hit> hits(packet.size());
                expect_same_answers(accel, packet, to_string(path));
                as_packets += accel.intersect(packet, hits);
                ++packets;
                for (const Hit& hit : hits) leaks += !hit.found();
            }
        EXPECT_EQ(leaks, 0) << to_string(path);
        EXPECT_EQ(as_packets, packets) << to_string(path) << ": every packet is traced as one";
    }
}

// Shadow rays from the hits of one camera packet towards one point: each
// packet's visibility, and whether it was traced as a packet.
struct ShadowPackets {
    std::vector<std::vector<Ray>> packets;
};

ShadowPackets shadow_packets(const Accelerator& accel, uint32_t size, vec3 light) {
    ShadowPackets shadows;
    for (const std::vector<Ray>& camera : camera_packets(accel.scene(), size)) {
        std::vector<Ray>& packet = shadows.packets.emplace_back();
        for (const Ray& ray : camera) {
            Hit hit;
            if (!accel.intersect(ray, hit)) continue;
            const SurfaceHit s = surface_at(accel.scene(), ray, hit);
            packet.push_back(spawn_ray_to(s.p, s.p_error, s.ng, light, s.time));
        }
    }
    return shadows;
}

TEST(AccelPacket, MovingCameraPacketsAnswerAsSingleRaysEachAtItsTime) {
    // The bunny moving by a tenth of its width; each ray of a packet at its
    // own time, as a time-sampled render's pixels take theirs.
    Scene scene = sample_scene("bunny.glb");
    const float shift = 0.1f * scene.bounds().extent().x;
    for (const vec3& p : scene.positions) scene.positions_close.push_back(p + vec3(shift, 0.0f, 0.0f));
    scene.normals_close = scene.normals;
    ASSERT_TRUE(scene.moving());
    for (SimdPath path : paths()) {
        const Accelerator accel(scene, 1, path);
        ASSERT_TRUE(accel.packets_serve());
        size_t as_packets = 0, hit_rays = 0, packets = 0;
        uint32_t key = 0;
        for (std::vector<Ray> packet : camera_packets(scene, 96)) {
            for (Ray& ray : packet) ray.time = unit_float(hash_combine(key++, 7u));
            std::vector<Hit> hits(packet.size());
            as_packets += accel.intersect(packet, hits);
            ++packets;
            for (size_t i = 0; i < packet.size(); ++i) {
                Hit single;
                hit_rays += accel.intersect(packet[i], single);
                EXPECT_EQ(hits[i].primitive, single.primitive) << to_string(path) << " ray " << i;
                EXPECT_EQ(hits[i].t, single.t) << to_string(path) << " ray " << i;
                EXPECT_EQ(hits[i].u, single.u) << to_string(path) << " ray " << i;
                EXPECT_EQ(hits[i].v, single.v) << to_string(path) << " ray " << i;
            }
            std::vector<float> visibility(packet.size());
            accel.visibility(packet, visibility);
            for (size_t i = 0; i < packet.size(); ++i)
                EXPECT_EQ(visibility[i], accel.visibility(packet[i])) << to_string(path) << " ray " << i;
        }
        EXPECT_GT(hit_rays, 96u * 96u / 8) << "the bunny fills part of the view";
        EXPECT_GT(as_packets, packets * 9 / 10) << to_string(path);
        // Shadow rays towards one light, each at its own time: the pyramid
        // against boxes swept over the packet's times.
        const Bounds3 box = scene.bounds();
        const vec3 light(box.center().x + 0.3f * box.extent().x, box.max.y + 2.0f * box.extent().y, box.center().z);
        size_t shadow_packets_served = 0, shadow_packets_count = 0, blocked = 0;
        for (std::vector<Ray> packet : shadow_packets(accel, 128, light).packets) {
            if (packet.size() < 2) continue;
            for (Ray& ray : packet) ray.time = unit_float(hash_combine(key++, 7u));
            std::vector<float> visibility(packet.size());
            shadow_packets_served += accel.visibility(packet, visibility);
            ++shadow_packets_count;
            for (size_t i = 0; i < packet.size(); ++i) {
                EXPECT_EQ(visibility[i], accel.visibility(packet[i])) << to_string(path) << " shadow ray " << i;
                blocked += visibility[i] == 0.0f;
            }
        }
        EXPECT_GT(blocked, 0u);
        EXPECT_GT(shadow_packets_served, shadow_packets_count / 2) << to_string(path);
    }
}

TEST(AccelPacket, ShadowPacketsTowardsOneLightAnswerAsSingleRays) {
    // Rays from many points to one: each node culled by the box around the
    // segments, then tested ray by ray (the single-ray traversal taking over
    // where few rays remain), so each ray meets the leaves its own box test
    // enters.
    const Scene scene = sample_scene("bunny.glb");
    const Bounds3 box = scene.bounds();
    const vec3 light(box.center().x + 0.3f * box.extent().x, box.max.y + 2.0f * box.extent().y, box.center().z);
    for (SimdPath path : paths()) {
        const Accelerator accel(scene, 1, path);
        size_t as_packets = 0, blocked = 0, rays = 0, with_rays = 0;
        for (const std::vector<Ray>& packet : shadow_packets(accel, 128, light).packets) {
            if (packet.size() < 2) continue;
            ++with_rays;
            std::vector<float> visibility(packet.size());
            as_packets += accel.visibility(packet, visibility);
            for (size_t i = 0; i < packet.size(); ++i) {
                EXPECT_EQ(visibility[i], accel.visibility(packet[i])) << to_string(path) << " ray " << rays;
                blocked += visibility[i] == 0.0f;
                ++rays;
            }
        }
        EXPECT_GT(blocked, rays / 20) << "the bunny shadows part of itself and the ground";
        EXPECT_LT(blocked, rays) << "and the light sees the rest";
        EXPECT_EQ(as_packets, with_rays) << to_string(path) << ": every such packet takes the packet traversal";
    }
}

TEST(AccelPacket, LightSamplesFromOnePointAnswerAsSingleRays) {
    // A spherical light's 16 samples from one hit, as the integrator traces
    // them: one origin, nearby directions.
    const Scene scene = sample_scene("bunny.glb");
    const Bounds3 box = scene.bounds();
    const vec3 light(box.center().x + 0.3f * box.extent().x, box.max.y + 2.0f * box.extent().y, box.center().z);
    const float radius = 0.03f * box.extent().x;  // small enough to be one thin pyramid
    for (SimdPath path : paths()) {
        const Accelerator accel(scene, 1, path);
        size_t as_packets = 0, packets = 0, blocked = 0, partly = 0, rays = 0;
        uint32_t key = 0;
        for (const std::vector<Ray>& camera : camera_packets(scene, 64)) {
            Hit hit;
            if (!accel.intersect(camera[5], hit)) continue;
            const SurfaceHit s = surface_at(scene, camera[5], hit);
            std::vector<Ray> packet;
            for (uint32_t i = 0; i < 16; ++i, ++key) {
                const float k = float(key);
                const vec3 u = glm::normalize(vec3(std::sin(1.7f * k), std::cos(2.3f * k), std::sin(0.9f * k + 1.0f)));
                packet.push_back(spawn_ray_to(s.p, s.p_error, s.ng, light + radius * u, s.time));
            }
            std::vector<float> visibility(packet.size());
            as_packets += accel.visibility(packet, visibility);
            ++packets;
            size_t here = 0;
            for (size_t i = 0; i < packet.size(); ++i) {
                EXPECT_EQ(visibility[i], accel.visibility(packet[i])) << to_string(path) << " ray " << rays;
                here += visibility[i] == 0.0f;
                ++rays;
            }
            blocked += here;
            partly += here > 0 && here < packet.size();
        }
        EXPECT_GT(blocked, rays / 20) << "the bunny shadows part of itself and the ground";
        EXPECT_LT(blocked, rays) << "and the light sees the rest";
        EXPECT_GT(partly, 0u) << "some points are in penumbra";
        EXPECT_GT(as_packets, packets * 9 / 10) << to_string(path) << ": rays from one point are one packet";
    }
}

// A uniformly distributed unit vector, from two hashes of `key`.
vec3 sphere_direction(uint32_t key, uint32_t salt) {
    const float z = 1.0f - 2.0f * unit_float(hash_combine(key, salt));
    const float phi = 6.2831853f * unit_float(hash_combine(key, salt + 1));
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    return {r * std::cos(phi), r * std::sin(phi), z};
}

// A packet's visibility ray by ray, and whether the packet traversal took it.
bool expect_same_visibility(const Accelerator& accel, const std::vector<Ray>& packet, size_t& blocked,
                            const std::string& what) {
    std::vector<float> visibility(packet.size());
    const bool as_packet = accel.visibility(packet, visibility);
    for (size_t i = 0; i < packet.size(); ++i) {
        EXPECT_EQ(visibility[i], accel.visibility(packet[i])) << what << " ray " << i;
        blocked += visibility[i] == 0.0f;
    }
    return as_packet;
}

TEST(AccelPacket, ShadowPacketsOfAnyShapeAnswerAsSingleRays) {
    // Packets no interval test bounds, each node's rays tested one by one:
    // a light as large as its distance, whose samples from one point straddle
    // the axes; rays to infinity, which no box of segments bounds, from one
    // point (the intervals cull) or from many in any direction (nothing does).
    const Scene scene = sample_scene("bunny.glb");
    const Bounds3 box = scene.bounds();
    const vec3 light(box.center().x, box.max.y + 0.5f * box.extent().y, box.center().z);
    const float radius = 0.5f * box.extent().y;
    for (SimdPath path : paths()) {
        const Accelerator accel(scene, 1, path);
        size_t as_packets = 0, packets = 0, blocked = 0, rays = 0;
        uint32_t key = 0;
        for (const std::vector<Ray>& camera : camera_packets(scene, 48)) {
            Hit hit;
            if (!accel.intersect(camera[5], hit)) continue;
            const SurfaceHit s = surface_at(scene, camera[5], hit);
            std::vector<Ray> wide, far, scattered;
            for (uint32_t i = 0; i < 16; ++i, ++key) {
                const vec3 u = sphere_direction(key, 1u);
                wide.push_back(spawn_ray_to(s.p, s.p_error, s.ng, light + radius * u, s.time));
                Ray to_infinity = wide.back();
                to_infinity.t_max = kInfinity;
                far.push_back(to_infinity);
                const vec3 w = sphere_direction(key, 3u);
                scattered.push_back({camera[i].at(hit.t * (0.5f + 0.5f * unit_float(hash_combine(key, 5u)))), w,
                                     kInfinity});
            }
            for (const std::vector<Ray>* packet : {&wide, &far, &scattered}) {
                as_packets += expect_same_visibility(accel, *packet, blocked, to_string(path));
                ++packets;
                rays += packet->size();
            }
        }
        EXPECT_GT(blocked, rays / 20) << "the bunny and the ground stop some of them";
        EXPECT_LT(blocked, rays - rays / 20) << "and let others pass";
        EXPECT_EQ(as_packets, packets) << to_string(path) << ": each takes the packet traversal";
    }
}

TEST(AccelPacket, ShadowPacketsThroughEdgesAndVerticesDoNotLeak) {
    // From just inside a closed mesh towards a far light, each packet's rays
    // cross one triangle's corners and edges, which it shares: every ray is
    // blocked, through the by-triangle leaf test as through single rays.
    const Scene scene = icosphere(3);
    const vec3 light(0.3f, 0.2f, 40.0f);
    for (SimdPath path : paths()) {
        const Accelerator accel(scene, 1, path);
        int leaks = 0, packets = 0;
        for (const uvec3& t : scene.triangles) {
            // Triangles that face the light, so that no ray grazes the mesh.
            const vec3 centre = (scene.positions[t[0]] + scene.positions[t[1]] + scene.positions[t[2]]) / 3.0f;
            if (glm::dot(normalize(light - centre), normalize(centre)) < 0.5f) continue;
            std::vector<Ray> packet;
            for (int k = 0; k < 3; ++k)
                for (float s : {0.0f, 0.25f, 0.5f, 0.75f, 1.0f / 3.0f}) {
                    const vec3 on_edge = glm::mix(scene.positions[t[k]], scene.positions[t[(k + 1) % 3]], s);
                    const vec3 origin = on_edge + 0.1f * normalize(on_edge - light);
                    packet.push_back({origin, normalize(light - origin), glm::length(light - origin)});
                }
            std::vector<float> visibility(packet.size());
            packets += accel.visibility(packet, visibility);
            for (size_t i = 0; i < packet.size(); ++i) {
                leaks += visibility[i] != 0.0f;
                EXPECT_EQ(visibility[i], accel.visibility(packet[i])) << to_string(path);
            }
        }
        EXPECT_EQ(leaks, 0) << to_string(path);
        EXPECT_GT(packets, int(scene.triangles.size()) / 8) << to_string(path) << ": the far light's packets";
    }
}

TEST(AccelPacket, SpheresInFrontOfTrianglesAreFound) {
    Scene scene = grid(4);
    scene.spheres.push_back({vec3(2.0f, 2.0f, 0.5f), 0.3f, 0});
    scene.materials.resize(1);
    const Accelerator accel(scene);
    std::vector<Ray> packet;
    for (int k = 0; k < 16; ++k)
        packet.push_back({vec3(1.5f, 1.5f, 5.0f), normalize(vec3(0.1f + 0.01f * float(k % 4),
                                                                 0.1f + 0.01f * float(k / 4), -1.0f)), kInfinity});
    EXPECT_TRUE(expect_same_answers(accel, packet, "spheres"));
    std::vector<Hit> hits(16);
    accel.intersect(packet, hits);
    EXPECT_EQ(hits[0].primitive, uint32_t(scene.triangles.size())) << "the sphere, before the grid";
}

TEST(AccelPacket, MismatchedOrOversizedSpansAreRefused) {
    const Scene scene = icosphere(1);
    const Accelerator accel(scene);
    std::vector<Ray> rays(17);
    std::vector<Hit> hits(17);
    std::vector<float> visibility(16);
    EXPECT_THROW(accel.intersect(rays, hits), std::invalid_argument);
    EXPECT_THROW(accel.visibility(std::span(rays).first(16), std::span(visibility).first(15)), std::invalid_argument);
}

}  // namespace
}  // namespace rt
