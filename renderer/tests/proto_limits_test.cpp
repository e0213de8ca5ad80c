#include "util/proto_limits.h"

#include <stdexcept>

#include <gtest/gtest.h>

#include "rt/render.pb.h"
#include "rt/scene.pb.h"

namespace rt {
namespace {

std::string error_of(std::string_view json, google::protobuf::Message& message) {
    try {
        parse_json_message(json, message, "settings");
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "";
}

TEST(ProtoLimits, AbsentFieldsTakeTheSchemaDefaults) {
    RenderSettings settings;
    parse_json_message("{}", settings, "settings");
    EXPECT_EQ(settings.width(), 640u);
    EXPECT_EQ(settings.height(), 480u);
    EXPECT_EQ(settings.max_depth(), 5u);
    EXPECT_FLOAT_EQ(settings.min_contribution(), 0.001f);
}

TEST(ProtoLimits, SamplingSettingsHaveTheirDefaultsAndLimits) {
    RenderSettings settings;
    parse_json_message("{}", settings, "settings");
    EXPECT_EQ(settings.samples_per_pixel(), 1u);
    EXPECT_EQ(settings.adaptive_threshold(), 0.0f);
    // Absent enums are their zero value, which is the default.
    EXPECT_EQ(settings.pixel_filter(), GAUSSIAN);
    EXPECT_EQ(settings.light_sampling(), CONE);
    EXPECT_FALSE(settings.has_pixel_filter());
    RenderSettings given;
    parse_json_message(R"({"pixelFilter": "GRID", "light_sampling": "SPHERE", "samplesPerPixel": 4})", given,
                       "settings");
    EXPECT_EQ(given.pixel_filter(), GRID);
    EXPECT_EQ(given.light_sampling(), SPHERE);
    RenderSettings zero;
    EXPECT_EQ(error_of(R"({"samplesPerPixel": 0})", zero), "settings.samples_per_pixel: 0 is below the minimum 1");
    RenderSettings many;
    EXPECT_EQ(error_of(R"({"samplesPerPixel": 65537})", many),
              "settings.samples_per_pixel: 65537 is above the maximum 65536");
    RenderSettings negative;
    EXPECT_EQ(error_of(R"({"adaptiveThreshold": -0.1})", negative),
              "settings.adaptive_threshold: -0.1 is below the minimum 0");
    RenderSettings unknown;
    EXPECT_NE(error_of(R"({"pixelFilter": "LANCZOS"})", unknown).find("LANCZOS"), std::string::npos);
}

// Proto3 enums are open: serialized input may hold numbers the schema never named.
TEST(ProtoLimits, UnnamedEnumValuesAreRefused) {
    RenderSettings settings;
    settings.set_pixel_filter(PixelFilter(7));
    try {
        apply_limits(settings, "settings");
        FAIL() << "pixel filter 7 accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_STREQ(e.what(), "settings.pixel_filter: 7 is not one of GAUSSIAN, BOX, TENT, GRID");
    }
    RenderSettings numeric;
    EXPECT_EQ(error_of(R"({"lightSampling": 1})", numeric), "");
    EXPECT_EQ(numeric.light_sampling(), SPHERE);
}

TEST(ProtoLimits, GivenFieldsAreKept) {
    RenderSettings settings;
    parse_json_message(R"({"width": 64, "maxDepth": 0})", settings, "settings");
    EXPECT_EQ(settings.width(), 64u);
    EXPECT_EQ(settings.max_depth(), 0u);  // an explicit zero is not replaced by the default
}

TEST(ProtoLimits, OutOfRangeValuesNameTheField) {
    RenderSettings settings;
    EXPECT_EQ(error_of(R"({"width": 0})", settings), "settings.width: 0 is below the minimum 1");
    RenderSettings other;
    EXPECT_EQ(error_of(R"({"height": 20000})", other), "settings.height: 20000 is above the maximum 16384");
}

TEST(ProtoLimits, UnknownFieldsAndBadJsonAreRefused) {
    RenderSettings settings;
    EXPECT_NE(error_of(R"({"widht": 10})", settings).find("widht"), std::string::npos);
    RenderSettings other;
    EXPECT_NE(error_of("{", other).find("invalid JSON"), std::string::npos);
}

TEST(ProtoLimits, VectorsNeedTheirCountAndRequiredFieldsTheirPresence) {
    Camera camera;
    EXPECT_EQ(error_of(R"({"position": [0, 1], "target": [0, 0, 0]})", camera),
              "settings.position: needs 3 values, got 2");
    Camera missing;
    EXPECT_EQ(error_of(R"({"position": [0, 1, 2]})", missing), "settings.target: is required");
}

TEST(ProtoLimits, NestedMessagesAreCheckedWithTheirPath) {
    SceneExtras extras;
    try {
        parse_json_message(R"({"lights": [{"position": [0, 0, 0]}, {"position": [0, 0, 0], "intensity": -1}]})",
                           extras, "extras");
        FAIL() << "negative intensity accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_STREQ(e.what(), "extras.lights[1].intensity: -1 is below the minimum 0");
    }
    EXPECT_FLOAT_EQ(extras.lights(0).intensity(), 1.0f);
}

TEST(ProtoLimits, NonFiniteNumbersAreRefused) {
    Camera camera;
    EXPECT_EQ(error_of(R"({"position": [0, "NaN", 0], "target": [0, 0, 0]})", camera),
              "settings.position[1]: must be a finite number");
}

TEST(ProtoLimits, FloatFieldsAdmitTheirLimitsRoundedToFloat) {
    // 1e30 is not a float; the nearest float lies above it and must still pass.
    SceneExtras at_limits;
    EXPECT_EQ(error_of(R"({"spheres": [{"center": [0, 0, 0], "radius": 1e30}]})", at_limits), "");
    SceneExtras tiny;
    EXPECT_EQ(error_of(R"({"spheres": [{"center": [0, 0, 0], "radius": 1e-30}]})", tiny), "");
    SceneExtras beyond;
    EXPECT_EQ(error_of(R"({"spheres": [{"center": [0, 0, 0], "radius": 2e30}]})", beyond),
              "settings.spheres[0].radius: 2e+30 is above the maximum 1e+30");
}

}  // namespace
}  // namespace rt
