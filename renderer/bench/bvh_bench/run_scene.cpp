#include "run_scene.h"

#include <memory>
#include <thread>

#include "ground.h"
#include "load/loader.h"
#include "ours_sah.h"
#include "ours_tile.h"
#include "rays.h"

namespace rt::bench {
namespace {

bool all_cores(unsigned threads) { return threads == std::max(1u, std::thread::hardware_concurrency()); }

// Accelerator's thread argument: 0 is all cores, as the renderer builds.
unsigned accel_threads(unsigned threads) { return all_cores(threads) ? 0 : threads; }

// Embree's device config for `threads`: its default for all cores.
std::string embree_threads(unsigned threads) {
    return all_cores(threads) ? std::string() : "threads=" + std::to_string(threads);
}

std::string join_config(const std::string& a, const std::string& b) {
    return a.empty() ? b : b.empty() ? a : a + "," + b;
}

// Runs of each build: half a second and more each on the big meshes, where
// three give a median; the small ones vary the most and cost nothing.
int build_runs(const Scene& scene) {
    const size_t triangles = scene.triangles.size();
    return triangles > 200000 ? 3 : triangles > 20000 ? 5 : 9;
}

// Embree sizes its TBB thread pool by the largest thread count of all live
// devices (the default counting as all cores), so a "threads=1" device only
// builds on one thread while it is the only device: these builds run before
// the scene's traversal device exists (kernels/common/device.cpp,
// Device::initTaskingSystem).
BuildResult time_builds(const Scene& scene, const Options& options) {
    BuildResult result;
    const int runs = build_runs(scene);
    const unsigned counts[2] = {1, options.threads};
    for (int k = 0; k < 2; ++k) {
        result.ours[k] = build_ms(runs, [&] { return std::make_unique<Accelerator>(scene, accel_threads(counts[k])); });
        const EmbreeDevice device(embree_threads(counts[k]));
        result.high[k] = build_ms(runs, [&] {
            return std::make_unique<EmbreeScene>(device, scene, RTC_BUILD_QUALITY_HIGH);
        });
        result.medium[k] = build_ms(runs, [&] {
            return std::make_unique<EmbreeScene>(device, scene, RTC_BUILD_QUALITY_MEDIUM);
        });
    }
    return result;
}

// Ours and Embree's pass on one thread, then on all; each pass takes the thread count.
template <typename Ours, typename Embree>
void time_both(QueryResult& q, size_t rays, const Options& options, Ours&& ours, Embree&& embree) {
    const unsigned counts[2] = {1, options.threads};
    for (int k = 0; k < 2; ++k) {
        const unsigned n = counts[k];
        const PairTiming timing =
            best_rays_per_second(rays, options.min_seconds, n, [&] { ours(n); }, [&] { embree(n); });
        q.t[k].ours = timing.a;
        q.t[k].embree = timing.b;
        if (k == 1) q.cpu_share = timing.cpu_share;  // one thread is timed on its own CPU clock
    }
}

// The peers a query is traced by: ours, and Embree's scene at one build quality.
struct Peers {
    const Scene& scene;
    const Accelerator& accel;
    const EmbreeScene& embree;
    const Options& options;
};

QueryResult closest(const std::string& name, const std::vector<Ray>& rays, const Peers& p) {
    QueryResult q;
    q.query = name;
    std::vector<Hit> ours(rays.size()), embree(rays.size());
    parallel_for(rays.size(), p.options.threads, [&](size_t i) {
        p.accel.intersect(rays[i], ours[i]);
        embree[i] = p.embree.intersect(rays[i]);
    });
    q.check = check_closest(p.scene, rays, ours, embree, p.options.threads);
    std::vector<float> t(rays.size());  // the answers go somewhere, so no pass is optimised away
    time_both(
        q, rays.size(), p.options,
        [&](unsigned n) {
            parallel_for(rays.size(), n, [&](size_t i) {
                Hit hit;
                p.accel.intersect(rays[i], hit);
                t[i] = hit.t;
            });
        },
        [&](unsigned n) { parallel_for(rays.size(), n, [&](size_t i) { t[i] = p.embree.intersect(rays[i]).t; }); });
    return q;
}

QueryResult occluded(const std::string& name, const std::vector<Ray>& rays, const Peers& p) {
    QueryResult q;
    q.query = name;
    std::vector<char> ours(rays.size()), embree(rays.size());
    parallel_for(rays.size(), p.options.threads, [&](size_t i) {
        ours[i] = p.accel.occluded(rays[i]);
        embree[i] = p.embree.occluded(rays[i]);
    });
    q.check = check_occluded(p.scene, rays, ours, embree, p.options.threads);
    std::vector<char> blocked(rays.size());
    time_both(
        q, rays.size(), p.options,
        [&](unsigned n) { parallel_for(rays.size(), n, [&](size_t i) { blocked[i] = p.accel.occluded(rays[i]); }); },
        [&](unsigned n) { parallel_for(rays.size(), n, [&](size_t i) { blocked[i] = p.embree.occluded(rays[i]); }); });
    return q;
}

// Packets are handed out 64 at a time: 1024 rays, a 32 x 32 tile's worth,
// as the single-ray passes.
constexpr size_t kPacketChunk = 64;

// One packet query of both peers: traced once for the check, its answers
// scattered to the rays' places, then timed. A timed pass keeps each
// packet's answers in its thread's tile buffer, as the renderer's tiles keep
// theirs, and not in arrays over every ray: with 16 MB of hits to write
// through per pass, the 2T figures on the small scenes measured the two
// threads' share of memory more than their queries (camera packets against
// Embree-16, 1T / 2T: the teapot 1.04 / 0.99 with the arrays and a thread
// started per pass, 1.04 / 1.07 with tile buffers and kept threads;
// smooth_sphere 1.04 / 0.99 and 1.06 / 1.06; the Cornell box 1.06 / 0.97
// and 1.06 / 1.04).
template <class Out, class OursTile, class EmbreeTile, class CheckBoth>
QueryResult packet_query(const std::string& name, const std::vector<Packet>& packets, size_t rays, const Peers& p,
                         OursTile ours_tile, EmbreeTile embree_tile, CheckBoth check_both) {
    QueryResult q;
    q.query = name;
    std::vector<Out> ours(rays), embree(rays);
    const auto check_pass = [&](std::vector<Out>& out, auto&& tile) {
        parallel_for(packets.size(), p.options.threads, [&](size_t b) {
            Out lanes[kPacketWidth];
            tile(packets[b], lanes);
            for (uint32_t lane = 0; lane < kPacketWidth; ++lane)
                if (packets[b][lane] != kInactiveLane) out[packets[b][lane]] = lanes[lane];
        }, kPacketChunk);
    };
    check_pass(ours, ours_tile);
    check_pass(embree, embree_tile);
    q.check = check_both(ours, embree);
    const auto timed_pass = [&](unsigned n, auto&& tile) {
        parallel_for(packets.size(), n, [&](size_t b) {
            thread_local Out tile_buffer[kPacketChunk * kPacketWidth];
            tile(packets[b], tile_buffer + b % kPacketChunk * kPacketWidth);
        }, kPacketChunk);
    };
    time_both(
        q, rays, p.options, [&](unsigned n) { timed_pass(n, ours_tile); },
        [&](unsigned n) { timed_pass(n, embree_tile); });
    return q;
}

QueryResult closest_packets(const std::string& name, const std::vector<Ray>& rays, const std::vector<Packet>& packets,
                            const Peers& p) {
    return packet_query<Hit>(
        name, packets, rays.size(), p,
        [&](const Packet& packet, Hit* lane_hits) { trace_tile_ours(p.accel, rays.data(), packet, lane_hits); },
        [&](const Packet& packet, Hit* lane_hits) { p.embree.intersect16(rays.data(), packet, lane_hits); },
        [&](const std::vector<Hit>& ours, const std::vector<Hit>& embree) {
            return check_closest(p.scene, rays, ours, embree, p.options.threads);
        });
}

QueryResult occluded_packets(const std::string& name, const std::vector<Ray>& rays,
                             const std::vector<Packet>& packets, const Peers& p) {
    return packet_query<char>(
        name, packets, rays.size(), p,
        [&](const Packet& packet, char* lane_blocked) {
            occluded_tile_ours(p.accel, rays.data(), packet, lane_blocked);
        },
        [&](const Packet& packet, char* lane_blocked) { p.embree.occluded16(rays.data(), packet, lane_blocked); },
        [&](const std::vector<char>& ours, const std::vector<char>& embree) {
            return check_occluded(p.scene, rays, ours, embree, p.options.threads);
        });
}

// An Embree scene on a verbose device, with what Embree printed building it.
struct VerboseEmbree {
    std::unique_ptr<EmbreeScene> scene;
    EmbreeReport report;
};

VerboseEmbree verbose_embree(const EmbreeDevice& device, const Scene& scene, RTCBuildQuality quality) {
    VerboseEmbree result;
    const std::string printed =
        capture_stdout([&] { result.scene = std::make_unique<EmbreeScene>(device, scene, quality); });
    result.report = parse_embree_report(printed);
    return result;
}

MemoryResult measure_memory(const Scene& scene, const Accelerator& accel, const EmbreeDevice& device,
                            const VerboseEmbree& high, const VerboseEmbree& medium) {
    MemoryResult m;
    m.ours = accel.stats();
    m.ours_embree_sah = embree_formula_sah(accel.wide_bvh());
    m.high = high.report;
    m.medium = medium.report;
    if (const std::optional<Scene> mesh = without_ground_quad(scene)) {
        const Accelerator mesh_accel(*mesh, 0);
        m.ours_mesh_sah = embree_formula_sah(mesh_accel.wide_bvh());
        const VerboseEmbree embree_mesh = verbose_embree(device, *mesh, RTC_BUILD_QUALITY_HIGH);
        if (const EmbreeBvhStats* bvh = embree_mesh.report.triangles()) m.embree_mesh_sah = bvh->sah;
        const VerboseEmbree medium_mesh = verbose_embree(device, *mesh, RTC_BUILD_QUALITY_MEDIUM);
        if (const EmbreeBvhStats* bvh = medium_mesh.report.triangles()) m.embree_medium_mesh_sah = bvh->sah;
    }
    return m;
}

void trace_all_kinds(const RaySet& rays, const Peers& p, const Options& o, SceneResult& result) {
    if (o.wants("primary")) result.queries.push_back(closest("primary", rays.primary, p));
    if (o.wants("camera-packets"))
        result.queries.push_back(closest_packets("primary (Embree-16)", rays.primary, rays.primary_packets, p));
    if (o.wants("shadow")) result.queries.push_back(occluded("shadow", rays.shadow, p));
    if (o.wants("shadow-packets"))
        result.queries.push_back(occluded_packets("shadow (Embree-16)", rays.shadow, rays.shadow_packets, p));
    if (o.wants("soft-shadows"))
        result.queries.push_back(
            occluded_packets("soft shadow (Embree-16)", rays.soft_shadow, rays.soft_shadow_packets, p));
    if (o.wants("random")) result.queries.push_back(closest("random", rays.random, p));
    if (o.wants("diffuse")) {
        result.queries.push_back(closest("diffuse", rays.diffuse, p));
        result.queries.push_back(occluded("diffuse (occluded)", rays.diffuse, p));
    }
}

}  // namespace

SceneResult run_scene(const std::filesystem::path& file, const Options& options) {
    const Scene scene = load_scene(file);
    SceneResult result;
    result.scene = file.filename().string();
    result.triangles = scene.triangles.size();
    if (options.wants("build")) result.build = time_builds(scene, options);

    const Accelerator accel(scene, accel_threads(options.threads));
    // verbose=2 makes Embree print its BVH statistics after each build, which
    // the memory table reads; it changes nothing of the tree or its traversal.
    // Its banner at device creation is captured too, so it stays out of the report.
    std::unique_ptr<EmbreeDevice> device;
    capture_stdout([&] { device = std::make_unique<EmbreeDevice>(join_config("verbose=2", embree_threads(options.threads))); });
    VerboseEmbree high = verbose_embree(*device, scene, RTC_BUILD_QUALITY_HIGH);
    VerboseEmbree medium;
    if (options.wants("build")) medium = verbose_embree(*device, scene, RTC_BUILD_QUALITY_MEDIUM);
    if (options.wants("memory")) result.memory = measure_memory(scene, accel, *device, high, medium);
    result.embree = high.report;

    if (!options.wants_rays()) return result;
    const RaySet rays = make_rays(scene, accel, options.size, options.random_rays(), options.threads);
    trace_all_kinds(rays, Peers{scene, accel, *high.scene, options}, options, result);
    if (medium.scene) {
        // Embree's default build quality: what its build time buys in traversal.
        const Peers p{scene, accel, *medium.scene, options};
        if (options.wants("primary")) result.queries.push_back(closest("primary (Embree MEDIUM)", rays.primary, p));
        if (options.wants("shadow")) result.queries.push_back(occluded("shadow (Embree MEDIUM)", rays.shadow, p));
    }
    return result;
}

}  // namespace rt::bench
