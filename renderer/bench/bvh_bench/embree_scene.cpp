#include "embree_scene.h"

#include <unistd.h>

#include <xmmintrin.h>
#include <emmintrin.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <sstream>
#include <stdexcept>

namespace rt::bench {
namespace {

// The number printed after `key` in `line` ("sah =   3.662": key "sah ="), or 0.
double number_after(const std::string& line, const std::string& key) {
    const size_t at = line.find(key);
    return at == std::string::npos ? 0.0 : std::strtod(line.c_str() + at + key.size(), nullptr);
}

std::string word_after(const std::string& line, const std::string& key) {
    const size_t at = line.find(key);
    if (at == std::string::npos) return {};
    std::istringstream rest(line.substr(at + key.size()));
    std::string word;
    rest >> word;
    return word;
}

// "  getAABBNodes     : sah = ..." -> "getAABBNodes".
std::string section_of(const std::string& line) {
    const size_t colon = line.find(':');
    if (colon == std::string::npos) return {};
    std::istringstream head(line.substr(0, colon));
    std::string name;
    head >> name;
    return name;
}

// One line of BVHNStatistics<N>::str() or of the allocator's print, into `bvh`.
void parse_statistics_line(const std::string& line, EmbreeBvhStats& bvh) {
    const std::string section = section_of(line);
    if (line.find("primitives =") != std::string::npos) {
        bvh.primitives = size_t(number_after(line, "primitives ="));
        bvh.depth = unsigned(number_after(line, "depth ="));
    } else if (section == "total" && line.find("sah =") != std::string::npos) {
        bvh.sah = number_after(line, "sah =");
        bvh.bytes_per_prim = number_after(line, "#bytes/prim =");
    } else if (section == "leaves") {
        bvh.leaf_sah = number_after(line, "sah =");
        bvh.leaf_bytes_per_prim = number_after(line, "#bytes/prim =");
        bvh.leaves = size_t(number_after(line, "#nodes ="));
    } else if (section == "alloc" && line.find("free =") == std::string::npos) {
        bvh.alloc_used_per_prim = number_after(line, "#bytes/prim =");
    } else if (section == "alloc") {
        bvh.alloc_total_per_prim = number_after(line, "#bytes/prim =");
    } else if (line.find("sah =") != std::string::npos && section.find("Nodes") != std::string::npos) {
        // getAABBNodes, quantizedNodes, getAABBNodesMB...: whichever kinds the tree has.
        bvh.node_sah += number_after(line, "sah =");
        bvh.node_bytes_per_prim += number_after(line, "#bytes/prim =");
        bvh.nodes += size_t(number_after(line, "#nodes ="));
    }
}

RTCRayHit embree_ray(const Ray& ray) {
    RTCRayHit query;
    query.ray.org_x = ray.origin.x, query.ray.org_y = ray.origin.y, query.ray.org_z = ray.origin.z;
    query.ray.dir_x = ray.direction.x, query.ray.dir_y = ray.direction.y, query.ray.dir_z = ray.direction.z;
    query.ray.tnear = 0.0f;
    query.ray.tfar = ray.t_max;
    query.ray.time = ray.time;
    query.ray.mask = 0xffffffffu;
    query.ray.id = 0;
    query.ray.flags = 0;
    query.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    query.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    return query;
}

// Lane `lane` of a 16-wide ray; an inactive lane gets a harmless empty ray,
// since Embree loads all 16 lanes before it applies the valid mask.
void set_lane(RTCRay16& packet, unsigned lane, const Ray* ray) {
    const Ray empty{vec3(0.0f), vec3(0.0f, 0.0f, 1.0f), 0.0f, 0.0f};
    const Ray& r = ray ? *ray : empty;
    packet.org_x[lane] = r.origin.x, packet.org_y[lane] = r.origin.y, packet.org_z[lane] = r.origin.z;
    packet.dir_x[lane] = r.direction.x, packet.dir_y[lane] = r.direction.y, packet.dir_z[lane] = r.direction.z;
    packet.tnear[lane] = 0.0f;
    packet.tfar[lane] = r.t_max;
    packet.time[lane] = r.time;
    packet.mask[lane] = 0xffffffffu;
    packet.id[lane] = lane;
    packet.flags[lane] = 0;
}

// Rays rays[0..15], one after another, into the packet's lanes, four at a
// time by a 4 x 4 transpose of each half of a Ray (its origin and direction
// x; direction y and z, t_max, time), as a caller that makes its rays one
// after another fills an RTCRay16: filled lane by lane, Embree's camera
// packets ran at 105-112 Mrays/s on the teapot and smooth_sphere, 115-123
// filled so (1T; see ours_tile.h).
void fill_lanes(RTCRay16& packet, const Ray* rays) {
    static_assert(sizeof(Ray) == 8 * sizeof(float));
    const __m128 zero = _mm_setzero_ps();
    const __m128i all = _mm_set1_epi32(-1);
    for (unsigned first = 0; first < kPacketWidth; first += 4) {
        __m128 low[4], high[4];
        for (unsigned i = 0; i < 4; ++i) {
            const float* ray = reinterpret_cast<const float*>(rays + first + i);
            low[i] = _mm_loadu_ps(ray);
            high[i] = _mm_loadu_ps(ray + 4);
        }
        _MM_TRANSPOSE4_PS(low[0], low[1], low[2], low[3]);
        _MM_TRANSPOSE4_PS(high[0], high[1], high[2], high[3]);
        _mm_store_ps(packet.org_x + first, low[0]);
        _mm_store_ps(packet.org_y + first, low[1]);
        _mm_store_ps(packet.org_z + first, low[2]);
        _mm_store_ps(packet.dir_x + first, low[3]);
        _mm_store_ps(packet.dir_y + first, high[0]);
        _mm_store_ps(packet.dir_z + first, high[1]);
        _mm_store_ps(packet.tfar + first, high[2]);
        _mm_store_ps(packet.time + first, high[3]);
        _mm_store_ps(packet.tnear + first, zero);
        _mm_store_si128(reinterpret_cast<__m128i*>(packet.mask + first), all);
        _mm_store_si128(reinterpret_cast<__m128i*>(packet.id + first),
                        _mm_add_epi32(_mm_set1_epi32(int(first)), _mm_set_epi32(3, 2, 1, 0)));
        _mm_store_si128(reinterpret_cast<__m128i*>(packet.flags + first), _mm_setzero_si128());
    }
}

// The packet's rays into `query`, and its valid mask.
void fill_packet(RTCRay16& query, int* valid, const Ray* rays, const Packet& packet) {
    if (consecutive(packet)) {
        fill_lanes(query, rays + packet[0]);
        std::fill_n(valid, kPacketWidth, -1);
        return;
    }
    for (unsigned lane = 0; lane < kPacketWidth; ++lane) {
        const bool active = packet[lane] != kInactiveLane;
        valid[lane] = active ? -1 : 0;
        set_lane(query, lane, active ? &rays[packet[lane]] : nullptr);
    }
}

// A renderer's tile hands Embree neighbouring pixels: it may say so.
RTCIntersectContext coherent_context() {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    return context;
}

}  // namespace

std::string EmbreeReport::isa() const {
    const size_t colons = intersector1.find("::");
    return colons == std::string::npos ? "unknown" : intersector1.substr(0, colons);
}

const EmbreeBvhStats* EmbreeReport::triangles() const {
    for (const EmbreeBvhStats& bvh : bvhs)
        if (bvh.type.find("triangle") != std::string::npos) return &bvh;
    return nullptr;
}

// The verbose=2 print of a device and its scene commits: kernels/bvh/bvh.cpp
// (BVHN<N>::preBuild/postBuild) writes "building BVH8<triangle4> using
// avx::BVH8BuilderFastSpatialSAH ...", then the statistics, and
// kernels/common/scene.cpp the "selected scene intersector" list.
EmbreeReport parse_embree_report(const std::string& printed) {
    EmbreeReport report;
    std::istringstream lines(printed);
    bool selected = false;
    for (std::string line; std::getline(lines, line);) {
        if (line.rfind("building ", 0) == 0) {
            EmbreeBvhStats bvh;
            bvh.type = word_after(line, "building ");
            bvh.builder = word_after(line, " using ");
            report.bvhs.push_back(bvh);
        } else if (line.rfind("selected scene intersector", 0) == 0) {
            selected = true;
        } else if (selected && line.find("intersector1 ") != std::string::npos) {
            report.intersector1 = word_after(line, "= ");
        } else if (selected && line.find("intersector16 ") != std::string::npos) {
            report.intersector16 = word_after(line, "= ");
        } else if (!report.bvhs.empty() && line.rfind("  ", 0) == 0) {
            parse_statistics_line(line, report.bvhs.back());
        }
    }
    return report;
}

std::string capture_stdout(const std::function<void()>& f) {
    std::cout.flush();
    std::fflush(stdout);
    FILE* file = std::tmpfile();
    if (!file) throw std::runtime_error("bvh_bench: no temporary file to capture Embree's statistics in");
    const int saved = dup(STDOUT_FILENO);
    dup2(fileno(file), STDOUT_FILENO);
    auto restore = [&] {
        std::cout.flush();
        std::fflush(stdout);
        dup2(saved, STDOUT_FILENO);
        close(saved);
    };
    try {
        f();
    } catch (...) {
        restore();
        std::fclose(file);
        throw;
    }
    restore();
    std::string text;
    std::rewind(file);
    char buffer[4096];
    for (size_t n; (n = std::fread(buffer, 1, sizeof buffer, file)) > 0;) text.append(buffer, n);
    std::fclose(file);
    return text;
}

EmbreeDevice::EmbreeDevice(const std::string& config) : device_(rtcNewDevice(config.c_str())) {
    if (!device_) throw std::runtime_error("bvh_bench: rtcNewDevice(\"" + config + "\") failed");
}

EmbreeScene::EmbreeScene(const EmbreeDevice& device, const Scene& scene, RTCBuildQuality quality)
    : scene_(rtcNewScene(device.get())), sphere_offset_(uint32_t(scene.triangles.size())) {
    rtcSetSceneBuildQuality(scene_, quality);
    if (!scene.triangles.empty()) {
        RTCGeometry mesh = rtcNewGeometry(device.get(), RTC_GEOMETRY_TYPE_TRIANGLE);
        std::memcpy(rtcSetNewGeometryBuffer(mesh, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, sizeof(vec3),
                                            scene.positions.size()),
                    scene.positions.data(), sizeof(vec3) * scene.positions.size());
        std::memcpy(rtcSetNewGeometryBuffer(mesh, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, sizeof(uvec3),
                                            scene.triangles.size()),
                    scene.triangles.data(), sizeof(uvec3) * scene.triangles.size());
        attach(mesh, 0);
    }
    if (!scene.spheres.empty()) {
        RTCGeometry spheres = rtcNewGeometry(device.get(), RTC_GEOMETRY_TYPE_SPHERE_POINT);
        auto* points = static_cast<float*>(rtcSetNewGeometryBuffer(
            spheres, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), scene.spheres.size()));
        for (const Sphere& s : scene.spheres) {
            *points++ = s.center.x, *points++ = s.center.y, *points++ = s.center.z, *points++ = s.radius;
        }
        attach(spheres, 1);
    }
    rtcCommitScene(scene_);
}

