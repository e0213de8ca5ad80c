// GLB export: the scene read back by our own loader must be the scene exported.
#include <algorithm>
#include <cmath>
#include <cstring>

#include <gtest/gtest.h>

#include "export/glb_export.h"
#include "loader_test_util.h"
#include "test_meshes.h"
#include "test_scenes.h"

namespace rt {
namespace {

using namespace rt::testing;

Scene round_trip(const Scene& scene) {
    const std::string glb = export_glb(scene);
    return load_scene_from_memory(std::as_bytes(std::span(glb.data(), glb.size())), "exported.glb");
}

// The JSON chunk of a GLB.
Json glb_json(const std::string& glb) {
    uint32_t length = 0;
    std::memcpy(&length, glb.data() + 12, 4);
    return Json::parse(glb.substr(20, length));
}

// Two materials on interleaved quads (so grouping reorders the triangles), a
// point and a spherical light, a camera and a background.
Scene two_material_scene() {
    Scene scene;
    const uint32_t red = add_material(scene, vec3(0.8f, 0.1f, 0.1f), vec3(0.04f), 50.0f);
    const uint32_t blue = add_material(scene, vec3(0.1f, 0.2f, 0.9f), vec3(0.04f), 200.0f);
    add_quad(scene, vec3(-1.0f, 0.0f, 1.0f), vec3(2.0f, 0.0f, 0.0f), vec3(0.0f, 0.0f, -2.0f), red);
    add_quad(scene, vec3(-1.0f, 0.0f, -1.0f), vec3(2.0f, 0.0f, 0.0f), vec3(0.0f, 2.0f, 0.0f), blue);
    add_quad(scene, vec3(-1.0f, 0.0f, 1.0f), vec3(0.0f, 0.0f, -2.0f), vec3(0.0f, 2.0f, 0.0f), red);
    scene.normals[5] = glm::normalize(vec3(0.1f, 0.2f, 1.0f));  // one smooth-shaded corner
    add_point_light(scene, vec3(0.2f, 1.8f, 0.5f), 3.0f);
    scene.lights.push_back({"bulb", vec3(-0.3f, 1.5f, 0.2f), vec3(2.0f, 1.0f, 0.5f), 0.1f});
    scene.cameras.push_back({"front", make_camera(vec3(0.0f, 1.0f, 4.0f), vec3(0.0f, 0.5f, 0.0f), 40.0f)});
    scene.background = vec3(0.1f, 0.2f, 0.3f);
    return scene;
}

// The scene's triangles in the order an export lists them: grouped by material.
std::vector<size_t> by_material(const Scene& scene) {
    std::vector<size_t> order(scene.triangles.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
        return scene.triangle_materials[a] < scene.triangle_materials[b];
    });
    return order;
}

TEST(GlbExport, RoundTripsGeometryMaterialsLightsAndCameras) {
    const Scene scene = two_material_scene();
    const Scene back = round_trip(scene);

    ASSERT_EQ(back.triangles.size(), scene.triangles.size());
    EXPECT_EQ(back.degenerate_triangles, 0u);
    const std::vector<size_t> order = by_material(scene);
    for (size_t t = 0; t < order.size(); ++t) {
        const uvec3 a = scene.triangles[order[t]], b = back.triangles[t];
        for (int k = 0; k < 3; ++k) {
            EXPECT_EQ(back.positions[b[k]], scene.positions[a[k]]) << "triangle " << t << " corner " << k;
            EXPECT_NEAR(glm::distance(back.normals[b[k]], scene.normals[a[k]]), 0.0f, 1e-6f);
        }
        const Material& original = scene.materials[scene.triangle_materials[order[t]]];
        const Material& loaded = back.materials[back.triangle_materials[t]];
        EXPECT_EQ(loaded.diffuse, original.diffuse);
        EXPECT_EQ(loaded.name, original.name);
        EXPECT_NEAR(loaded.shininess, original.shininess, 1e-3f * original.shininess);
    }

    ASSERT_EQ(back.lights.size(), 2u);
    for (size_t i = 0; i < 2; ++i) {
        EXPECT_EQ(back.lights[i].position, scene.lights[i].position);
        EXPECT_NEAR(glm::distance(back.lights[i].intensity, scene.lights[i].intensity), 0.0f, 1e-6f);
    }
    EXPECT_EQ(back.lights[1].name, "bulb");
    EXPECT_EQ(back.background, scene.background);

    ASSERT_EQ(back.cameras.size(), 1u);
    EXPECT_EQ(back.cameras[0].name, "front");
    const Camera& camera = back.cameras[0].camera;
    const vec3 position(camera.position(0), camera.position(1), camera.position(2));
    const vec3 target(camera.target(0), camera.target(1), camera.target(2));
    const vec3 up(camera.up(0), camera.up(1), camera.up(2));
    EXPECT_EQ(position, vec3(0.0f, 1.0f, 4.0f));
    EXPECT_NEAR(glm::distance(glm::normalize(target - position), glm::normalize(vec3(0.0f, -0.5f, -4.0f))), 0.0f,
                1e-6f);
    EXPECT_NEAR(glm::dot(up, glm::normalize(target - position)), 0.0f, 1e-6f);
    EXPECT_GT(up.y, 0.9f);
    EXPECT_NEAR(camera.fov_y(), 40.0f, 1e-4f);
}

// Spot and directional lights keep their kind, direction, cones, range and
// angular diameter through model.glb; the default rig's lights are marked.
TEST(GlbExport, SpotAndDirectionalLightsRoundTrip) {
    Scene scene = two_material_scene();
    scene.lights.clear();
    Light spot;
    spot.kind = SPOT;
    spot.position = {0.0f, 2.0f, 0.0f};
    spot.direction = glm::normalize(vec3(0.3f, -1.0f, 0.2f));
    spot.cos_inner = std::cos(0.2f);
    spot.cos_outer = std::cos(0.6f);
    spot.range = 7.0f;
    Light sun;
    sun.kind = DIRECTIONAL;
    sun.direction = glm::normalize(vec3(-0.5f, -1.0f, 0.1f));
    sun.angular_diameter = 0.02f;
    Light rig = sun;
    rig.direction = vec3(0.0f, 0.0f, 1.0f);  // opposite glTF's -Z
    rig.angular_diameter = 0.0f;
    scene.lights = {spot, sun, rig};
    scene.rig_lights = 1;
    const Scene back = round_trip(scene);
    ASSERT_EQ(back.lights.size(), 3u);
    for (size_t i = 0; i < 3; ++i) {
        EXPECT_EQ(back.lights[i].kind, scene.lights[i].kind);
        EXPECT_NEAR(glm::distance(back.lights[i].direction, scene.lights[i].direction), 0.0f, 1e-5f) << i;
        EXPECT_NEAR(back.lights[i].angular_diameter, scene.lights[i].angular_diameter, 1e-6f);
    }
    EXPECT_NEAR(back.lights[0].cos_inner, spot.cos_inner, 1e-6f);
    EXPECT_NEAR(back.lights[0].cos_outer, spot.cos_outer, 1e-6f);
    EXPECT_EQ(back.lights[0].range, 7.0f);
    const Json doc = glb_json(export_glb(scene));
    const Json& types = doc["extensions"]["KHR_lights_punctual"]["lights"];
    EXPECT_EQ(types[0]["type"], "spot");
    EXPECT_EQ(types[1]["type"], "directional");
    size_t marked = 0;
    for (const Json& node : doc["nodes"])
        marked += node.contains("extras") && node["extras"]["rt"].contains("default_rig");
    EXPECT_EQ(marked, 1u);
}

TEST(GlbExport, WritesAValidContainerAndTheRequiredFields) {
    const std::string glb = export_glb(two_material_scene());
    ASSERT_GE(glb.size(), 28u);
    EXPECT_EQ(glb.substr(0, 4), "glTF");
    uint32_t version = 0, length = 0;
    std::memcpy(&version, glb.data() + 4, 4);
    std::memcpy(&length, glb.data() + 8, 4);
    EXPECT_EQ(version, 2u);
    EXPECT_EQ(length, glb.size());
    EXPECT_EQ(glb.size() % 4, 0u);

    const Json doc = glb_json(glb);
    ASSERT_EQ(doc["meshes"].size(), 1u);
    const Json& primitives = doc["meshes"][0]["primitives"];
    ASSERT_EQ(primitives.size(), 2u) << "one primitive per material";
    for (const Json& primitive : primitives) {
        const Json& position = doc["accessors"][primitive["attributes"]["POSITION"].get<size_t>()];
        EXPECT_EQ(position["min"].size(), 3u);
        EXPECT_EQ(position["max"].size(), 3u);
        EXPECT_EQ(doc["accessors"][primitive["indices"].get<size_t>()]["componentType"], 5125);
        EXPECT_FALSE(primitive["attributes"].contains("TEXCOORD_0")) << "the scene has no texture coordinates";
    }
    EXPECT_EQ(doc["materials"][1]["pbrMetallicRoughness"]["metallicFactor"], 0.0);
    EXPECT_EQ(doc["extensionsUsed"], Json::array({"KHR_lights_punctual"}));
    const Json& bulb = doc["nodes"][2];
    EXPECT_EQ(bulb["extensions"]["KHR_lights_punctual"]["light"], 1);
    EXPECT_FLOAT_EQ(bulb["extras"]["rt"]["radius"].get<float>(), 0.1f);
    EXPECT_FALSE(doc["nodes"][1].contains("extras")) << "a point light has no radius to tell";
    EXPECT_NEAR(doc["cameras"][0]["perspective"]["yfov"].get<double>(), 40.0 * kPi / 180.0, 1e-6);
}

TEST(GlbExport, SpheresBecomeMeshesOnNodesWithTheirExtras) {
    Scene scene = floor_and_sphere(1.0f);
    scene.spheres.push_back({vec3(3.0f, 0.5f, -1.0f), 0.5f, scene.spheres[0].material});
    const std::string glb = export_glb(scene);

    const Json doc = glb_json(glb);
    std::vector<Json> spheres;
    for (const Json& node : doc["nodes"])
        if (node.contains("extras")) spheres.push_back(node["extras"]["rt"]["sphere"]);
    ASSERT_EQ(spheres.size(), 2u);
    EXPECT_EQ(spheres[1]["center"], Json::array({3.0f, 0.5f, -1.0f}));
    EXPECT_EQ(spheres[1]["radius"], 0.5f);

    // Loaded back, each sphere is a closed mesh on its surface, wound outwards.
    const Scene back = round_trip(scene);
    EXPECT_EQ(back.degenerate_triangles, 0u);
    EXPECT_TRUE(back.spheres.empty());
    const size_t per_sphere = (back.triangles.size() - scene.triangles.size()) / 2;
    EXPECT_GT(per_sphere, 1000u);
    for (size_t t = scene.triangles.size(); t < back.triangles.size(); ++t) {
        const Sphere& sphere = scene.spheres[(t - scene.triangles.size()) / per_sphere];
        const uvec3 tri = back.triangles[t];
        const vec3 p0 = back.positions[tri.x], p1 = back.positions[tri.y], p2 = back.positions[tri.z];
        for (vec3 p : {p0, p1, p2}) ASSERT_NEAR(glm::distance(p, sphere.center), sphere.radius, 1e-5f);
        EXPECT_GT(glm::dot(glm::cross(p1 - p0, p2 - p0), p0 + p1 + p2 - 3.0f * sphere.center), 0.0f);
        EXPECT_EQ(back.materials[back.triangle_materials[t]].diffuse, scene.materials[sphere.material].diffuse);
    }
}

TEST(GlbExport, TexturedSceneRoundTripsItsTexture) {
    // A glTF quad with a 3x2 texture that clamps in s and mirrors in t.
    GltfDoc doc;
    const int positions = doc.add_vec3({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0});
    const int texcoords = doc.add_vec2({0, 1, 1, 1, 1, 0, 0, 0});
    const int indices = doc.add_indices({0, 1, 2, 0, 2, 3});
    const Bytes image = png(3, 2, {255, 0, 0, 0, 255, 0, 0, 0, 255, 10, 20, 30, 128, 128, 128, 1, 2, 254});
    doc.json["images"] = Json::array({{{"uri", "data:image/png;base64," + base64(image)}}});
    doc.json["samplers"] = Json::array({{{"wrapS", 33071}, {"wrapT", 33648}}});
    doc.json["textures"] = Json::array({{{"source", 0}, {"sampler", 0}}});
    const Json transform = {{"offset", {0.5, -0.25}}, {"rotation", 0.3}, {"scale", {2, 3}}};
    doc.json["materials"] = Json::array(
        {{{"name", "checker"},
          {"pbrMetallicRoughness",
           {{"baseColorTexture", {{"index", 0}, {"extensions", {{"KHR_texture_transform", transform}}}}},
            {"metallicFactor", 0}}}}});
    doc.add_mesh_node({{"attributes", {{"POSITION", positions}, {"TEXCOORD_0", texcoords}}},
                       {"indices", indices},
                       {"material", 0}});
    const Scene scene = load_text(doc.text(), "textured.gltf");
    ASSERT_EQ(scene.textures.size(), 1u);

    const Scene back = round_trip(scene);
    ASSERT_EQ(back.textures.size(), 1u);
    const Texture &a = scene.textures[0], &b = back.textures[0];
    EXPECT_EQ(b.width, 3);
    EXPECT_EQ(b.height, 2);
    EXPECT_EQ(b.channels, 3);
    EXPECT_EQ(b.encoding, Texture::Encoding::Srgb);
    ASSERT_EQ(b.levels.size(), a.levels.size());
    for (size_t l = 0; l < a.levels.size(); ++l)
        EXPECT_EQ(b.levels[l].texels, a.levels[l].texels) << "8-bit texels survive re-encoding exactly, level " << l;
    EXPECT_EQ(b.wrap_s, Texture::Wrap::ClampToEdge);
    EXPECT_EQ(b.wrap_t, Texture::Wrap::MirroredRepeat);
    EXPECT_EQ(back.texcoords, scene.texcoords);
    ASSERT_EQ(back.materials.size(), 1u);
    EXPECT_EQ(back.materials[0].name, "checker");
    EXPECT_EQ(back.materials[0].base_color_texture.index, 0);
    // KHR_texture_transform travels to the viewer as it came.
    const TextureTransform& t = back.materials[0].base_color_texture.transform;
    EXPECT_EQ(t.offset, vec2(0.5f, -0.25f));
    EXPECT_FLOAT_EQ(t.rotation, 0.3f);
    EXPECT_EQ(t.scale, vec2(2.0f, 3.0f));
}

TEST(GlbExport, ObjSceneBecomesTheSameGlb) {
    const Scene scene = sample_scene("cornell.obj");
    const Scene back = round_trip(scene);
    EXPECT_EQ(back.triangles.size(), scene.triangles.size());
    EXPECT_EQ(back.bounds().min, scene.bounds().min);
    EXPECT_EQ(back.bounds().max, scene.bounds().max);
    ASSERT_EQ(back.lights.size(), scene.lights.size());
    EXPECT_EQ(back.lights[0].position, scene.lights[0].position);
    EXPECT_EQ(back.cameras.size(), scene.cameras.size());
}

TEST(GlbExport, EmptySceneIsAValidGlb) {
    Scene scene;
    scene.background = vec3(0.5f);
    const std::string glb = export_glb(scene);
    EXPECT_EQ(glb.size() % 4, 0u);
    const Scene back = round_trip(scene);
    EXPECT_TRUE(back.triangles.empty());
    EXPECT_EQ(back.background, vec3(0.5f));
}

TEST(GlbExport, TriangleWithoutItsMaterialIsRefused) {
    Scene scene = two_material_scene();
    scene.triangle_materials[1] = 7;
    EXPECT_THROW(export_glb(scene), std::invalid_argument);
}

}  // namespace
}  // namespace rt

