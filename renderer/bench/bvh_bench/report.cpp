#include "report.h"

#include <embree3/rtcore.h>

#include <cstdio>

namespace rt::bench {
namespace {

std::string format(const char* pattern, auto... values) {
    char cell[256];
    std::snprintf(cell, sizeof cell, pattern, values...);
    return cell;
}

std::string mrays(double rays_per_second) { return format("%.2f", rays_per_second * 1e-6); }
std::string ratio(double ours, double embree) { return embree > 0.0 ? format("%.2f", ours / embree) : "-"; }

// "8 (all)" or "230 (1 in 4)": how many mismatches brute force tested.
std::string checked_cell(const Check& c) {
    if (c.mismatches == 0) return "-";
    if (c.stride == 1) return format("%zu (all)", c.checked);
    return format("%zu (1 in %zu)", c.checked, c.stride);
}

std::string spread_cell(const Spread& s) {
    if (s.runs == 0) return "-";
    // Two decimals below 10 ms: the small scenes build in tenths of a millisecond.
    return s.median < 10.0 ? format("%.2f (%.2f–%.2f)", s.median, s.min, s.max)
                           : format("%.1f (%.1f–%.1f)", s.median, s.min, s.max);
}

std::string per_triangle(size_t bytes, size_t triangles) {
    return triangles ? format("%.1f", double(bytes) / double(triangles)) : "-";
}

void print_checks(const std::vector<SceneResult>& results) {
    std::printf("\n### Answers checked before timing\n\n");
    std::printf("Every ray's answer against Embree's; where they differ, against brute force (at most "
                "max(%zu, %.0e / primitives) rays per query, capped at %zu, every n-th mismatch beyond).\n\n",
                kMinChecked, kBruteForceBudget, kMaxChecked);
    std::printf("| scene | query | rays | differ from Embree | brute-forced | ours wrong |\n");
    std::printf("| --- | --- | ---: | ---: | ---: | ---: |\n");
    for (const SceneResult& r : results)
        for (const QueryResult& q : r.queries)
            std::printf("| %s | %s | %zu | %zu | %s | %zu |\n", r.scene.c_str(), q.query.c_str(), q.check.rays,
                        q.check.mismatches, checked_cell(q.check).c_str(), q.check.ours_wrong);
}

void print_throughput(const std::vector<SceneResult>& results, unsigned threads) {
    std::printf("\n### Mrays/s, ours / Embree (ratio > 1: ours faster)\n\n");
    std::printf("1T: one thread, per CPU second of that thread; %uT: %u threads, per wall-clock second; "
                "the best of %d windows per side, taken in turns, the side that goes first alternating (A B, B A, ...). %uT CPU share: CPU time the process got in the "
                "%uT windows per wall second and thread; under 100%% the machine's other work took cores from both "
                "sides alike. "
                "Embree-1: rtcIntersect1/rtcOccluded1; Embree-16: rtcIntersect16/rtcOccluded16 on 4x4-pixel packets "
                "(ours: trace_tile_ours), and for soft shadows on the 16 rays from one hit towards a spherical light "
                "(ours: the integrator's packet of light samples); a packet's rays are read where they lie, one after "
                "another, by ours and into Embree's RTCRayHit16 by 4x4 transposes, and its answers kept in a tile "
                "buffer per thread; MEDIUM: Embree's default build quality (all others HIGH).\n\n",
                threads, threads, kTimingWindows, threads, threads);
    std::printf("| scene | query | ours 1T | Embree 1T | ratio | ours %uT | Embree %uT | ratio | %uT CPU share |\n",
                threads, threads, threads);
    std::printf("| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n");
    for (const SceneResult& r : results)
        for (const QueryResult& q : r.queries)
            std::printf("| %s | %s | %s | %s | %s | %s | %s | %s | %.0f%% |\n", r.scene.c_str(), q.query.c_str(),
                        mrays(q.t[0].ours).c_str(), mrays(q.t[0].embree).c_str(),
                        ratio(q.t[0].ours, q.t[0].embree).c_str(), mrays(q.t[1].ours).c_str(),
                        mrays(q.t[1].embree).c_str(), ratio(q.t[1].ours, q.t[1].embree).c_str(),
                        100.0 * q.cpu_share);
}

void print_builds(const std::vector<SceneResult>& results, unsigned threads) {
    bool any = false;
    for (const SceneResult& r : results) any |= r.build.has_value();
    if (!any) return;
    std::printf("\n### Build ms, median (min–max) of the runs (ratio < 1: ours faster)\n\n");
    std::printf("Ours: Accelerator(scene, threads), triangle blocks included. Embree: geometry buffers and "
                "rtcCommitScene, device \"threads=1\" or the default.\n\n");
    std::printf("| scene | tris | runs | ours 1T | Embree HIGH 1T | ratio | ours %uT | Embree HIGH %uT | ratio "
                "| Embree MEDIUM 1T | Embree MEDIUM %uT |\n",
                threads, threads, threads);
    std::printf("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n");
    for (const SceneResult& r : results) {
        if (!r.build) continue;
        const BuildResult& b = *r.build;
        std::printf("| %s | %zu | %d | %s | %s | %s | %s | %s | %s | %s | %s |\n", r.scene.c_str(), r.triangles,
                    b.ours[0].runs, spread_cell(b.ours[0]).c_str(), spread_cell(b.high[0]).c_str(),
                    ratio(b.ours[0].median, b.high[0].median).c_str(), spread_cell(b.ours[1]).c_str(),
                    spread_cell(b.high[1]).c_str(), ratio(b.ours[1].median, b.high[1].median).c_str(),
                    spread_cell(b.medium[0]).c_str(), spread_cell(b.medium[1]).c_str());
    }
}

// Embree prints SAH costs with three decimals and bytes per primitive with
// two; the cells show what it printed.
std::string embree_cell(const EmbreeBvhStats* bvh, double EmbreeBvhStats::*field) {
    const bool sah = field == &EmbreeBvhStats::sah;
    return bvh ? format(sah ? "%.3f" : "%.2f", bvh->*field) : "-";
}

std::string optional_cell(const std::optional<double>& value) { return value ? format("%.3f", *value) : "-"; }

// The trees' shape: how many nodes and leaves each side needs, how full they are.
void print_shapes(const std::vector<SceneResult>& results) {
    std::printf("\n| scene | ours nodes | ours leaves | ours leaf blocks | ours depth | Embree nodes | Embree leaves "
                "| Embree depth |\n");
    std::printf("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n");
    for (const SceneResult& r : results) {
        if (!r.memory) continue;
        const AccelStats& ours = r.memory->ours;
        const EmbreeBvhStats* high = r.memory->high.triangles();
        std::printf("| %s | %zu | %zu | %zu | %u | %s | %s | %s |\n", r.scene.c_str(), ours.nodes, ours.leaves,
                    ours.leaf_blocks, ours.depth, high ? std::to_string(high->nodes).c_str() : "-",
                    high ? std::to_string(high->leaves).c_str() : "-",
                    high ? std::to_string(high->depth).c_str() : "-");
    }
}

// Which builder Embree ran at each quality: the same for every triangle mesh,
// so the first scene's says it.
void print_builders(const std::vector<SceneResult>& results) {
    for (const SceneResult& r : results) {
        const EmbreeBvhStats* high = r.memory ? r.memory->high.triangles() : nullptr;
        if (!high) continue;
        const EmbreeBvhStats* medium = r.memory->medium.triangles();
        std::printf("\nEmbree's builders (%s): HIGH %s, MEDIUM %s\n", r.scene.c_str(), high->builder.c_str(),
                    medium ? medium->builder.c_str() : "-");
        return;
    }
}

void print_memory(const std::vector<SceneResult>& results) {
    bool any = false;
    for (const SceneResult& r : results) any |= r.memory.has_value();
    if (!any) return;
    std::printf("\n### BVH memory (bytes per triangle) and SAH cost\n\n");
    std::printf("SAH in Embree's formula (bench/bvh_bench/ours_sah.h: node and leaf-block cost 1, area-weighted, "
                "over the root's area), Embree's as its verbose=2 statistics print it. Ours also with our own "
                "costs (AccelStats::sah_cost). Embree's alloc: all its allocator handed out for the BVH. The sample meshes stand "
                "on a ground quad ~1000x their box in area, which makes every SAH about 1.97 (bench/bvh_bench/ground.h): "
                "the last three columns are trees over the scene without that quad (Embree HIGH: spatial splits; MEDIUM: "
                "plain binned SAH).\n\n");
    std::printf("| scene | tris | ours nodes B/tri | ours leaves B/tri | ours total B/tri | ours SAH | ours SAH (own costs) "
                "| Embree BVH | Embree nodes B/tri | Embree leaves B/tri | Embree total B/tri | Embree alloc B/tri | Embree SAH "
                "| Embree MEDIUM total B/tri | Embree MEDIUM SAH | ours SAH w/o ground | Embree SAH w/o ground "
                "| Embree MEDIUM SAH w/o ground |\n");
    std::printf("| --- | ---: | ---: | ---: | ---: | ---: | ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: "
                "| ---: | ---: | ---: |\n");
    for (const SceneResult& r : results) {
        if (!r.memory) continue;
        const MemoryResult& m = *r.memory;
        const EmbreeBvhStats* high = m.high.triangles();
        const EmbreeBvhStats* medium = m.medium.triangles();
        const size_t tris = m.ours.triangles;
        std::printf("| %s | %zu | %s | %s | %s | %.3f | %.3f | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n",
                    r.scene.c_str(), tris, per_triangle(m.ours.node_bytes, tris).c_str(),
                    per_triangle(m.ours.leaf_bytes, tris).c_str(),
                    per_triangle(m.ours.node_bytes + m.ours.leaf_bytes, tris).c_str(), m.ours_embree_sah,
                    m.ours.sah_cost, high ? high->type.c_str() : "-",
                    embree_cell(high, &EmbreeBvhStats::node_bytes_per_prim).c_str(),
                    embree_cell(high, &EmbreeBvhStats::leaf_bytes_per_prim).c_str(),
                    embree_cell(high, &EmbreeBvhStats::bytes_per_prim).c_str(),
                    embree_cell(high, &EmbreeBvhStats::alloc_used_per_prim).c_str(),
                    embree_cell(high, &EmbreeBvhStats::sah).c_str(),
                    embree_cell(medium, &EmbreeBvhStats::bytes_per_prim).c_str(),
                    embree_cell(medium, &EmbreeBvhStats::sah).c_str(), optional_cell(m.ours_mesh_sah).c_str(),
                    optional_cell(m.embree_mesh_sah).c_str(), optional_cell(m.embree_medium_mesh_sah).c_str());
    }
    print_shapes(results);
    print_builders(results);
}

}  // namespace

void print_header(const RunInfo& info) {
    std::printf("CPU: %s, %u threads used for \"all threads\"; Embree %s; ours: SIMD path %s\n", info.cpu.c_str(),
                info.threads, RTC_VERSION_STRING, info.ours_simd.c_str());
    std::printf("Rays per scene: %ux%u primary (in 4x4 pixel blocks), shadow and diffuse from their hits, %zu random; "
                "each side timed for at least %.2f s\n",
                info.size, info.size, info.random_rays, info.min_seconds);
}

void print_scene(const SceneResult& result, unsigned threads) {
    for (const QueryResult& q : result.queries)
        std::printf("  %-28s %8zu rays, %5zu differ from Embree, %s brute-forced, %zu ours wrong; Mrays/s 1T %s / %s, "
                    "%uT %s / %s (CPU share %.0f%%)\n",
                    q.query.c_str(), q.check.rays, q.check.mismatches, checked_cell(q.check).c_str(), q.check.ours_wrong,
                    mrays(q.t[0].ours).c_str(), mrays(q.t[0].embree).c_str(), threads, mrays(q.t[1].ours).c_str(),
                    mrays(q.t[1].embree).c_str(), 100.0 * q.cpu_share);
    std::fflush(stdout);
}

bool any_queries(const std::vector<SceneResult>& results) {
    for (const SceneResult& r : results)
        if (!r.queries.empty()) return true;
    return false;
}

void print_tables(const RunInfo& info, const std::vector<SceneResult>& results) {
    std::printf("\n## BVH: ours against Embree %s\n\n", RTC_VERSION_STRING);
    std::printf("%s; ours: %s kernels; Embree: %s kernels (%s, %s), flush-to-zero off on both sides.\n",
                info.cpu.c_str(), info.ours_simd.c_str(), info.embree.isa().c_str(),
                info.embree.intersector1.c_str(), info.embree.intersector16.c_str());
    if (any_queries(results)) {
        print_throughput(results, info.threads);
        print_checks(results);
    }
    print_builds(results, info.threads);
    print_memory(results);
}

size_t ours_proven_wrong(const std::vector<SceneResult>& results) {
    size_t wrong = 0;
    for (const SceneResult& r : results)
        for (const QueryResult& q : r.queries) wrong += q.check.ours_wrong;
    return wrong;
}

}  // namespace rt::bench