void EmbreeScene::attach(RTCGeometry geometry, unsigned id) {
    rtcCommitGeometry(geometry);
    rtcAttachGeometryByID(scene_, geometry, id);
    rtcReleaseGeometry(geometry);
}

Hit EmbreeScene::to_hit(float t, unsigned geometry, unsigned primitive, float u, float v) const {
    if (geometry == RTC_INVALID_GEOMETRY_ID) return {};
    return {t, primitive + (geometry == 1 ? sphere_offset_ : 0), u, v};
}

Hit EmbreeScene::intersect(const Ray& ray) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit query = embree_ray(ray);
    rtcIntersect1(scene_, &context, &query);
    return to_hit(query.ray.tfar, query.hit.geomID, query.hit.primID, query.hit.u, query.hit.v);
}

bool EmbreeScene::occluded(const Ray& ray) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay query = embree_ray(ray).ray;
    rtcOccluded1(scene_, &context, &query);
    return query.tfar < 0.0f;  // Embree marks an occluded ray with tfar = -inf
}

void EmbreeScene::intersect16(const Ray* rays, const Packet& packet, Hit* lane_hits) const {
    alignas(64) int valid[kPacketWidth];
    RTCRayHit16 query;
    fill_packet(query.ray, valid, rays, packet);
    std::fill_n(query.hit.geomID, kPacketWidth, RTC_INVALID_GEOMETRY_ID);
    std::fill_n(query.hit.instID[0], kPacketWidth, RTC_INVALID_GEOMETRY_ID);
    RTCIntersectContext context = coherent_context();
    rtcIntersect16(valid, scene_, &context, &query);
    for (unsigned lane = 0; lane < kPacketWidth; ++lane)
        if (valid[lane])
            lane_hits[lane] = to_hit(query.ray.tfar[lane], query.hit.geomID[lane], query.hit.primID[lane],
                                     query.hit.u[lane], query.hit.v[lane]);
}

void EmbreeScene::occluded16(const Ray* rays, const Packet& packet, char* lane_blocked) const {
    alignas(64) int valid[kPacketWidth];
    RTCRay16 query;
    fill_packet(query, valid, rays, packet);
    RTCIntersectContext context = coherent_context();
    rtcOccluded16(valid, scene_, &context, &query);
    for (unsigned lane = 0; lane < kPacketWidth; ++lane)
        if (valid[lane]) lane_blocked[lane] = query.tfar[lane] < 0.0f;
}

}  // namespace rt::bench
