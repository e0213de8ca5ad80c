// Normal maps: glTF's tangent-space formula, the MikkTSpace tangents the
// loader gives a mesh without TANGENT (with its vertex splits), mirrored uvs
// turning the bitangent, and what a render and its debug path show.
#include <gtest/gtest.h>

#include <cmath>

#include "geometry/accel.h"
#include "geometry/normal_map.h"
#include "integrator/render.h"
#include "load/generate_tangents.h"
#include "test_scenes.h"

namespace rt {
namespace {

using namespace rt::testing;

// The 8-bit code of a tangent-space component in [-1, 1], and its decoding.
uint8_t encode(float c) { return uint8_t(std::lround((c * 0.5f + 0.5f) * 255.0f)); }
float decode(uint8_t code) { return 2.0f * (float(code) / 255.0f) - 1.0f; }

TEST(NormalMap, BendNormalIsTheGltfFormula) {
    const vec3 n(0.0f, 0.0f, 1.0f);
    const vec3 m(0.3f, -0.2f, 0.9f);
    const vec3 texel = 0.5f * m + vec3(0.5f);
    // T = +x, w = +1: B = cross(N, T) = +y, the map's components land on x, y, z.
    const vec3 plain = bend_normal(n, glm::vec4(1.0f, 0.0f, 0.0f, 1.0f), texel, 1.0f);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(plain[k], glm::normalize(m)[k], 1e-6f);
    // The scale multiplies x and y only.
    const vec3 scaled = bend_normal(n, glm::vec4(1.0f, 0.0f, 0.0f, 1.0f), texel, 0.5f);
    const vec3 expected = glm::normalize(vec3(0.5f * m.x, 0.5f * m.y, m.z));
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(scaled[k], expected[k], 1e-6f);
    // w = -1 turns the bitangent: y lands on -y.
    const vec3 mirrored = bend_normal(n, glm::vec4(1.0f, 0.0f, 0.0f, -1.0f), texel, 1.0f);
    EXPECT_NEAR(mirrored.y, -glm::normalize(m).y, 1e-6f);
    EXPECT_NEAR(mirrored.x, glm::normalize(m).x, 1e-6f);
    // A tangent not orthogonal to N is made so (Gram-Schmidt) first.
    const vec3 skew = bend_normal(n, glm::vec4(1.0f, 0.0f, 5.0f, 1.0f), texel, 1.0f);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(skew[k], plain[k], 1e-6f);
    // No frame (a tangent along N, or none): N.
    EXPECT_EQ(bend_normal(n, glm::vec4(0.0f, 0.0f, 1.0f, 1.0f), texel, 1.0f), n);
    EXPECT_EQ(bend_normal(n, glm::vec4(1.0f, 0.0f, 0.0f, 0.0f), texel, 1.0f), n);
}

// The unit square in z = 0 facing +z, uv given per corner, its material
// normal-mapped by a one-texel map holding `m`, under a sun from `to_light`.
struct MappedSquare {
    Scene scene;
    vec3 texel_normal;  // the map's (x, y, z) as the texture decodes it
};

MappedSquare mapped_square(vec3 m, float scale, const std::vector<vec2>& uvs, vec3 to_light) {
    MappedSquare out;
    Scene& scene = out.scene;
    const uint32_t material = add_material(scene, vec3(0.6f));
    add_quad(scene, {-1.0f, -1.0f, 0.0f}, {2.0f, 0.0f, 0.0f}, {0.0f, 2.0f, 0.0f}, material);
    scene.texcoords = uvs;
    const std::vector<uint8_t> texel = {encode(m.x), encode(m.y), encode(m.z)};
    out.texel_normal = vec3(decode(texel[0]), decode(texel[1]), decode(texel[2]));
    scene.textures.push_back(Texture(1, 1, 3, Texture::Encoding::Linear, texel));
    scene.materials[material].normal_texture.index = 0;
    scene.materials[material].normal_scale = scale;
    Light sun;
    sun.kind = DIRECTIONAL;
    sun.direction = -glm::normalize(to_light);
    sun.intensity = vec3(2.0f);
    scene.lights.push_back(sun);
    generate_tangents(scene, "square");
    return out;
}

// What the centre pixel shows, seen from straight above, and its bent normal.
struct Seen {
    vec3 color;
    vec3 normal;
};

Seen seen_from_above(const Scene& scene) {
    const Accelerator accel(scene, 1);
    const Renderer renderer(accel, make_settings(9, 9), make_camera({0.0f, 0.0f, 4.0f}, vec3(0.0f), 20.0f));
    const DebugPath path = renderer.debug_pixel(4, 4);
    const auto& n = path.segments(0).normal();
    return {render_pixel(renderer, 4, 4), vec3(n[0], n[1], n[2])};
}

// glTF's uv: u along +x, v down the image, so v = 1 - y.
const std::vector<vec2> kUpright = {{0.0f, 1.0f}, {1.0f, 1.0f}, {1.0f, 0.0f}, {0.0f, 0.0f}};

TEST(NormalMap, ConstantTiltedMapTiltsTheShadingAsTheFormulaSays) {
    const vec3 m = glm::normalize(vec3(0.35f, 0.25f, 0.9f));
    const vec3 to_light = glm::normalize(vec3(0.6f, -0.3f, 0.75f));
    const float scale = 0.8f;
    const MappedSquare square = mapped_square(m, scale, kUpright, to_light);
    // MikkTSpace's frame here: T = +x and, for glTF's v, B = +y (w = +1).
    ASSERT_EQ(square.scene.tangents.size(), square.scene.positions.size());
    for (const glm::vec4& t : square.scene.tangents) {
        EXPECT_NEAR(t.x, 1.0f, 1e-6f);
        EXPECT_EQ(t.w, 1.0f);
    }
    const vec3 t = square.texel_normal;
    const vec3 bent = glm::normalize(vec3(scale * t.x, scale * t.y, t.z));
    const Seen seen = seen_from_above(square.scene);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(seen.normal[k], bent[k], 1e-5f);  // the debug path's (and AOV's) normal
    const float expected = 0.6f / kPi * 2.0f * glm::dot(bent, to_light);
    EXPECT_NEAR(seen.color.r, expected, 1e-4f * expected);
    // Unmapped, the same square is lit by cos = to_light.z: the map made the difference.
    EXPECT_GT(std::abs(seen.color.r - 0.6f / kPi * 2.0f * to_light.z), 0.02f);
}

TEST(NormalMap, MirroredUvsTurnTheBitangent) {
    const vec3 m = glm::normalize(vec3(0.3f, 0.4f, 0.85f));
    const vec3 to_light = glm::normalize(vec3(0.2f, 0.7f, 0.6f));
    // v up the square instead of down: the image is mirrored top to bottom.
    const std::vector<vec2> flipped = {{0.0f, 0.0f}, {1.0f, 0.0f}, {1.0f, 1.0f}, {0.0f, 1.0f}};
    const MappedSquare upright = mapped_square(m, 1.0f, kUpright, to_light);
    const MappedSquare mirrored = mapped_square(m, 1.0f, flipped, to_light);
    for (const glm::vec4& t : mirrored.scene.tangents) EXPECT_EQ(t.w, -1.0f);
    const vec3 t = mirrored.texel_normal;
    const Seen a = seen_from_above(upright.scene), b = seen_from_above(mirrored.scene);
    EXPECT_NEAR(a.normal.y, glm::normalize(t).y, 1e-5f);
    EXPECT_NEAR(b.normal.y, -glm::normalize(t).y, 1e-5f);  // B = -y
    EXPECT_NEAR(b.normal.x, glm::normalize(t).x, 1e-5f);
    // The light comes from +y: the mirrored tilt turns away from it.
    EXPECT_LT(b.color.r, a.color.r - 0.02f);
}

// Corners whose MikkTSpace tangents differ get vertices of their own, with
// every attribute; corners that agree keep sharing one.
TEST(NormalMap, VerticesSplitWhereCornersDisagree) {
    Scene scene;
    const uint32_t material = add_material(scene, vec3(0.6f));
    // Two triangles sharing the edge (1, 2), the right one's u mirrored: its
    // tangents point the other way, so vertices 1 and 2 split.
    scene.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {2, 0, 0}};
    scene.normals.assign(4, vec3(0, 0, 1));
    scene.texcoords = {{0, 1}, {1, 1}, {1, 0}, {0, 1}};
    scene.colors = {glm::vec4(0.1f), glm::vec4(0.2f), glm::vec4(0.3f), glm::vec4(0.4f)};
    scene.triangles = {{0, 1, 2}, {1, 3, 2}};
    scene.triangle_materials = {material, material};
    scene.textures.push_back(Texture(1, 1, 3, Texture::Encoding::Linear, {128, 128, 255}));
    scene.materials[material].normal_texture.index = 0;
    generate_tangents(scene, "split");
    ASSERT_EQ(scene.positions.size(), 6u);
    EXPECT_EQ(scene.normals.size(), 6u);
    EXPECT_EQ(scene.texcoords.size(), 6u);
    EXPECT_EQ(scene.colors.size(), 6u);
    EXPECT_EQ(scene.tangents.size(), 6u);
    const uvec3 left = scene.triangles[0], right = scene.triangles[1];
    EXPECT_EQ(left, uvec3(0, 1, 2));
    for (uint32_t v : {right.x, right.z}) {
        EXPECT_GE(v, 4u);  // copies of 1 and 2
        EXPECT_NEAR(scene.tangents[v].x, -1.0f, 1e-6f);
    }
    EXPECT_EQ(scene.positions[right.x], scene.positions[1]);
    EXPECT_EQ(scene.colors[right.z], scene.colors[2]);
    EXPECT_NEAR(scene.tangents[1].x, 1.0f, 1e-6f);
    EXPECT_EQ(scene.tangents[1].w, -scene.tangents[right.x].w);
}

// A material without a normal map, or a vertex with a tangent of its own,
// is left as it was.
TEST(NormalMap, OnlyMappedTrianglesWithoutTangentsGetThem) {
    Scene scene;
    add_material(scene, vec3(0.6f));
    add_quad(scene, {-1.0f, -1.0f, 0.0f}, {2.0f, 0.0f, 0.0f}, {0.0f, 2.0f, 0.0f}, 0);
    scene.texcoords = kUpright;
    generate_tangents(scene, "plain");
    EXPECT_TRUE(scene.tangents.empty());
    scene.textures.push_back(Texture(1, 1, 3, Texture::Encoding::Linear, {128, 128, 255}));
    scene.materials[0].normal_texture.index = 0;
    scene.tangents.assign(4, glm::vec4(0.0f, 1.0f, 0.0f, -1.0f));
    generate_tangents(scene, "given");
    for (const glm::vec4& t : scene.tangents) EXPECT_EQ(t, glm::vec4(0.0f, 1.0f, 0.0f, -1.0f));
    // Without the texture coordinates it reads: a warning, no tangents.
    Scene bare;
    add_material(bare, vec3(0.6f));
    add_quad(bare, {-1.0f, -1.0f, 0.0f}, {2.0f, 0.0f, 0.0f}, {0.0f, 2.0f, 0.0f}, 0);
    bare.materials[0].normal_texture.index = 0;
    generate_tangents(bare, "bare");
    EXPECT_TRUE(bare.tangents.empty());
    ASSERT_EQ(bare.warnings.size(), 1u);
}

}  // namespace
}  // namespace rt
