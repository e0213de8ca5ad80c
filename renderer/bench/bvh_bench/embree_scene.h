// The peer: the scene in Embree 3, traced one ray at a time (rtcIntersect1,
// rtcOccluded1) and in 16-ray packets (rtcIntersect16, rtcOccluded16), and
// what Embree itself reports about the BVH it built.
#pragma once

#include <embree3/rtcore.h>

#include <functional>
#include <string>
#include <vector>

#include "geometry/scene.h"
#include "rays.h"
#include "util/ray.h"

namespace rt::bench {

// One BVH as Embree's statistics print it (device config "verbose=2";
// kernels/bvh/bvh_statistics.cpp, BVHNStatistics<N>::str(), and the
// allocator's FastAllocator::AllStatistics::print after it).
struct EmbreeBvhStats {
    std::string type;     // "BVH8<triangle4>": node width and leaf block type
    std::string builder;  // "avx::BVH8BuilderFastSpatialSAH"
    size_t primitives = 0;
    unsigned depth = 0;
    // SAH cost with node and leaf-block cost 1 (see ours_sah.h for the formula).
    double sah = 0.0, node_sah = 0.0, leaf_sah = 0.0;
    // Bytes per primitive, as Embree prints them (two decimals): of the nodes,
    // of the leaf blocks, of both; then what its allocator handed out (used),
    // and that plus what it reserved but left free or wasted (total).
    double node_bytes_per_prim = 0.0, leaf_bytes_per_prim = 0.0, bytes_per_prim = 0.0;
    double alloc_used_per_prim = 0.0, alloc_total_per_prim = 0.0;
    size_t nodes = 0, leaves = 0;
};

// What a verbose device printed: the ISA it picked and one entry per BVH.
struct EmbreeReport {
    std::string intersector1;   // "avx512::BVH8Triangle4Intersector1Moeller"
    std::string intersector16;  // "avx512::BVH8Triangle4Intersector16HybridMoellerNoFilter"
    std::vector<EmbreeBvhStats> bvhs;

    std::string isa() const;  // the intersector's prefix: "avx512"
    // The triangles' BVH (Embree builds one per geometry type), or null.
    const EmbreeBvhStats* triangles() const;
};

EmbreeReport parse_embree_report(const std::string& printed);

// Everything `f` writes to this process's stdout (file descriptor 1, where
// Embree's std::cout goes), instead of printing it.
std::string capture_stdout(const std::function<void()>& f);

class EmbreeDevice {
  public:
    // `config` as rtcNewDevice takes it: "threads=1", "verbose=2", or "".
    explicit EmbreeDevice(const std::string& config);
    ~EmbreeDevice() { rtcReleaseDevice(device_); }
    EmbreeDevice(const EmbreeDevice&) = delete;
    EmbreeDevice& operator=(const EmbreeDevice&) = delete;
    RTCDevice get() const { return device_; }

  private:
    RTCDevice device_;
};

// The scene in Embree: triangles as geometry 0, spheres as geometry 1, so that
// primitive numbers match ours.
class EmbreeScene {
  public:
    EmbreeScene(const EmbreeDevice& device, const Scene& scene, RTCBuildQuality quality);
    ~EmbreeScene() { rtcReleaseScene(scene_); }
    EmbreeScene(const EmbreeScene&) = delete;
    EmbreeScene& operator=(const EmbreeScene&) = delete;

    Hit intersect(const Ray& ray) const;
    bool occluded(const Ray& ray) const;

    // The packet's rays (indices into `rays`), answers written to the
    // packet's lanes; inactive lanes are masked off and left.
    void intersect16(const Ray* rays, const Packet& packet, Hit* lane_hits) const;
    void occluded16(const Ray* rays, const Packet& packet, char* lane_blocked) const;

  private:
    void attach(RTCGeometry geometry, unsigned id);
    Hit to_hit(float t, unsigned geometry, unsigned primitive, float u, float v) const;

    RTCScene scene_;
    uint32_t sphere_offset_ = 0;
};

}  // namespace rt::bench
