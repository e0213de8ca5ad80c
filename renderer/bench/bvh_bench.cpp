// Our BVH against Embree 3 on the sample scenes: build statistics, then primary
// and shadow rays per second, on one thread and on all, with the same rays for
// both. Before timing, every hit is checked against Embree's, and where the two
// differ, against brute force.
//
//   bvh_bench --scenes build/scenes [--only dragon_1.glb,bunny.glb] [--size 1024] [--min-seconds 0.3]
#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "geometry/accel.h"
#include "geometry/brute_force.h"
#include "integrator/camera.h"
#include "integrator/default_camera.h"
#include "load/loader.h"
#include "geometry/spawn.h"
#include "geometry/surface.h"
#include "geometry/triangle.h"

namespace rt {
namespace {

// The sample scenes, smallest first within each family (bench/report_table.py
// sets them beside the 2020 report's performance table, docs/origin.md).
const char* const kScenes[] = {"cornell.obj", "cornell_sphere_light.obj", "smooth_sphere.glb", "bunny.glb",
                               "dragon_4.glb", "dragon_3.glb", "dragon_2.glb", "dragon_1.glb",
                               "teapot.glb", "donut.glb"};

struct Options {
    std::filesystem::path scenes;
    std::vector<std::string> only;
    uint32_t size = 1024;
    double min_seconds = 0.3;
};

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

std::string cpu_model() {
    std::ifstream cpuinfo("/proc/cpuinfo");
    for (std::string line; std::getline(cpuinfo, line);)
        if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
    return "unknown CPU";
}

// Calls f(i) for i in [0, count) on `threads` threads, in chunks handed out in order.
template <typename F>
void parallel_for(size_t count, unsigned threads, F&& f) {
    constexpr size_t kChunk = 1024;
    std::atomic<size_t> next{0};
    auto work = [&] {
        for (size_t begin; (begin = next.fetch_add(kChunk)) < count;)
            for (size_t i = begin; i < std::min(count, begin + kChunk); ++i) f(i);
    };
    std::vector<std::thread> helpers;
    for (unsigned t = 1; t < threads; ++t) helpers.emplace_back(work);
    work();
    for (std::thread& helper : helpers) helper.join();
}

// Seconds on the calling thread's CPU clock: what one-thread figures are
// timed with, so that whatever else runs on the machine does not skew them.
double thread_cpu_seconds() {
    timespec now;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
    return double(now.tv_sec) + 1e-9 * double(now.tv_nsec);
}

// Rays per second of `pass`, which traces `rays` rays, repeated for at least
// min_seconds; on the thread's CPU clock when the pass runs on this thread only.
template <typename Pass>
double rays_per_second(size_t rays, double min_seconds, bool on_this_thread, Pass&& pass) {
    auto now = [&] {
        return on_this_thread ? thread_cpu_seconds()
                              : std::chrono::duration<double>(Clock::now().time_since_epoch()).count();
    };
    size_t passes = 0;
    const double start = now();
    do {
        pass();
        ++passes;
    } while (now() - start < min_seconds);
    return double(rays * passes) / (now() - start);
}

// The scene in Embree: triangles as geometry 0, spheres as geometry 1, so that
// primitive numbers match ours.
class EmbreeScene {
  public:
    explicit EmbreeScene(const Scene& scene) : device_(rtcNewDevice(nullptr)), scene_(rtcNewScene(device_)) {
        const auto start = Clock::now();
        rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
        if (!scene.triangles.empty()) {
            RTCGeometry mesh = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
            std::memcpy(rtcSetNewGeometryBuffer(mesh, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, sizeof(vec3),
                                                scene.positions.size()),
                        scene.positions.data(), sizeof(vec3) * scene.positions.size());
            std::memcpy(rtcSetNewGeometryBuffer(mesh, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, sizeof(uvec3),
                                                scene.triangles.size()),
                        scene.triangles.data(), sizeof(uvec3) * scene.triangles.size());
            attach(mesh, 0);
        }
        if (!scene.spheres.empty()) {
            RTCGeometry spheres = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_SPHERE_POINT);
            auto* points = static_cast<float*>(rtcSetNewGeometryBuffer(
                spheres, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), scene.spheres.size()));
            for (const Sphere& s : scene.spheres) {
                *points++ = s.center.x, *points++ = s.center.y, *points++ = s.center.z, *points++ = s.radius;
            }
            attach(spheres, 1);
        }
        rtcCommitScene(scene_);
        build_ms_ = 1000.0 * seconds_since(start);
        sphere_offset_ = uint32_t(scene.triangles.size());
    }
    ~EmbreeScene() {
        rtcReleaseScene(scene_);
        rtcReleaseDevice(device_);
    }
    EmbreeScene(const EmbreeScene&) = delete;
    EmbreeScene& operator=(const EmbreeScene&) = delete;

