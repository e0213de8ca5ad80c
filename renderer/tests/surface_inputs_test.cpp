// glTF's surface inputs beyond the base colour: emission, alpha (MASK and
// BLEND, for every ray kind alike), vertex colours and the occlusion map's
// reach, each against what the specification says the pixel must be.
#include <cmath>

#include <gtest/gtest.h>

#include "geometry/accel.h"
#include "geometry/surface_material.h"
#include "integrator/render.h"
#include "load/light_rig.h"
#include "test_scenes.h"

namespace rt {
namespace {

using namespace rt::testing;

Light sun_from_above(float lux) {
    Light sun;
    sun.kind = DIRECTIONAL;
    sun.direction = {0.0f, -1.0f, 0.0f};
    sun.intensity = vec3(lux);
    return sun;
}

// Per-vertex alpha on the last quad added: `left` on its first and last
// corners (x = c.x), `right` on the other two.
void set_quad_alpha(Scene& scene, float left, float right) {
    scene.colors.resize(scene.positions.size(), glm::vec4(1.0f));
    const size_t base = scene.positions.size() - 4;
    scene.colors[base] = scene.colors[base + 3] = glm::vec4(1.0f, 1.0f, 1.0f, left);
    scene.colors[base + 1] = scene.colors[base + 2] = glm::vec4(1.0f, 1.0f, 1.0f, right);
}

// A white floor at y = 0 lit by a sun straight above, under a card at y = 1
// spanning x in [-1, 1] whose alpha runs from `left` to `right`; a camera
// above the card looks straight down with a 90 degree view: x in [-2, 2] on
// the floor, [-1, 1] on the card, so every pixel looks through the card.
struct CardScene {
    Scene scene;
    uint32_t card_material;

