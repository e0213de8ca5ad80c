// Our BVH against Embree 3 on the sample scenes (issue 16): primary, shadow,
// random and diffuse rays, single rays and Embree's 16-ray packets, on one
// thread and on all, with the same rays for both sides; builds on one and all
// threads at Embree's HIGH and MEDIUM quality; memory and SAH cost as Embree
// itself reports them. Every ray kind is checked before it is timed: against
// Embree, and where the two differ, against brute force. Exits 1 when brute
// force proves any of our answers wrong, after printing everything (2 on a
// usage or load error).
//
//   bvh_bench --scenes build/scenes [--only dragon_1.glb,bunny.glb] [--size 1024] [--min-seconds 0.2]
//             [--kinds primary,shadow,random,diffuse,packets,build,memory] [--threads N]
//   packets: camera-packets, shadow-packets and soft-shadows, which --kinds may also name one by one.
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "run_scene.h"
#include "timing.h"
#include "util/cpu_features.h"

namespace rt::bench {
namespace {

// The sample scenes, smallest first within each family (bench/report_table.py
// sets them beside the 2020 report's performance table, docs/origin.md).
const char* const kScenes[] = {"cornell.obj", "cornell_sphere_light.obj", "smooth_sphere.glb", "bunny.glb",
                               "dragon_4.glb", "dragon_3.glb", "dragon_2.glb", "dragon_1.glb",
                               "teapot.glb", "donut.glb"};

constexpr const char* kUsage =
    "usage: bvh_bench --scenes DIR [--only a.glb,b.obj] [--size N] [--min-seconds S] "
    "[--kinds primary,shadow,random,diffuse,packets,build,memory] [--threads N]\n"
    "  packets: camera-packets, shadow-packets and soft-shadows, which --kinds may also name one by one";

std::string cpu_model() {
    std::ifstream cpuinfo("/proc/cpuinfo");
    for (std::string line; std::getline(cpuinfo, line);)
        if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
    return "unknown CPU";
}

std::vector<std::string> split_list(const std::string& list) {
    std::vector<std::string> items;
    std::stringstream stream(list);
    for (std::string item; std::getline(stream, item, ',');) items.push_back(item);
    return items;
}

std::set<std::string> parse_kinds(const std::string& list) {
    std::set<std::string> kinds;
    for (const std::string& kind : split_list(list)) {
        if (kind == "packets") {
            kinds.insert(std::begin(kPacketKinds), std::end(kPacketKinds));
            continue;
        }
        if (std::find(std::begin(kKinds), std::end(kKinds), kind) == std::end(kKinds))
            throw std::invalid_argument("bvh_bench: unknown kind " + kind + " in --kinds");
        kinds.insert(kind);
    }
    return kinds;
}

Options parse_options(int argc, char** argv) {
    Options options;
    options.threads = std::max(1u, std::thread::hardware_concurrency());
    options.kinds = {std::begin(kKinds), std::end(kKinds)};
    if (argc % 2 == 0) throw std::invalid_argument(kUsage);
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string flag = argv[i], value = argv[i + 1];
        if (flag == "--scenes") options.scenes = value;
        else if (flag == "--only") options.only = split_list(value);
        else if (flag == "--size") options.size = uint32_t(std::stoul(value));
        else if (flag == "--min-seconds") options.min_seconds = std::stod(value);
        else if (flag == "--kinds") options.kinds = parse_kinds(value);
        else if (flag == "--threads") options.threads = std::max(1u, unsigned(std::stoul(value)));
        else throw std::invalid_argument("bvh_bench: unknown option " + flag + "\n" + kUsage);
    }
    if (options.scenes.empty()) throw std::invalid_argument(kUsage);
    return options;
}

bool wanted(const Options& options, const std::string& name) {
    return options.only.empty() || std::find(options.only.begin(), options.only.end(), name) != options.only.end();
}

int run(int argc, char** argv) {
    const Options options = parse_options(argc, argv);
    RunInfo info;
    info.cpu = cpu_model();
    info.threads = options.threads;
    info.ours_simd = simd_path_name();
    info.size = options.size;
    info.random_rays = options.random_rays();
    info.min_seconds = options.min_seconds;
    print_header(info);

    const auto start = Clock::now();
    std::vector<SceneResult> results;
    for (const char* name : kScenes) {
        if (!wanted(options, name)) continue;
        const std::filesystem::path file = options.scenes / name;
        if (!std::filesystem::exists(file)) {
            std::printf("%s: missing, skipped\n", file.string().c_str());
            continue;
        }
        std::printf("%s ...\n", name);
        std::fflush(stdout);
        results.push_back(run_scene(file, options));
        if (info.embree.intersector1.empty()) info.embree = results.back().embree;
        print_scene(results.back(), options.threads);
    }
    print_tables(info, results);

    const size_t wrong = ours_proven_wrong(results);
    std::printf("\n%zu of our answers proven wrong by brute force; %.0f s in all\n", wrong, seconds_since(start));
    return wrong == 0 ? 0 : 1;
}

}  // namespace
}  // namespace rt::bench

int main(int argc, char** argv) {
    try {
        return rt::bench::run(argc, argv);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s\n", e.what());
        return 2;
    }
}