    double build_ms() const { return build_ms_; }

    Hit intersect(const Ray& ray) const {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        RTCRayHit query = embree_ray(ray);
        query.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(scene_, &context, &query);
        if (query.hit.geomID == RTC_INVALID_GEOMETRY_ID) return {};
        return {query.ray.tfar, query.hit.primID + (query.hit.geomID == 1 ? sphere_offset_ : 0), query.hit.u,
                query.hit.v};
    }

    bool occluded(const Ray& ray) const {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        RTCRay query = embree_ray(ray).ray;
        rtcOccluded1(scene_, &context, &query);
        return query.tfar < 0.0f;  // Embree marks an occluded ray with tfar = -inf
    }

  private:
    static RTCRayHit embree_ray(const Ray& ray) {
        RTCRayHit query{};
        query.ray.org_x = ray.origin.x, query.ray.org_y = ray.origin.y, query.ray.org_z = ray.origin.z;
        query.ray.dir_x = ray.direction.x, query.ray.dir_y = ray.direction.y, query.ray.dir_z = ray.direction.z;
        query.ray.tnear = 0.0f;
        query.ray.tfar = ray.t_max;
        query.ray.mask = 0xffffffffu;
        return query;
    }

    void attach(RTCGeometry geometry, unsigned id) {
        rtcCommitGeometry(geometry);
        rtcAttachGeometryByID(scene_, geometry, id);
        rtcReleaseGeometry(geometry);
    }

    RTCDevice device_;
    RTCScene scene_;
    double build_ms_ = 0.0;
    uint32_t sphere_offset_ = 0;
};

struct Rays {
    std::vector<Ray> primary;
    std::vector<Ray> shadow;  // from the primary hits towards the first light
};

// A size x size pinhole image from the scene's first camera (or a default view
// of its bounds), and shadow rays from where those rays hit.
Rays make_rays(const Scene& scene, const Accelerator& accel, uint32_t size) {
    Rays rays;
    const ViewCamera camera(default_camera(scene), size, size);
    for (uint32_t y = 0; y < size; ++y)
        for (uint32_t x = 0; x < size; ++x) rays.primary.push_back(camera.generate_ray(x + 0.5f, y + 0.5f));
    const Bounds3 bounds = scene.bounds();
    const vec3 light = !scene.lights.empty() ? scene.lights.front().position
                                             : vec3(bounds.center().x, bounds.max.y + bounds.extent().y, bounds.center().z);
    for (const Ray& ray : rays.primary) {
        Hit hit;
        if (!accel.intersect(ray, hit)) continue;
        const SurfaceHit s = surface_at(scene, ray, hit);
        rays.shadow.push_back(spawn_ray_to(s.p, s.p_error, s.ng, light, s.time));
    }
    return rays;
}

bool same_hit(const Hit& ours, const Hit& embree) {
    if (ours.found() != embree.found()) return false;
    return !ours.found() || std::abs(ours.t - embree.t) <= 1e-4f * std::max(1.0f, ours.t);
}

struct Throughput {
    double ours = 0.0;
    double embree = 0.0;
};

struct Result {
    std::string scene;
    size_t triangles = 0;
    AccelStats stats;
    double embree_build_ms = 0.0;
    // Rays where our hit differs from Embree's, and of those, where ours also
    // differs from brute force.
    size_t primary_mismatches = 0, primary_ours_wrong = 0;
    size_t shadow_mismatches = 0, shadow_ours_wrong = 0, shadow_rays = 0;
    Throughput primary[2], shadow[2];  // [0]: one thread, [1]: all threads
};

Result run_scene(const std::filesystem::path& file, const Options& options, unsigned threads) {
    const Scene scene = load_scene(file);
    const Accelerator accel(scene);
    const EmbreeScene embree(scene);
    const Rays rays = make_rays(scene, accel, options.size);

    Result result;
    result.scene = file.filename().string();
    result.triangles = scene.triangles.size();
    result.stats = accel.stats();
    result.embree_build_ms = embree.build_ms();
    result.shadow_rays = rays.shadow.size();
    for (const Ray& ray : rays.primary) {
        Hit hit;
        accel.intersect(ray, hit);
        if (same_hit(hit, embree.intersect(ray))) continue;
        ++result.primary_mismatches;
        result.primary_ours_wrong += !same_hit(hit, brute_force_hit(scene, ray));
    }
    for (const Ray& ray : rays.shadow) {
        const bool occluded = accel.occluded(ray);
        if (occluded == embree.occluded(ray)) continue;
        ++result.shadow_mismatches;
        result.shadow_ours_wrong += occluded != brute_force_hit(scene, ray).found();
    }

    std::vector<float> t(rays.primary.size());
    std::vector<char> blocked(rays.shadow.size());
    const unsigned thread_counts[2] = {1, threads};
    for (int k = 0; k < 2; ++k) {
        const unsigned n = thread_counts[k];
        auto time = [&](const std::vector<Ray>& batch, auto&& trace) {
            return rays_per_second(batch.size(), options.min_seconds, n == 1,
                                   [&] { parallel_for(batch.size(), n, trace); });
        };
        result.primary[k].ours = time(rays.primary, [&](size_t i) {
            Hit hit;
            accel.intersect(rays.primary[i], hit);
            t[i] = hit.t;
        });
        result.primary[k].embree = time(rays.primary, [&](size_t i) { t[i] = embree.intersect(rays.primary[i]).t; });
        result.shadow[k].ours = time(rays.shadow, [&](size_t i) { blocked[i] = accel.occluded(rays.shadow[i]); });
        result.shadow[k].embree = time(rays.shadow, [&](size_t i) { blocked[i] = embree.occluded(rays.shadow[i]); });
    }
    return result;
}