    CardScene(AlphaMode mode, float left, float right) {
        const uint32_t floor = add_material(scene, vec3(1.0f));
        add_quad(scene, {-10.0f, 0.0f, 10.0f}, {20.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -20.0f}, floor);
        scene.colors.assign(scene.positions.size(), glm::vec4(1.0f));
        card_material = add_material(scene, vec3(0.0f));
        scene.materials[card_material].alpha_mode = mode;
        add_quad(scene, {-1.0f, 1.0f, 10.0f}, {2.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -20.0f}, card_material);
        set_quad_alpha(scene, left, right);
        scene.lights.push_back(sun_from_above(kPi));  // a white floor in full sun shows 1
    }
    Camera camera() const { return make_camera({0.0f, 2.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, 90.0f, {0.0f, 0.0f, -1.0f}); }
};

TEST(SurfaceInputs, MaskedTexelsAreHolesForCameraAndShadowRays) {
    CardScene card(AlphaMode::Mask, 0.0f, 1.0f);  // alpha < 0.5 (x < 0) is a hole
    const Accelerator accel(card.scene, 1);
    // Row 20 of 40: floor x from -2 to 2.
    const Renderer renderer(accel, make_settings(40, 40), card.camera());
    for (uint32_t x = 0; x < 40; ++x) {
        const float px = -2.0f + (float(x) + 0.5f) * 0.1f;
        if (std::abs(px) < 0.15f) continue;  // the edge of the hole
        // Through the hole the floor shows, lit through the same hole or from
        // beside the card; the card's covered half is black.
        EXPECT_NEAR(render_pixel(renderer, x, 20).x, px < 0.0f ? 1.0f : 0.0f, 1e-4f) << "x " << px;
    }
    // Under the covered half, outside the camera's view of the card, the floor
    // is in the card's shadow: a ray from below the card's solid half is stopped.
    const Ray up_solid{{0.5f, 0.001f, 0.0f}, {0.0f, 1.0f, 0.0f}, 10.0f};
    const Ray up_hole{{-0.5f, 0.001f, 0.0f}, {0.0f, 1.0f, 0.0f}, 10.0f};
    EXPECT_TRUE(accel.occluded(up_solid));
    EXPECT_FALSE(accel.occluded(up_hole));
    Hit hit;
    EXPECT_FALSE(accel.intersect(Ray{{-0.5f, 5.0f, 0.0f}, {0.0f, -1.0f, 0.0f}, 4.5f}, hit));
    EXPECT_TRUE(accel.intersect(Ray{{0.5f, 5.0f, 0.0f}, {0.0f, -1.0f, 0.0f}, 4.5f}, hit));
}

TEST(SurfaceInputs, BlendIsSeeThroughInProportionToAlphaForEveryRayKind) {
    CardScene card(AlphaMode::Blend, 0.25f, 0.25f);
    const Accelerator accel(card.scene, 1);
    // A shadow ray through the card keeps 1 - alpha of the light. (Not along
    // the quad's diagonal: a ray through the edge two triangles share meets both.)
    EXPECT_NEAR(accel.visibility(Ray{{0.3f, 0.001f, 0.0f}, {0.0f, 1.0f, 0.0f}, 10.0f}), 0.75f, 1e-6f);
    // The camera sees a quarter of the black card and three quarters of the
    // floor behind it, which the card's shadow dims to three quarters...
    const Renderer renderer(accel, make_settings(40, 40), card.camera());
    EXPECT_NEAR(render_pixel(renderer, 16, 20).x, 0.75f * 0.75f, 1e-4f);
    // ...except beside the card (floor x below -1), where it is fully lit.
    EXPECT_NEAR(render_pixel(renderer, 2, 20).x, 0.75f, 1e-4f);
}

TEST(SurfaceInputs, AFullyOpaqueAlphaSceneRendersLikeTheOpaqueOne) {
    CardScene blended(AlphaMode::Blend, 1.0f, 1.0f);
    CardScene opaque(AlphaMode::Opaque, 1.0f, 1.0f);
    const Accelerator a(blended.scene, 1), b(opaque.scene, 1);
    const Renderer ra(a, make_settings(40, 40), blended.camera()), rb(b, make_settings(40, 40), opaque.camera());
    for (uint32_t x = 0; x < 40; ++x) EXPECT_EQ(render_pixel(ra, x, 20), render_pixel(rb, x, 20)) << x;
}

TEST(SurfaceInputs, EmissionIsSeenDirectlyAndInMirrors) {
    Scene scene;
    const uint32_t glow = add_material(scene, vec3(0.0f));
    scene.materials[glow].emission = vec3(2.0f, 1.0f, 0.5f);
    // An emitter facing +z at z = -3, and a mirror at z = 3 facing -z; no lights.
    add_quad(scene, {-1.0f, -1.0f, -3.0f}, {2.0f, 0.0f, 0.0f}, {0.0f, 2.0f, 0.0f}, glow);
    const uint32_t mirror = add_material(scene, vec3(0.0f), vec3(0.0f), 1.0f, vec3(0.5f));
    add_quad(scene, {-5.0f, -5.0f, 3.0f}, {0.0f, 10.0f, 0.0f}, {10.0f, 0.0f, 0.0f}, mirror);
    const Accelerator accel(scene, 1);
    const Renderer ahead(accel, make_settings(1, 1), make_camera({0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -1.0f}));
    const vec3 direct = render_pixel(ahead, 0, 0);
    EXPECT_NEAR(direct.x, 2.0f, 1e-5f);
    EXPECT_NEAR(direct.z, 0.5f, 1e-5f);
    // Looking at the mirror: half of the emitter, which lies behind the camera.
    const Renderer behind(accel, make_settings(1, 1), make_camera({0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 1.0f}));
    EXPECT_NEAR(render_pixel(behind, 0, 0).x, 1.0f, 1e-5f);
}

TEST(SurfaceInputs, AnUnlitSurfaceShowsItsBaseColourWhateverLightsIt) {
    // KHR_materials_unlit: the card shows base colour × vertex colour under a
    // bright sun, in the dark, and in its own shadow alike; the floor under it
    // is still shadowed by it.
    CardScene lit(AlphaMode::Opaque, 1.0f, 1.0f);
    Material& card = lit.scene.materials[lit.card_material];
    card.metallic_roughness = true;
    card.base_color = vec3(0.25f, 0.5f, 0.75f);
    card.unlit = true;
    const vec3 expected = card.base_color;
    CardScene dark = lit;
    dark.scene.lights.clear();
    for (Scene* scene : {&lit.scene, &dark.scene}) {
        const Accelerator accel(*scene, 1);
        const Renderer renderer(accel, make_settings(4, 4), lit.camera());
        const vec3 got = render_pixel(renderer, 2, 2);
        EXPECT_NEAR(got.x, expected.x, 1e-5f);
        EXPECT_NEAR(got.y, expected.y, 1e-5f);
        EXPECT_NEAR(got.z, expected.z, 1e-5f);
    }
    SurfaceHit s;
    s.material = lit.card_material;
    s.color = glm::vec4(0.5f, 1.0f, 1.0f, 1.0f);
    const SurfaceMaterial sm = surface_material(lit.scene, card, s);
    EXPECT_EQ(sm.diffuse, vec3(0.0f));
    EXPECT_EQ(sm.specular, vec3(0.0f));
    EXPECT_NEAR(sm.emission.x, 0.125f, 1e-6f);
    // The floor beside the card is in full sun; under it, in the card's shadow.
    const Accelerator accel(lit.scene, 1);
    const auto floor_at = [&](float x) {
        const Renderer below(accel, make_settings(1, 1),
                             make_camera({x, 0.5f, 0.0f}, {x, 0.0f, 0.0f}, 10.0f, {0.0f, 0.0f, -1.0f}));
        return render_pixel(below, 0, 0).x;
    };
    EXPECT_NEAR(floor_at(5.0f), 1.0f, 1e-3f);
    EXPECT_NEAR(floor_at(0.0f), 0.0f, 1e-6f);
}

TEST(SurfaceInputs, VertexColoursMultiplyTheBaseColour) {
    Scene scene;
    const uint32_t m = add_material(scene, vec3(0.8f));
    scene.materials[m].metallic_roughness = true;
    scene.materials[m].base_color = vec3(0.8f);
    add_quad(scene, {-1.0f, -1.0f, -2.0f}, {2.0f, 0.0f, 0.0f}, {0.0f, 2.0f, 0.0f}, m);
    SurfaceHit s;
    s.material = m;
    s.color = glm::vec4(0.5f, 1.0f, 0.25f, 1.0f);
    const SurfaceMaterial sm = surface_material(scene, scene.materials[m], s);
    EXPECT_NEAR(sm.diffuse.x, 0.4f, 1e-6f);
    EXPECT_NEAR(sm.diffuse.y, 0.8f, 1e-6f);
    EXPECT_NEAR(sm.diffuse.z, 0.2f, 1e-6f);
    EXPECT_NEAR(sm.specular.x, 0.04f, 1e-6f);  // a dielectric's F0 does not take the colour
}

TEST(SurfaceInputs, MetallicAndRoughnessMapThroughTheLoadersMapping) {
    const PhongTerms metal = phong_from_metallic_roughness(vec3(0.9f, 0.6f, 0.3f), 1.0f, 0.0f);
    EXPECT_EQ(metal.diffuse, vec3(0.0f));
    EXPECT_EQ(metal.specular, vec3(0.9f, 0.6f, 0.3f));
    EXPECT_EQ(metal.shininess, 10000.0f);
    EXPECT_EQ(metal.reflectance, metal.specular);
    const PhongTerms plastic = phong_from_metallic_roughness(vec3(1.0f), 0.0f, 1.0f);
    EXPECT_EQ(plastic.diffuse, vec3(1.0f));
    EXPECT_EQ(plastic.specular, vec3(0.04f));
    EXPECT_EQ(plastic.shininess, 1.0f);
    EXPECT_EQ(plastic.reflectance, vec3(0.0f));
}

// The occlusion map stands in for ambient occlusion: it darkens the default
// rig's fill light, the scene's stand-in for ambient light, and nothing else.
TEST(SurfaceInputs, OcclusionDarkensTheRigsFillOnly) {
    Scene scene;
    const uint32_t m = add_material(scene, vec3(0.5f));
    add_quad(scene, {-10.0f, 0.0f, 10.0f}, {20.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -20.0f}, m);
    scene.cameras.push_back({"view", make_camera({0.0f, 3.0f, 3.0f}, {0.0f, 0.0f, 0.0f})});
    add_light_rig(scene);
    ASSERT_EQ(scene.rig_lights, 2u);
    const auto render = [&](float occlusion, bool without_key) {
        Scene copy = scene;
        if (without_key) {  // the fill stays the last light
            copy.lights.erase(copy.lights.end() - 2);
            copy.rig_lights = 1;
        }
        if (occlusion < 1.0f) {
            copy.texcoords.assign(copy.positions.size(), vec2(0.5f));
            // A linear 8-bit grey: 0.6 is code 153 exactly.
            copy.textures.push_back(
                Texture(1, 1, 1, Texture::Encoding::Linear, {uint8_t(std::lround(occlusion * 255.0f))}));
            copy.materials[m].occlusion_texture.index = 0;
        }
        const Accelerator accel(copy, 1);
        const Renderer renderer(accel, make_settings(1, 1), copy.cameras[0].camera);
        return render_pixel(renderer, 0, 0).x;
    };
    const float both = render(1.0f, false), fill = render(1.0f, true);
    ASSERT_GT(fill, 0.0f);
    ASSERT_GT(both, fill);  // the key lights the point too
    EXPECT_NEAR(render(0.6f, true), 0.6f * fill, 1e-5f);
    EXPECT_NEAR(render(0.6f, false), both - 0.4f * fill, 1e-5f);
}

}  // namespace
}  // namespace rt
