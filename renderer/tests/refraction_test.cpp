// Refraction through smooth dielectrics: the Fresnel and Snell functions, the
// rays the integrator spawns at glass (read from the debugger's path), the
// depth bound, and what the loaders make of glTF and MTL transparency.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "geometry/accel.h"
#include "integrator/dielectric.h"
#include "export/glb_export.h"
#include "loader_test_util.h"
#include "integrator/render.h"
#include "test_scenes.h"

namespace rt {
namespace {

using namespace rt::testing;

uint32_t add_glass(Scene& scene, float ior = 1.5f) {
    const uint32_t index = add_material(scene, vec3(0.0f));
    scene.materials[index].transmission = vec3(1.0f);
    scene.materials[index].ior = ior;
    return index;
}

vec3 get(const google::protobuf::RepeatedField<float>& v) { return {v[0], v[1], v[2]}; }
vec3 direction(const RaySegment& s) { return glm::normalize(get(s.end()) - get(s.origin())); }

// The one pixel of a 1x1 image looking from `eye` at `target`, traced with no
// significance cutoff.
DebugPath trace_pixel(const Scene& scene, vec3 eye, vec3 target, uint32_t max_depth) {
    const Accelerator accel(scene, 1);
    RenderSettings settings = make_settings(1, 1);
    settings.set_max_depth(max_depth);
    settings.set_min_contribution(0.0f);
    const Renderer renderer(accel, settings, make_camera(eye, target));
    return renderer.debug_pixel(0, 0);
}

// The segments of `kind` spawned at depth `depth`.
std::vector<int> segments_of(const DebugPath& path, RayKind kind, uint32_t depth) {
    std::vector<int> found;
    for (int i = 0; i < path.segments_size(); ++i)
        if (path.segments(i).kind() == kind && path.segments(i).depth() == depth) found.push_back(i);
    return found;
}

TEST(Refraction, FresnelAtNormalIncidenceIsTheSquaredRatio) {
    const float n = 1.5f;
    const float expected = ((n - 1.0f) / (n + 1.0f)) * ((n - 1.0f) / (n + 1.0f));
    EXPECT_NEAR(expected, 0.04f, 1e-7f);
    EXPECT_NEAR(fr_dielectric(1.0f, n), expected, 1e-6f);
    // The same from inside: a negative cosine inverts eta.
    EXPECT_NEAR(fr_dielectric(-1.0f, n), expected, 1e-6f);
    EXPECT_NEAR(fr_dielectric(1.0f, 1.0f / n), expected, 1e-6f);
    // Past the critical angle from inside, everything reflects.
    EXPECT_EQ(fr_dielectric(std::cos(glm::radians(60.0f)), 1.0f / n), 1.0f);
    vec3 wt;
    EXPECT_FALSE(refract(glm::normalize(vec3(std::sin(glm::radians(60.0f)), std::cos(glm::radians(60.0f)), 0.0f)),
                         vec3(0.0f, 1.0f, 0.0f), 1.0f / n, wt));
    ASSERT_TRUE(refract(vec3(0.0f, 1.0f, 0.0f), vec3(0.0f, 1.0f, 0.0f), n, wt));
    EXPECT_NEAR(glm::length(wt - vec3(0.0f, -1.0f, 0.0f)), 0.0f, 1e-7f);
}

// A slab of glass 1 thick between y = 0 and y = -1, hit at 40 degrees: the ray
// leaves parallel to how it came, displaced by t sin(theta_i - theta_t) / cos(theta_t).
TEST(Refraction, SlabDisplacesTheRayParallel) {
    Scene scene;
    const uint32_t glass = add_glass(scene);
    const float thickness = 1.0f;
    add_quad(scene, {-50.0f, 0.0f, 50.0f}, {100.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -100.0f}, glass);  // faces +y
    add_quad(scene, {-50.0f, -thickness, -50.0f}, {100.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 100.0f}, glass);  // faces -y
    const float theta = glm::radians(40.0f);
    const DebugPath path = trace_pixel(scene, {-2.0f * std::tan(theta), 2.0f, 0.3f}, {0.0f, 0.0f, 0.3f}, 4);

    ASSERT_GT(path.segments_size(), 0);
    const RaySegment& entry = path.segments(0);
    ASSERT_EQ(entry.kind(), PRIMARY);
    const std::vector<int> inside = segments_of(path, REFRACTION, 1);
    ASSERT_EQ(inside.size(), 1u);
    const std::vector<int> exits = segments_of(path, REFRACTION, 2);
    int exit_index = -1;
    for (int i : exits)
        if (path.segments(i).parent() == inside[0]) exit_index = i;
    ASSERT_GE(exit_index, 0);
    const RaySegment& exit = path.segments(exit_index);
    EXPECT_EQ(exit.outcome(), MISS);

    const vec3 d_in = direction(entry), d_inside = direction(path.segments(inside[0])), d_out = direction(exit);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(d_out[c], d_in[c], 1e-5f) << c;

    // Snell inside, and the displacement it implies.
    const float sin_i = std::sqrt(1.0f - d_in.y * d_in.y);
    const float sin_t = std::sqrt(1.0f - d_inside.y * d_inside.y);
    EXPECT_NEAR(sin_t, sin_i / 1.5f, 1e-5f);
    const double theta_i = std::asin(double(sin_i)), theta_t = std::asin(double(sin_i) / 1.5);
    const double expected = thickness * std::sin(theta_i - theta_t) / std::cos(theta_t);
    const vec3 offset = get(exit.origin()) - get(entry.origin());
    const double lateral = glm::length(offset - glm::dot(offset, d_in) * d_in);
    EXPECT_NEAR(lateral, expected, 1e-4 * expected);

    // Fresnel weights: the refracted ray carries 1 - F, the reflection F.
    const float f = fr_dielectric(-d_in.y, 1.5f);
    EXPECT_NEAR(path.segments(inside[0]).weight(0), 1.0f - f, 1e-6f);
    const std::vector<int> reflected = segments_of(path, REFLECTION, 1);
    ASSERT_EQ(reflected.size(), 1u);
    EXPECT_NEAR(path.segments(reflected[0]).weight(0), f, 1e-6f);
}

// From inside glass at 60 degrees (critical angle asin(1/1.5) = 41.8), nothing
// leaves: one reflection with the whole weight. At 30 degrees a ray does leave.
TEST(Refraction, TotalInternalReflectionPastTheCriticalAngle) {
    Scene scene;
    add_quad(scene, {-50.0f, 0.0f, 50.0f}, {100.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -100.0f}, add_glass(scene));
    const DebugPath tir =
        trace_pixel(scene, {0.0f, -1.0f, 0.0f}, {std::tan(glm::radians(60.0f)), 0.0f, 0.0f}, 1);
    EXPECT_TRUE(segments_of(tir, REFRACTION, 1).empty());
    const std::vector<int> reflected = segments_of(tir, REFLECTION, 1);
    ASSERT_EQ(reflected.size(), 1u);
    for (int c = 0; c < 3; ++c) EXPECT_EQ(tir.segments(reflected[0]).weight(c), 1.0f);
    EXPECT_LT(direction(tir.segments(reflected[0])).y, 0.0f);  // back down into the glass

    const DebugPath leaves =
        trace_pixel(scene, {0.0f, -1.0f, 0.0f}, {std::tan(glm::radians(30.0f)), 0.0f, 0.0f}, 1);
    const std::vector<int> refracted = segments_of(leaves, REFRACTION, 1);
    ASSERT_EQ(refracted.size(), 1u);
    EXPECT_GT(direction(leaves.segments(refracted[0])).y, 0.0f);
    const float f = fr_dielectric(direction(leaves.segments(0)).y, 1.0f / 1.5f);
    EXPECT_LT(f, 1.0f);
    EXPECT_NEAR(leaves.segments(refracted[0]).weight(0), 1.0f - f, 1e-6f);
}

// A glass sphere inside a glass sphere between two facing mirrors: every ray
// splits in two, yet the tree stops at max_depth and a render terminates.
TEST(Refraction, NestedGlassBetweenMirrorsStopsAtMaxDepth) {
    Scene scene;
    const uint32_t mirror = add_material(scene, vec3(0.1f), vec3(0.0f), 1.0f, vec3(1.0f));
    add_quad(scene, {-4.0f, -5.0f, -5.0f}, {0.0f, 10.0f, 0.0f}, {0.0f, 0.0f, 10.0f}, mirror);  // x = -4, faces +x
    add_quad(scene, {4.0f, -5.0f, -5.0f}, {0.0f, 0.0f, 10.0f}, {0.0f, 10.0f, 0.0f}, mirror);   // x = +4, faces -x
    const uint32_t glass = add_glass(scene);
    scene.spheres.push_back({vec3(0.0f), 3.0f, glass});
    scene.spheres.push_back({vec3(0.0f), 1.0f, glass});
    add_point_light(scene, {0.0f, 4.0f, 0.0f}, 10.0f);
    for (uint32_t max_depth : {0u, 1u, 4u, 8u}) {
        const DebugPath path = trace_pixel(scene, {-3.9f, 0.1f, 0.2f}, {0.0f, 0.3f, 0.1f}, max_depth);
        int closest = 0;
        uint32_t deepest = 0;
        for (const RaySegment& s : path.segments()) {
            EXPECT_LE(s.depth(), max_depth);
            if (s.kind() == SHADOW) continue;
            ++closest;
            deepest = std::max(deepest, s.depth());
        }
        EXPECT_LE(closest, (2 << max_depth) - 1) << max_depth;  // a binary tree of height max_depth
        EXPECT_EQ(deepest, max_depth);
    }

    const Accelerator accel(scene, 1);
    RenderSettings settings = make_settings(8, 8);
    settings.set_max_depth(8);
    settings.set_min_contribution(0.0f);
    const Renderer renderer(accel, settings, make_camera({-3.9f, 0.1f, 0.2f}, {0.0f, 0.3f, 0.1f}, 90.0f));
    std::vector<float> rgb(8 * 8 * 3);
    const RenderStats stats = renderer.render_tile({0, 0, 8, 8}, rgb.data());
    EXPECT_GT(stats.rays.refraction, 0u);
    for (float v : rgb) EXPECT_TRUE(std::isfinite(v));
}

TEST(Refraction, OpaqueMaterialsSpawnNoRefraction) {
    Scene scene = floor_and_sphere(1.0f);
    const DebugPath path = trace_pixel(scene, {0.0f, 1.0f, 5.0f}, {0.0f, 1.0f, 0.0f}, 5);
    for (const RaySegment& s : path.segments()) EXPECT_NE(s.kind(), REFRACTION);
}

// glTF: KHR_materials_transmission and KHR_materials_ior.
GltfDoc glass_doc(const Json& extensions) {
    GltfDoc doc;
    doc.json["materials"] = Json::array({{{"name", "glass"}, {"extensions", extensions}}});
    doc.add_mesh_node({{"attributes", {{"POSITION", doc.add_vec3({0, 0, 0, 1, 0, 0, 0, 1, 0})}}}, {"material", 0}});
    return doc;
}

const Material& material_named(const Scene& scene, const std::string& name) {
    for (const Material& m : scene.materials)
        if (m.name == name) return m;
    throw std::runtime_error("no material " + name);
}

TEST(Refraction, GltfTransmissionAndIorSetTheMaterial) {
    GltfDoc doc = glass_doc(
        {{"KHR_materials_transmission", {{"transmissionFactor", 0.75}}}, {"KHR_materials_ior", {{"ior", 1.33}}}});
    doc.json["extensionsUsed"] = {"KHR_materials_transmission", "KHR_materials_ior"};
    doc.json["extensionsRequired"] = {"KHR_materials_transmission", "KHR_materials_ior"};
    const Material& m = material_named(load_text(doc.text(), "g.gltf"), "glass");
    EXPECT_EQ(m.transmission, vec3(0.75f));
    EXPECT_FLOAT_EQ(m.ior, 1.33f);

    const Scene defaults = load_text(glass_doc({{"KHR_materials_transmission", {{"transmissionFactor", 1.0}}}}).text(),
                                     "g.gltf");
    EXPECT_EQ(material_named(defaults, "glass").transmission, vec3(1.0f));
    EXPECT_FLOAT_EQ(material_named(defaults, "glass").ior, 1.5f);
    const Scene opaque = load_text(glass_doc(Json::object()).text(), "g.gltf");
    EXPECT_EQ(material_named(opaque, "glass").transmission, vec3(0.0f));
}

TEST(Refraction, GltfIorBelowOneIsRefusedNamingTheMaterial) {
    for (const Json& ior : {Json(0.5), Json("1.5")}) {
        const GltfDoc doc = glass_doc({{"KHR_materials_ior", {{"ior", ior}}}});
        const std::string error = scene_error([&] { load_text(doc.text(), "g.gltf"); });
        EXPECT_TRUE(contains(error, "materials[0] 'glass'")) << error;
        EXPECT_TRUE(contains(error, "KHR_materials_ior.ior")) << error;
    }
}

TEST(Refraction, GlbExportKeepsTransmissionAndIor) {
    Scene scene;
    const uint32_t glass = add_glass(scene, 1.33f);
    scene.materials[glass].transmission = vec3(0.5f);
    add_quad(scene, {0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, glass);
    add_quad(scene, {0.0f, 0.0f, 1.0f}, {1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, add_material(scene, vec3(0.5f)));
    const std::string glb = export_glb(scene);
    const Scene back = load_scene_from_memory(std::as_bytes(std::span(glb.data(), glb.size())), "exported.glb");
    EXPECT_EQ(material_named(back, scene.materials[glass].name).transmission, vec3(0.5f));
    EXPECT_FLOAT_EQ(material_named(back, scene.materials[glass].name).ior, 1.33f);
    EXPECT_EQ(material_named(back, scene.materials[1].name).transmission, vec3(0.0f));
}

// MTL: d < 1 is transmission 1 - d with Ni its index; Ni of opaque materials is ignored.
TEST(Refraction, MtlDissolveAndNiSetTheMaterial) {
    TempDir dir;
    dir.write("m.mtl", "newmtl glass\nKd 0 0 0\nd 0.25\nNi 1.7\nnewmtl opaque\nKd 1 1 1\nNi 0\n");
    const Scene scene = load_scene(dir.write("m.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"
                                                     "usemtl glass\nf 1 2 3\nusemtl opaque\nf 1 3 2\n"));
    EXPECT_EQ(material_named(scene, "glass").transmission, vec3(0.75f));
    EXPECT_FLOAT_EQ(material_named(scene, "glass").ior, 1.7f);
    EXPECT_EQ(material_named(scene, "opaque").transmission, vec3(0.0f));
    EXPECT_FLOAT_EQ(material_named(scene, "opaque").ior, 1.5f);
}

TEST(Refraction, MtlTransparentWithNiBelowOneIsRefused) {
    TempDir dir;
    dir.write("m.mtl", "newmtl bad\nd 0.5\nNi 0.5\n");
    const auto obj = dir.write("m.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl bad\nf 1 2 3\n");
    const std::string error = scene_error([&] { load_scene(obj); });
    EXPECT_TRUE(contains(error, "'bad'")) << error;
    EXPECT_TRUE(contains(error, "Ni")) << error;
}

}  // namespace
}  // namespace rt
