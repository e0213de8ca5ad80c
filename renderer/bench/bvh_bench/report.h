// What one run measured, and the tables it prints: checks, throughput (one
// markdown table to paste into an issue note), builds and memory.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "check.h"
#include "embree_scene.h"
#include "geometry/accel.h"
#include "timing.h"

namespace rt::bench {

struct Throughput {
    double ours = 0.0, embree = 0.0;  // rays per second
};

struct QueryResult {
    std::string query;  // "primary", "shadow (Embree-16)", ...
    Check check;
    Throughput t[2];    // [0]: one thread, [1]: all threads
    double cpu_share = 1.0;  // how much of its cores the all-thread timing got (timing.h)
};

// Milliseconds, [0] on one thread and [1] on all; Embree at both build qualities.
struct BuildResult {
    Spread ours[2], high[2], medium[2];
};

struct MemoryResult {
    AccelStats ours;
    double ours_embree_sah = 0.0;  // ours_sah.h
    EmbreeReport high, medium;     // medium empty unless the build kind ran
    // The SAH costs over the scene without its ground quad (ground.h), where it
    // has one: ours, Embree HIGH's (spatial splits) and MEDIUM's (plain binned
    // SAH), which tell apart what spatial splits buy from what the rest of the
    // build does.
    std::optional<double> ours_mesh_sah, embree_mesh_sah, embree_medium_mesh_sah;
};

struct SceneResult {
    std::string scene;
    size_t triangles = 0;
    std::vector<QueryResult> queries;
    std::optional<BuildResult> build;
    std::optional<MemoryResult> memory;
    EmbreeReport embree;  // what Embree printed building the HIGH scene the queries ran on
};

struct RunInfo {
    std::string cpu;
    unsigned threads = 1;
    std::string ours_simd;      // rt::simd_path_name()
    EmbreeReport embree;        // of the first scene: which ISA and kernels Embree picked
    uint32_t size = 0;
    size_t random_rays = 0;
    double min_seconds = 0.0;
};

// One line per query as a scene finishes, so a long run shows progress.
void print_scene(const SceneResult& result, unsigned threads);
void print_header(const RunInfo& info);
void print_tables(const RunInfo& info, const std::vector<SceneResult>& results);

// Rays where brute force proved ours wrong, over every scene and query.
size_t ours_proven_wrong(const std::vector<SceneResult>& results);

}  // namespace rt::bench
