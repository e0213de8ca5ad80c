// Shadow rays from surfaces at every scale from 1e-4 to 1e6 (tests/
// stability_scenes.h): started as spawn.h starts them, they never shadow a lit
// point nor light a shadowed one; started a fixed epsilon off, as the 2020
// report did, they do both, each epsilon at the scales it does not suit.
#include <string>

#include <gtest/gtest.h>

#include "stability_probes.h"

namespace rt {
namespace {

using namespace rt::testing;

constexpr uint32_t kImageSize = 96;

ShadowTally tally_of(const ShadowScene& scene, const std::string& method) {
    const std::vector<ShadowTally> tallies = tally_shadow_rays(scene, kImageSize);
    for (size_t m = 0; m < tallies.size(); ++m)
        if (kShadowOrigins[m].name == method) return tallies[m];
    throw std::invalid_argument("no shadow origin " + method);
}

ShadowTally tally_of(float scale, const std::string& scene_name, const std::string& method) {
    for (const ShadowScene& scene : shadow_scenes(scale))
        if (scene.name == scene_name) return tally_of(scene, method);
    throw std::invalid_argument("no shadow scene " + scene_name);
}

TEST(StabilitySelfIntersection, OursIsRightAtEveryScale) {
    for (float scale : shadow_scales()) {
        for (const ShadowScene& scene : shadow_scenes(scale)) {
            const ShadowTally ours = tally_of(scene, "ours");
            // Each scene fills a good part of the image with surfaces facing the light.
            EXPECT_GT(ours.pixels, kImageSize * kImageSize / 8) << scene.name << " at scale " << scale;
            EXPECT_EQ(ours.wrong, 0u) << scene.name << " at scale " << scale << (scene.lit ? ": shadowed" : ": lit");
        }
    }
}

// What makes the test above mean something: the same scenes and camera rays
// catch both ways a fixed epsilon fails.
TEST(StabilitySelfIntersection, FixedEpsilonsShadowLitPointsAtLargeScales) {
    // An epsilon below the rounding error of the hit point leaves the ray on,
    // or under, the surface it starts from.
    for (const char* scene : {"plane", "cube", "icosphere"}) {
        EXPECT_GT(tally_of(1e6f, scene, "eps_1e-3").share(), 0.005) << scene;
        EXPECT_GT(tally_of(1e3f, scene, "eps_1e-5").share(), 0.005) << scene;
    }
    EXPECT_EQ(tally_of(1.0f, "plane", "eps_1e-3").wrong, 0u);  // where the 2020 report's epsilon suits
}

TEST(StabilitySelfIntersection, FixedEpsilonsLightShadowedPointsAtSmallScales) {
    // An epsilon above the gap to the roof starts the ray above it.
    EXPECT_EQ(tally_of(1e-2f, "roof", "eps_1e-3").share(), 1.0);
    EXPECT_EQ(tally_of(1e-4f, "roof", "eps_1e-5").share(), 1.0);
    EXPECT_EQ(tally_of(1.0f, "roof", "eps_1e-3").wrong, 0u);
}

}  // namespace
}  // namespace rt
