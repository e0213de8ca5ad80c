// Where fixed epsilons and the plain ray/triangle test fail and ours does not:
// the measurements of the Stability tests (tests/stability_*_test.cpp), from
// the same code (tests/stability_probes.h), as CSV for `make charts`.
//
//   stability_table [--out DIR] [--size 96] [--leak-rays 1000000]
//
// Without --out, the tables go to stdout, each after a line "# <file name>"
// and followed by an empty line; with it, each to DIR/<file name>.
//
// self_intersection.csv: scale,method,wrongly_shadowed,wrongly_lit
//   scale: every coordinate of the scenes times this (1e-4 to 1e6).
//   method: where the shadow ray starts: eps_1e-3 and eps_1e-5 step that far
//     towards the light (the 2020 report's method), ours offsets by the hit point's
//     rounding-error bound (spawn.h).
//   wrongly_shadowed: share of the camera rays' hits on a plane, a cube and an
//     icosphere (each alone, so nothing facing the light is in shadow) whose
//     shadow ray is blocked.
//   wrongly_lit: share of the hits on a floor under a roof 0.05 * scale above
//     it, seen from between the two (everything in shadow), whose shadow ray
//     is not blocked.
// edge_leaks.csv: mesh,method,rays,leaks
//   mesh: icosphere, cube or torus, closed.
//   method: moller_trumbore (the usual test) or ours (watertight, triangle.h),
//     both in the renderer's BVH.
//   rays: aimed exactly at edge points (float lerps of the two vertices) and
//     vertices, half from outside, half from inside; leaks: those that met
//     nothing there.
// non_finite.csv: case,pixels,non_finite
//   case: a whole render through rt::Renderer of grazing and in-plane rays,
//     degenerate and sliver triangles, or scenes at scales 1e-30 to 1e30;
//     non_finite: pixels with a NaN or infinite channel.
// depth_bound.csv: scene,max_depth,min_contribution,closest_rays,bound,shadow_rays,seconds
//   scene: facing_mirrors, nested_glass_between_mirrors, or the same with glass
//     that is a mirror too (nested_mirror_glass_...: reflectance 1,
//     transmission 0.9).
//   closest_rays, shadow_rays: the most any camera sample traced.
//   bound: closest_rays_bound(): what max_depth and min_contribution allow.
//   seconds: to render the 16x16 image pixel by pixel on one thread.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

#include "util/proto_limits.h"
#include "stability_probes.h"

namespace rt {
namespace {

using namespace rt::testing;

struct Options {
    std::filesystem::path out;  // empty: stdout
    uint32_t size = 96;
    size_t leak_rays = 1000000;
};

Options parse(int argc, char** argv) {
    Options options;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        const bool has_value = i + 1 < argc;
        if (arg == "--out" && has_value) {
            options.out = argv[++i];
        } else if (arg == "--size" && has_value) {
            options.size = uint32_t(std::stoul(argv[++i]));
        } else if (arg == "--leak-rays" && has_value) {
            options.leak_rays = std::stoul(argv[++i]);
        } else {
            std::cerr << "usage: stability_table [--out DIR] [--size 96] [--leak-rays 1000000]\n";
            std::exit(arg == "--help" ? 0 : 2);
        }
    }
    return options;
}

std::string self_intersection(uint32_t size) {
    std::ostringstream csv;
    csv << "scale,method,wrongly_shadowed,wrongly_lit\n";
    for (float scale : shadow_scales()) {
        std::vector<ShadowTally> lit(std::size(kShadowOrigins)), shadowed(std::size(kShadowOrigins));
        for (const ShadowScene& scene : shadow_scenes(scale)) {
            const std::vector<ShadowTally> tallies = tally_shadow_rays(scene, size);
            for (size_t m = 0; m < tallies.size(); ++m) (scene.lit ? lit : shadowed)[m] += tallies[m];
        }
        for (size_t m = 0; m < lit.size(); ++m)
            csv << scale << ',' << kShadowOrigins[m].name << ',' << lit[m].share() << ',' << shadowed[m].share()
                << '\n';
    }
    return csv.str();
}

std::string edge_leaks(size_t total_rays) {
    std::ostringstream csv;
    csv << "mesh,method,rays,leaks\n";
    const std::vector<NamedMesh> meshes = closed_meshes();
    for (size_t i = 0; i < meshes.size(); ++i) {
        const Accelerator accel(meshes[i].scene);
        // The total split between the meshes, the first ones taking the remainder.
        const size_t count = total_rays / meshes.size() + (i < total_rays % meshes.size());
        const std::vector<Ray> rays = edge_and_vertex_rays(meshes[i].scene, count, uint32_t(i + 1));
        csv << meshes[i].name << ",moller_trumbore," << rays.size() << ',' << moller_trumbore_leaks(accel, rays)
            << '\n';
        csv << meshes[i].name << ",ours," << rays.size() << ',' << watertight_leaks(accel, rays) << '\n';
    }
    return csv.str();
}

std::string non_finite() {
    std::ostringstream csv;
    csv << "case,pixels,non_finite\n";
    for (const HostileCase& c : hostile_cases())
        csv << c.name << ',' << c.settings.width() * c.settings.height() << ','
            << non_finite_pixels(c.scene, c.camera, c.settings) << '\n';
    return csv.str();
}

std::string depth_bound() {
    std::ostringstream csv;
    csv << "scene,max_depth,min_contribution,closest_rays,bound,shadow_rays,seconds\n";
    for (const DepthScene& d : depth_scenes()) {
        for (uint32_t max_depth : {1u, 2u, 4u, 8u, 16u, 32u, 64u}) {
            RenderSettings settings = make_settings(16, 16);
            settings.set_max_depth(max_depth);
            apply_limits(settings, "settings");  // the default min_contribution
            const DepthRun run = trace_depth(d.scene, d.camera, settings);
            csv << d.name << ',' << max_depth << ',' << settings.min_contribution() << ',' << run.most_closest_rays
                << ',' << closest_rays_bound(max_depth, settings.min_contribution(), d.branches) << ','
                << run.most_shadow_rays << ',' << run.seconds << '\n';
        }
    }
    return csv.str();
}

void emit(const Options& options, const std::string& name, const std::string& csv) {
    if (options.out.empty()) {
        std::cout << "# " << name << '\n' << csv << '\n' << std::flush;
        return;
    }
    std::ofstream file(options.out / name);
    file << csv;
    if (!file) throw std::runtime_error("stability_table: cannot write " + (options.out / name).string());
}

}  // namespace
}  // namespace rt

int main(int argc, char** argv) {
    const rt::Options options = rt::parse(argc, argv);
    if (!options.out.empty()) std::filesystem::create_directories(options.out);
    rt::emit(options, "self_intersection.csv", rt::self_intersection(options.size));
    rt::emit(options, "edge_leaks.csv", rt::edge_leaks(options.leak_rays));
    rt::emit(options, "non_finite.csv", rt::non_finite());
    rt::emit(options, "depth_bound.csv", rt::depth_bound());
    return 0;
}
