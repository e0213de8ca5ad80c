// Auxiliary outputs and preview tiles: what each layer holds, that asking for
// them leaves the colour alone, and that a preview pixel is the final pixel.
#include <algorithm>
#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>

#include "geometry/accel.h"
#include "image/aov.h"
#include "loader_test_util.h"
#include "integrator/render.h"
#include "test_meshes.h"
#include "test_scenes.h"

// After protobuf's headers: OpenImageIO's define a bswap_16 that makes
// protobuf's port.h skip its own bswap_32 and bswap_64.
#include <OpenImageIO/imageio.h>

namespace rt {
namespace {

using namespace rt::testing;

const std::vector<AuxOutput> kAll = {DEPTH, NORMAL, ALBEDO, BVH_COST, ALPHA};

struct TileResult {
    std::vector<float> rgb;
    AuxImage aux;
    RenderStats counts;
};

TileResult render_tile(const Renderer& renderer, TileRect tile, const std::vector<AuxOutput>& outputs,
                       uint32_t scale = 1) {
    const uint32_t w = preview_extent(tile.width, scale), h = preview_extent(tile.height, scale);
    TileResult result{std::vector<float>(size_t(w) * h * 3), AuxImage(w, h, outputs), {}};
    result.counts = renderer.render_tile(tile, result.rgb.data(), result.aux.layers(), scale);
    return result;
}

TEST(Aov, NamesFollowTheSchema) {
    EXPECT_EQ(parse_aux_output("bvh_cost"), BVH_COST);
    EXPECT_EQ(parse_aux_output("Depth"), DEPTH);
    EXPECT_EQ(aux_name(ALBEDO), "albedo");
    EXPECT_EQ(aux_output_from_value(2), NORMAL);
    EXPECT_EQ(aux_channel_names(NORMAL), (std::vector<std::string>{"normal.X", "normal.Y", "normal.Z"}));
    EXPECT_EQ(aux_channel_count(BVH_COST), 2u);
    try {
        parse_aux_output("speed");
        FAIL() << "no error";
    } catch (const std::invalid_argument& e) {
        EXPECT_TRUE(contains(e.what(), "'speed'") && contains(e.what(), "depth, normal, albedo, bvh_cost, alpha")) << e.what();
    }
    EXPECT_THROW(parse_aux_output("aux_output_unspecified"), std::invalid_argument);
    EXPECT_THROW(aux_output_from_value(0), std::invalid_argument);
    EXPECT_EQ(aux_channel_names(ALPHA), std::vector<std::string>{"A"});
    EXPECT_THROW(aux_output_from_value(6), std::invalid_argument);
}

// A camera at the origin looking down -z at the plane z = -5, which covers
// the left part of the view only.
TEST(Aov, DepthOfAPlaneIsTheDistanceAlongEachRay) {
    Scene scene;
    add_quad(scene, vec3(-50.0f, -50.0f, -5.0f), vec3(50.0f, 0.0f, 0.0f), vec3(0.0f, 100.0f, 0.0f),
             add_material(scene, vec3(0.5f)));
    add_point_light(scene, vec3(0.0f, 0.0f, 0.0f), 1.0f);
    const Accelerator accel(scene, 1);
    const Camera camera = make_camera(vec3(0.0f), vec3(0.0f, 0.0f, -1.0f), 60.0f);
    const uint32_t w = 40, h = 30;
    const Renderer renderer(accel, make_settings(w, h), camera);
    const TileResult result = render_tile(renderer, {0, 0, w, h}, {DEPTH});
    const ViewCamera pinhole(camera, w, h);
    int hits = 0, misses = 0;
    for (uint32_t y = 0; y < h; ++y) {
        for (uint32_t x = 0; x < w; ++x) {
            const vec3 d = pinhole.generate_ray(float(x) + 0.5f, float(y) + 0.5f).direction;
            const float depth = result.aux.depth[size_t(y) * w + x];
            if (d.x < 0.0f) {
                EXPECT_NEAR(depth, 5.0f / -d.z, 1e-5f * 5.0f / -d.z) << x << ", " << y;
                ++hits;
            } else {
                EXPECT_EQ(depth, 0.0f) << "a miss has depth 0 at " << x << ", " << y;
                ++misses;
            }
        }
    }
    EXPECT_GT(hits, 0);
    EXPECT_GT(misses, 0);
}

// With several samples per pixel, depth, normal, albedo and alpha are their
// means over the samples, as colour is, and the cost is their sum: GRID's four
// sub-pixels are four known rays, and the plane's edge (x = kEdge, film
// x = 20.5) leaves half of those of pixel column 20 on the plane.
TEST(Aov, SeveralSamplesAverageTheLayersAndSumTheCost) {
    constexpr float kEdge = 0.0962f;
    Scene scene;
    add_quad(scene, vec3(-50.0f, -50.0f, -5.0f), vec3(50.0f + kEdge, 0.0f, 0.0f), vec3(0.0f, 100.0f, 0.0f),
             add_material(scene, vec3(0.5f)));
    add_point_light(scene, vec3(0.0f, 0.0f, 0.0f), 1.0f);
    const Accelerator accel(scene, 1);
    const Camera camera = make_camera(vec3(0.0f), vec3(0.0f, 0.0f, -1.0f), 60.0f);
    const uint32_t w = 40, h = 30;
    RenderSettings settings = make_settings(w, h);
    settings.set_pixel_filter(GRID);
    settings.set_samples_per_pixel(4);
    const Renderer renderer(accel, settings, camera);
    const TileResult result = render_tile(renderer, {0, 0, w, h}, {DEPTH, NORMAL, ALBEDO, BVH_COST, ALPHA});
    EXPECT_EQ(result.counts.samples, uint64_t(4) * w * h);
    const ViewCamera pinhole(camera, w, h);
    int edge_pixels = 0;
    for (uint32_t y = 0; y < h; ++y) {
        for (uint32_t x = 0; x < w; ++x) {
            float depth = 0.0f;
            int hits = 0;
            for (float dy : {0.25f, 0.75f}) {
                for (float dx : {0.25f, 0.75f}) {
                    const vec3 d = pinhole.generate_ray(float(x) + dx, float(y) + dy).direction;
                    if (5.0f * d.x / -d.z < kEdge) depth += 5.0f / -d.z, ++hits;
                }
            }
            const size_t p = size_t(y) * w + x;
            EXPECT_NEAR(result.aux.depth[p], depth / 4.0f, 1e-5f * (1.0f + depth)) << x << ", " << y;
            EXPECT_NEAR(result.aux.normal[3 * p + 2], float(hits) / 4.0f, 1e-6f) << x << ", " << y;
            EXPECT_NEAR(result.aux.albedo[3 * p], 0.5f * float(hits) / 4.0f, 1e-6f) << x << ", " << y;
            EXPECT_EQ(result.aux.alpha[p], float(hits) / 4.0f) << x << ", " << y;
            edge_pixels += hits == 2;
        }
    }
    EXPECT_GT(edge_pixels, 0);
    // The cost of one pixel is the sum over the rays of all its samples.
    const DebugPath path = renderer.debug_pixel(20, 15);
    uint64_t nodes = 0;
    for (const RaySegment& segment : path.segments()) nodes += uint64_t(segment.visited_nodes_size());
    EXPECT_EQ(result.aux.bvh_cost[2 * (15 * w + 20)], nodes);
}

TEST(Aov, NormalsAreUnitAndFaceTheCameraAlbedoIsTheDiffuseColour) {
    const Scene scene = floor_and_sphere(1.0f);
    const Accelerator accel(scene, 1);
    const Camera camera = make_camera({0.0f, 3.0f, 9.0f}, {0.0f, 0.8f, 0.0f}, 60.0f);
    const uint32_t w = 48, h = 36;
    const Renderer renderer(accel, make_settings(w, h), camera);
    const TileResult result = render_tile(renderer, {0, 0, w, h}, {NORMAL, ALBEDO});
    const ViewCamera pinhole(camera, w, h);
    int floor = 0, sphere = 0;
    for (uint32_t y = 0; y < h; ++y) {
        for (uint32_t x = 0; x < w; ++x) {
            const size_t p = size_t(y) * w + x;
            const vec3 n(result.aux.normal[3 * p], result.aux.normal[3 * p + 1], result.aux.normal[3 * p + 2]);
            const vec3 albedo(result.aux.albedo[3 * p], result.aux.albedo[3 * p + 1], result.aux.albedo[3 * p + 2]);
            const Ray ray = pinhole.generate_ray(float(x) + 0.5f, float(y) + 0.5f);
            Hit hit;
            if (!accel.intersect(ray, hit)) {
                EXPECT_EQ(n, vec3(0.0f));
                EXPECT_EQ(albedo, vec3(0.0f));
                continue;
            }
            EXPECT_NEAR(glm::length(n), 1.0f, 1e-5f);
            EXPECT_GT(glm::dot(n, -ray.direction), 0.0f) << x << ", " << y;
            const bool on_sphere = hit.primitive >= scene.triangles.size();
            const uint32_t material = on_sphere ? scene.spheres[0].material : scene.triangle_materials[hit.primitive];
            EXPECT_EQ(albedo, scene.materials[material].diffuse) << x << ", " << y;
            ++(on_sphere ? sphere : floor);
        }
    }
    EXPECT_GT(floor, 100);
    EXPECT_GT(sphere, 20);
}

TEST(Aov, AlbedoCarriesTheTexture) {
    Scene scene;
    const uint32_t material = add_material(scene, vec3(0.5f, 1.0f, 1.0f));
    add_quad(scene, vec3(-5.0f, -5.0f, -2.0f), vec3(10.0f, 0.0f, 0.0f), vec3(0.0f, 10.0f, 0.0f), material);
    scene.texcoords.assign(scene.positions.size(), vec2(0.5f));
    scene.textures.push_back(Texture(1, 1, 3, Texture::Encoding::Linear, {51, 102, 153}));  // 0.2, 0.4, 0.6
    scene.materials[material].base_color_texture.index = 0;
    const Accelerator accel(scene, 1);
    const Renderer renderer(accel, make_settings(4, 4), make_camera(vec3(0.0f), vec3(0.0f, 0.0f, -1.0f)));
    const TileResult result = render_tile(renderer, {1, 1, 2, 2}, {ALBEDO});
    for (size_t p = 0; p < 4; ++p)
        EXPECT_EQ(vec3(result.aux.albedo[3 * p], result.aux.albedo[3 * p + 1], result.aux.albedo[3 * p + 2]),
                  vec3(0.5f, 1.0f, 1.0f) * vec3(0.2f, 0.4f, 0.6f));
}

TEST(Aov, ColourAndRayCountsAreTheSameWithAndWithoutAuxOutputs) {
    const Scene scene = sample_scene("cornell.obj");
    const Accelerator accel(scene);
    const Renderer renderer(accel, make_settings(40, 30), scene.cameras.back().camera);
    const TileResult plain = render_tile(renderer, {0, 0, 40, 30}, {});
    const TileResult with_aux = render_tile(renderer, {0, 0, 40, 30}, kAll);
    EXPECT_EQ(plain.rgb, with_aux.rgb);
    EXPECT_EQ(plain.counts.rays.total(), with_aux.counts.rays.total());
    EXPECT_EQ(plain.counts.rays.shadow, with_aux.counts.rays.shadow);
}

// The Cornell box's mirror camera: reflections add rays, and every ray adds cost.
TEST(Aov, BvhCostCoversEveryRayAndGrowsWithMaxDepth) {
    const Scene scene = sample_scene("cornell.obj");
    const Accelerator accel(scene);
    const Camera& mirror = scene.cameras.back().camera;
    ASSERT_EQ(scene.cameras.back().name, "mirror");
    uint64_t previous_total = 0;
    for (uint32_t max_depth : {0u, 1u}) {
        RenderSettings settings = make_settings(32, 24);
        settings.set_max_depth(max_depth);
        const Renderer renderer(accel, settings, mirror);
        const TileResult result = render_tile(renderer, {0, 0, 32, 24}, {DEPTH, BVH_COST});
        uint64_t total = 0;
        for (size_t p = 0; p < size_t(32) * 24; ++p) {
            const uint32_t nodes = result.aux.bvh_cost[2 * p], triangles = result.aux.bvh_cost[2 * p + 1];
            if (result.aux.depth[p] > 0.0f) {
                EXPECT_GT(nodes, 0u) << "pixel " << p;
                EXPECT_GT(triangles, 0u) << "pixel " << p;
            }
            total += nodes + triangles;
        }
        EXPECT_GT(total, previous_total) << "max_depth " << max_depth;
        previous_total = total;

        // One pixel's cost is the sum over the rays the debugger records for it.
        const DebugPath path = renderer.debug_pixel(16, 12);
        uint64_t nodes = 0, triangles = 0;
        for (const RaySegment& segment : path.segments()) {
            nodes += uint64_t(segment.visited_nodes_size());
            triangles += segment.triangles_tested();
        }
        EXPECT_EQ(result.aux.bvh_cost[2 * (12 * 32 + 16)], nodes);
        EXPECT_EQ(result.aux.bvh_cost[2 * (12 * 32 + 16) + 1], triangles);
    }
}

TEST(Aov, PreviewPixelsAreTheFullRendersPixels) {
    const Scene scene = sample_scene("cornell.obj");
    const Accelerator accel(scene);
    const Renderer renderer(accel, make_settings(64, 48), scene.cameras.back().camera);
    const TileRect tile{5, 3, 30, 21};
    const TileResult full = render_tile(renderer, tile, kAll);
    const TileResult preview = render_tile(renderer, tile, kAll, 4);
    ASSERT_EQ(preview.aux.width, 8u);  // ceil(30 / 4)
    ASSERT_EQ(preview.aux.height, 6u);  // ceil(21 / 4)
    for (uint32_t j = 0; j < 6; ++j) {
        for (uint32_t i = 0; i < 8; ++i) {
            const size_t p = size_t(j) * 8 + i, f = size_t(4 * j) * tile.width + 4 * i;
            for (int c = 0; c < 3; ++c) {
                EXPECT_EQ(preview.rgb[3 * p + c], full.rgb[3 * f + c]) << i << ", " << j;
                EXPECT_EQ(preview.aux.normal[3 * p + c], full.aux.normal[3 * f + c]);
                EXPECT_EQ(preview.aux.albedo[3 * p + c], full.aux.albedo[3 * f + c]);
            }
            EXPECT_EQ(preview.aux.depth[p], full.aux.depth[f]);
            EXPECT_EQ(preview.aux.bvh_cost[2 * p], full.aux.bvh_cost[2 * f]);
            EXPECT_EQ(preview.aux.bvh_cost[2 * p + 1], full.aux.bvh_cost[2 * f + 1]);
        }
    }
    // A scale beyond the tile leaves its top-left pixel.
    const TileResult corner = render_tile(renderer, tile, {}, 1000);
    EXPECT_EQ(corner.rgb, std::vector<float>(full.rgb.begin(), full.rgb.begin() + 3));
    std::vector<float> rgb(3);
    EXPECT_THROW(renderer.render_tile(tile, rgb.data(), {}, 0), std::invalid_argument);
}

TEST(Aov, WholeImageLayersMatchTheTiles) {
    const Scene scene = floor_and_sphere(1.0f);
    const Accelerator accel(scene, 2);
    const Renderer renderer(accel, make_settings(37, 29), make_camera({0.0f, 3.0f, 9.0f}, {0.0f, 0.8f, 0.0f}));
    AuxImage aux(37, 29, kAll);
    RenderStats counts;
    const Image image = renderer.render(2, 8, nullptr, counts, &aux);
    const TileResult tile = render_tile(renderer, {0, 0, 37, 29}, kAll);
    EXPECT_EQ(image.rgb, tile.rgb);
    EXPECT_EQ(aux.depth, tile.aux.depth);
    EXPECT_EQ(aux.normal, tile.aux.normal);
    EXPECT_EQ(aux.albedo, tile.aux.albedo);
    EXPECT_EQ(aux.bvh_cost, tile.aux.bvh_cost);
    AuxImage wrong_size(36, 29, kAll);
    EXPECT_THROW(renderer.render(1, 8, nullptr, counts, &wrong_size), std::invalid_argument);
}

TEST(Aov, ExrCarriesTheLayersAsNamedChannels) {
    const Scene scene = floor_and_sphere(1.0f);
    const Accelerator accel(scene, 1);
    const Renderer renderer(accel, make_settings(12, 9), make_camera({0.0f, 3.0f, 9.0f}, {0.0f, 0.8f, 0.0f}));
    AuxImage aux(12, 9, {BVH_COST, DEPTH});
    RenderStats counts;
    const Image image = renderer.render(1, 4, nullptr, counts, &aux);
    const TempDir dir;
    const std::filesystem::path file = dir.path() / "aux.exr";
    write_image(file, image, &aux);

    auto in = OIIO::ImageInput::open(file.string());
    ASSERT_TRUE(in) << OIIO::geterror();
    // OpenEXR keeps channels sorted by name: find each one.
    const std::vector<std::string>& names = in->spec().channelnames;
    ASSERT_EQ(names.size(), 6u);
    const auto channel = [&](const std::string& name) {
        const auto it = std::find(names.begin(), names.end(), name);
        EXPECT_NE(it, names.end()) << name;
        return size_t(it - names.begin());
    };
    const size_t red = channel("R"), depth = channel("depth.Z"), nodes = channel("bvh_cost.nodes"),
                 triangles = channel("bvh_cost.triangles");
    std::vector<float> values(size_t(12) * 9 * 6);
    ASSERT_TRUE(in->read_image(0, 0, 0, 6, OIIO::TypeDesc::FLOAT, values.data()));
    for (size_t p = 0; p < size_t(12) * 9; ++p) {
        EXPECT_EQ(values[6 * p + red], image.rgb[3 * p]);
        EXPECT_EQ(values[6 * p + depth], aux.depth[p]);
        EXPECT_EQ(values[6 * p + nodes], float(aux.bvh_cost[2 * p]));
        EXPECT_EQ(values[6 * p + triangles], float(aux.bvh_cost[2 * p + 1]));
    }
    EXPECT_THROW(write_image(dir.path() / "aux.png", image, &aux), std::invalid_argument);
}

}  // namespace
}  // namespace rt
