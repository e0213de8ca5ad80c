// OBJ + MTL loading: fan triangulation, relative indices, de-indexing of
// per-corner attributes, smoothing, the MTL to Phong mapping, map_Kd textures.
#include <sstream>

#include <gtest/gtest.h>

#include "loader_test_util.h"
#include "load/texture_decode.h"

namespace rt {
namespace {

using namespace rt::testing;

void expect_vec3(vec3 actual, vec3 expected, float eps = 1e-5f) {
    EXPECT_NEAR(actual.x, expected.x, eps);
    EXPECT_NEAR(actual.y, expected.y, eps);
    EXPECT_NEAR(actual.z, expected.z, eps);
}

const Material& material_named(const Scene& scene, const std::string& name) {
    for (const Material& m : scene.materials)
        if (m.name == name) return m;
    throw std::runtime_error("no material " + name);
}

TEST(LoaderObj, HandWrittenQuadsWithMaterialsAndRelativeIndices) {
    const Scene scene = load_scene(RT_TEST_DATA_DIR "/quads.obj");
    ASSERT_EQ(scene.triangles.size(), 4u);
    // Four corners with their own normal and texcoord, four of the floor without.
    EXPECT_EQ(scene.positions.size(), 8u);
    EXPECT_EQ(scene.texcoords.size(), 8u);
    EXPECT_EQ(scene.degenerate_triangles, 0u);

    const Material& matte = material_named(scene, "matte");
    expect_vec3(matte.diffuse, {0.7f, 0.6f, 0.5f});
    EXPECT_FLOAT_EQ(matte.shininess, 10.0f);
    expect_vec3(matte.reflectance, vec3(0.0f));  // illum 2: no mirror
    const Material& mirror = material_named(scene, "mirror");
    expect_vec3(mirror.specular, vec3(0.9f));
    EXPECT_FLOAT_EQ(mirror.shininess, 500.0f);
    expect_vec3(mirror.reflectance, vec3(0.9f));  // illum 3: ray traced reflection

    // The floor quad (f -6 -5 -1 -2) faces +y, with computed normals.
    const uvec3 floor = scene.triangles[2];
    EXPECT_EQ(scene.materials[scene.triangle_materials[2]].name, "mirror");
    expect_vec3(scene.positions[floor.x], {0, 0, 0});
    expect_vec3(scene.positions[floor.y], {1, 0, 0});
    expect_vec3(scene.positions[floor.z], {1, 0, -1});
    for (int k = 0; k < 3; ++k) expect_vec3(scene.normals[scene.triangles[2][k]], {0, 1, 0});
    // OBJ's v = 0 is the bottom of the image; ours is the top.
    EXPECT_EQ(scene.texcoords[scene.triangles[0].x], vec2(0.0f, 1.0f));
    EXPECT_EQ(scene.texcoords[scene.triangles[0].z], vec2(1.0f, 0.0f));
}

TEST(LoaderObj, PolygonsAreFannedFromTheirFirstCorner) {
    const Scene scene = load_text("v 0 0 0\nv 2 0 0\nv 3 1 0\nv 1 2 0\nv -1 1 0\nf -5 -4 -3 -2 -1\n", "p.obj");
    ASSERT_EQ(scene.triangles.size(), 3u);
    const vec3 first = scene.positions[scene.triangles[0].x];
    for (const uvec3& t : scene.triangles) {
        EXPECT_EQ(scene.positions[t.x], first);
        expect_vec3(scene.normals[t.y], {0, 0, 1});
    }
    expect_vec3(scene.positions[scene.triangles[2].z], {-1, 1, 0});
}

TEST(LoaderObj, EachDistinctCornerBecomesOneVertex) {
    // A cube: 8 positions, 6 normals; each corner of each face has its own
    // (position, normal) pair, so 24 vertices, each with its face's normal.
    std::string obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
                      "vn 0 0 -1\nvn 0 0 1\nvn 0 -1 0\nvn 0 1 0\nvn -1 0 0\nvn 1 0 0\n"
                      "f 1//1 4//1 3//1 2//1\nf 5//2 6//2 7//2 8//2\nf 1//3 2//3 6//3 5//3\n"
                      "f 4//4 8//4 7//4 3//4\nf 1//5 5//5 8//5 4//5\nf 2//6 3//6 7//6 6//6\n";
    const Scene scene = load_text(obj, "cube.obj");
    EXPECT_EQ(scene.triangles.size(), 12u);
    EXPECT_EQ(scene.positions.size(), 24u);
    for (const uvec3& t : scene.triangles) {
        const vec3 face = glm::normalize(glm::cross(scene.positions[t.y] - scene.positions[t.x],
                                                    scene.positions[t.z] - scene.positions[t.x]));
        for (int k = 0; k < 3; ++k) expect_vec3(scene.normals[t[k]], face);
    }
}

TEST(LoaderObj, MissingNormalsAreSmoothedAcrossTexcoordSeams) {
    // A roof: two faces meeting at the ridge (positions 2 and 3), with different
    // texcoords there. The ridge normal averages both faces all the same.
    const Scene scene = load_text("v 0 0 0\nv 0 1 1\nv 1 1 1\nv 1 0 0\nv 0 0 2\nv 1 0 2\n"
                                  "vt 0 0\nvt 1 0\nvt 0 1\nvt 1 1\n"
                                  "f 1/1 2/3 3/4 4/2\nf 2/1 5/3 6/4 3/2\n",
                                  "roof.obj");
    ASSERT_EQ(scene.triangles.size(), 4u);
    EXPECT_EQ(scene.positions.size(), 8u);
    int ridge_corners = 0;
    for (size_t v = 0; v < scene.positions.size(); ++v) {
        if (scene.positions[v].y != 1.0f) continue;
        expect_vec3(scene.normals[v], {0, 1, 0});
        ++ridge_corners;
    }
    EXPECT_EQ(ridge_corners, 4);  // two ridge positions, each split by the seam
}

TEST(LoaderObj, IllumModelsThreeFiveAndSevenReflect) {
    TempDir dir;
    std::ostringstream mtl, obj;
    obj << "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n";
    for (int illum = 0; illum <= 9; ++illum) {
        mtl << "newmtl m" << illum << "\nKs 0.5 0.25 0.125\nillum " << illum << "\n";
        obj << "usemtl m" << illum << "\nf 1 2 3\n";
    }
    dir.write("m.mtl", mtl.str());
    const Scene scene = load_scene(dir.write("m.obj", obj.str()));
    for (int illum = 0; illum <= 9; ++illum) {
        std::string name = "m";
        name += std::to_string(illum);
        const Material& m = material_named(scene, name);
        const bool mirror = illum == 3 || illum == 5 || illum == 7;
        expect_vec3(m.reflectance, mirror ? vec3(0.5f, 0.25f, 0.125f) : vec3(0.0f));
        expect_vec3(m.specular, {0.5f, 0.25f, 0.125f});
    }
}

TEST(LoaderObj, MapKdIsReadThroughTheFolderAndDecodedFromSrgb) {
    TempDir dir;
    dir.write("tex/wood.png", png(2, 1, {128, 128, 128, 255, 255, 255}));
    dir.write("m.mtl", "newmtl wood\nKd 1 1 1\nmap_Kd -clamp on tex/wood.png\n"
                       "newmtl same\nmap_Kd -clamp on tex/wood.png\n");
    const Scene scene = load_scene(dir.write("m.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\n"
                                                     "usemtl wood\nf 1/1 2/2 3/1\nusemtl same\nf 1/1 2/2 3/1\n"));
    ASSERT_EQ(scene.textures.size(), 1u);  // both materials share the decoded image
    const Material& wood = material_named(scene, "wood");
    ASSERT_EQ(wood.base_color_texture.index, 0);
    EXPECT_EQ(material_named(scene, "same").base_color_texture.index, 0);
    const Texture& texture = scene.textures[0];
    EXPECT_EQ(texture.wrap_s, Texture::Wrap::ClampToEdge);
    expect_vec3(vec3(texture.sample({0.25f, 0.5f})), vec3(srgb_to_linear(128.0f / 255.0f)));
    expect_vec3(vec3(texture.sample({0.0f, 0.5f})), vec3(srgb_to_linear(128.0f / 255.0f)));  // clamped, not wrapped
}

TEST(LoaderObj, MissingLibraryAndTextureAreWarningsNotErrors) {
    TempDir dir;
    dir.write("m.mtl", "newmtl a\nKd 1 0 0\nmap_Kd gone.png\n");
    const Scene scene = load_scene(dir.write("m.obj", "mtllib m.mtl\nmtllib nowhere.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"
                                                     "usemtl a\nf 1 2 3\nusemtl b\nf 1 3 2\n"));
    EXPECT_TRUE(has_warning(scene, "'nowhere.mtl' not found"));
    EXPECT_TRUE(has_warning(scene, "'gone.png' not found"));
    ASSERT_EQ(scene.triangles.size(), 2u);
    EXPECT_EQ(scene.materials[scene.triangle_materials[0]].name, "a");
    expect_vec3(scene.materials[scene.triangle_materials[1]].diffuse, vec3(0.8f));  // the default grey
}

TEST(LoaderObj, LinesAndPointsAreSkippedWithAWarning) {
    const Scene scene = load_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\np 3\nf 1 2 3\n", "l.obj");
    EXPECT_EQ(scene.triangles.size(), 1u);
    EXPECT_TRUE(has_warning(scene, "lines or points"));
}

TEST(LoaderObj, SkinWeightLinesAreIgnored) {
    // tinyobjloader's `vw` extension would convert 1e300 to int.
    const Scene scene = load_text("v 0 0 0\nv 1 0 0\nv 0 1 0\n  vw 0 1e300 0.5\r\nf 1 2 3\n", "w.obj");
    EXPECT_EQ(scene.triangles.size(), 1u);
}

}  // namespace
}  // namespace rt