namespace rt {
namespace {

using namespace rt::testing;

// What three.js needs to preview a glTF material as the renderer shades it.
TEST(GlbExport, EmissionAlphaAndMetallicRoughnessRoundTrip) {
    Scene scene = two_material_scene();
    Material& m = scene.materials[0];
    m.metallic_roughness = true;
    m.base_color = vec3(0.9f, 0.5f, 0.2f);
    m.metallic = 0.75f;
    m.roughness = 0.25f;
    m.alpha = 0.5f;
    m.alpha_mode = AlphaMode::Mask;
    m.alpha_cutoff = 0.3f;
    m.double_sided = true;
    m.emission = vec3(4.0f, 2.0f, 1.0f);
    scene.materials[1].alpha_mode = AlphaMode::Blend;
    const Json json = glb_json(export_glb(scene));
    EXPECT_EQ(json["materials"][0]["alphaMode"], "MASK");
    EXPECT_EQ(json["materials"][1]["alphaMode"], "BLEND");

    const Scene back = round_trip(scene);
    const Material& b = back.materials[0];
    EXPECT_EQ(b.base_color, m.base_color);
    EXPECT_FLOAT_EQ(b.metallic, m.metallic);
    EXPECT_FLOAT_EQ(b.roughness, m.roughness);
    EXPECT_FLOAT_EQ(b.alpha, m.alpha);
    EXPECT_EQ(b.alpha_mode, AlphaMode::Mask);
    EXPECT_FLOAT_EQ(b.alpha_cutoff, 0.3f);
    EXPECT_TRUE(b.double_sided);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(b.emission[c], m.emission[c], 1e-6f);
    EXPECT_EQ(back.materials[1].alpha_mode, AlphaMode::Blend);
}

}  // namespace
}  // namespace rt