std::string ratio_cell(const Throughput& t) {
    char cell[64];
    std::snprintf(cell, sizeof cell, "%6.2f %6.2f %5.2f", t.ours * 1e-6, t.embree * 1e-6, t.ours / t.embree);
    return cell;
}

void print_tables(const std::vector<Result>& results, unsigned threads) {
    std::printf("\nBVH                          tris  build ms   nodes    leaves  depth    SAH  | Embree build ms\n");
    for (const Result& r : results)
        std::printf("%-26s %7zu %9.1f %8zu %8zu %5u %8.2f  | %9.1f\n", r.scene.c_str(), r.triangles, r.stats.build_ms,
                    r.stats.nodes, r.stats.leaves, r.stats.depth, r.stats.sah_cost, r.embree_build_ms);

    std::printf("\nMrays/s: ours, Embree, ours/Embree   (1T: one thread, per CPU second; %uT: all threads, per second)\n",
                threads);
    std::printf("%-26s %-20s %-20s %-20s %-20s  differ from Embree: primary, shadow (of them ours wrong)\n", "", "primary 1T",
                ("primary " + std::to_string(threads) + "T").c_str(), "shadow 1T",
                ("shadow " + std::to_string(threads) + "T").c_str());
    for (const Result& r : results)
        std::printf("%-26s %-20s %-20s %-20s %-20s  %zu (%zu), %zu (%zu) of %zu\n", r.scene.c_str(),
                    ratio_cell(r.primary[0]).c_str(), ratio_cell(r.primary[1]).c_str(), ratio_cell(r.shadow[0]).c_str(),
                    ratio_cell(r.shadow[1]).c_str(), r.primary_mismatches, r.primary_ours_wrong, r.shadow_mismatches,
                    r.shadow_ours_wrong, r.shadow_rays);

}

std::vector<std::string> split_list(const std::string& list) {
    std::vector<std::string> items;
    std::stringstream stream(list);
    for (std::string item; std::getline(stream, item, ',');) items.push_back(item);
    return items;
}

int run(int argc, char** argv) {
    Options options;
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string flag = argv[i], value = argv[i + 1];
        if (flag == "--scenes") options.scenes = value;
        else if (flag == "--only") options.only = split_list(value);
        else if (flag == "--size") options.size = uint32_t(std::stoul(value));
        else if (flag == "--min-seconds") options.min_seconds = std::stod(value);
        else throw std::invalid_argument("bvh_bench: unknown option " + flag);
    }
    if (options.scenes.empty() || argc % 2 == 0)
        throw std::invalid_argument("usage: bvh_bench --scenes DIR [--only a.glb,b.obj] [--size N] [--min-seconds S]");

    const unsigned threads = std::max(1u, std::thread::hardware_concurrency());
    std::printf("CPU: %s, %u threads; Embree %s; %ux%u primary rays per scene\n", cpu_model().c_str(), threads,
                RTC_VERSION_STRING, options.size, options.size);
    std::vector<Result> results;
    for (const char* name : kScenes) {
        const std::filesystem::path file = options.scenes / name;
        const bool wanted = options.only.empty() || std::find(options.only.begin(), options.only.end(), name) != options.only.end();
        if (!wanted) continue;
        if (!std::filesystem::exists(file)) {
            std::printf("%s: missing, skipped\n", file.string().c_str());
            continue;
        }
        std::printf("%s ...\n", name);
        std::fflush(stdout);
        results.push_back(run_scene(file, options, threads));
    }
    print_tables(results, threads);
    return 0;
}

}  // namespace
}  // namespace rt

int main(int argc, char** argv) {
    try {
        return rt::run(argc, argv);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s\n", e.what());
        return 1;
    }
}
