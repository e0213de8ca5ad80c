// Every kind of data: URI the glTF spec allows (buffers as
// application/octet-stream and application/gltf-buffer, images as PNG, JPEG and,
// with EXT_texture_webp, WebP), each loaded; malformed ones refused by name.
#include <gtest/gtest.h>
#include <webp/encode.h>

#include "loader_test_util.h"

namespace rt {
namespace {

using namespace rt::testing;

#define EXPECT_MENTIONS(error, part) EXPECT_TRUE(contains(error, part)) << (error)

// A textured triangle: its document, with `buffers` filled in by the test.
GltfDoc textured_triangle() {
    GltfDoc doc;
    doc.add_mesh_node({{"attributes",
                        {{"POSITION", doc.add_vec3({0, 0, 0, 1, 0, 0, 0, 1, 0})},
                         {"TEXCOORD_0", doc.add_vec2({0, 0, 1, 0, 0, 1})}}},
                       {"material", 0}});
    doc.json["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
    doc.json["textures"] = {{{"source", 0}}};
    return doc;
}

// 2x2 RGB texels, row by row.
const std::vector<unsigned char> kTexels = {200, 10, 10, 10, 200, 10, 10, 10, 200, 90, 90, 90};

Bytes jpeg(int width, int height, const std::vector<unsigned char>& rgb) {
    Bytes out;
    stbi_write_jpg_to_func(
        [](void* context, void* data, int size) {
            auto* bytes = static_cast<Bytes*>(context);
            bytes->insert(bytes->end(), static_cast<unsigned char*>(data), static_cast<unsigned char*>(data) + size);
        },
        &out, width, height, 3, rgb.data(), 100);
    return out;
}

Bytes webp(int width, int height, const std::vector<unsigned char>& rgb) {
    uint8_t* encoded = nullptr;
    const size_t size = WebPEncodeLosslessRGB(rgb.data(), width, height, width * 3, &encoded);
    Bytes out(encoded, encoded + size);
    WebPFree(encoded);
    return out;
}

TEST(LoaderDataUri, BuffersLoadFromBothMediaTypes) {
    for (const std::string media : {"application/octet-stream", "application/gltf-buffer"}) {
        GltfDoc doc = textured_triangle();
        doc.json.erase("materials");
        doc.json["meshes"][0]["primitives"][0].erase("material");
        Json json = Json::parse(doc.text());
        json["buffers"][0]["uri"] = "data:" + media + ";base64," + base64(doc.data);
        const Scene scene = load_text(json.dump(), "b.gltf");
        ASSERT_EQ(scene.positions.size(), 3u) << media;
        EXPECT_EQ(scene.positions[1], vec3(1, 0, 0)) << media;
    }
}

TEST(LoaderDataUri, ImagesLoadFromPngJpegAndWebp) {
    struct Kind {
        std::string media;
        Bytes image;
        int tolerance;  // JPEG is lossy
    };
    for (const Kind& kind : {Kind{"image/png", png(2, 2, kTexels), 0}, Kind{"image/jpeg", jpeg(2, 2, kTexels), 40},
                             Kind{"image/webp", webp(2, 2, kTexels), 0}}) {
        GltfDoc doc = textured_triangle();
        doc.json["images"] = {{{"uri", "data:" + kind.media + ";base64," + base64(kind.image)}}};
        if (kind.media == "image/webp") {
            doc.json["textures"] = {{{"extensions", {{"EXT_texture_webp", {{"source", 0}}}}}}};
            doc.json["extensionsUsed"] = {"EXT_texture_webp"};
            doc.json["extensionsRequired"] = {"EXT_texture_webp"};
        }
        for (const bool binary : {false, true}) {
            const Scene scene = binary ? load_bytes(doc.glb(), "i.glb") : load_text(doc.text(), "i.gltf");
            ASSERT_EQ(scene.textures.size(), 1u) << kind.media;
            const Texture& t = scene.textures[0];
            ASSERT_EQ(t.width, 2) << kind.media;
            ASSERT_EQ(t.height, 2) << kind.media;
            ASSERT_EQ(t.channels, 3) << kind.media;
            for (size_t k = 0; k < kTexels.size(); ++k)
                EXPECT_NEAR(int(t.levels[0].texels[k]), int(kTexels[k]), kind.tolerance) << kind.media << " " << k;
        }
    }
}

TEST(LoaderDataUri, MalformedBufferUrisAreRefusedByName) {
    GltfDoc doc = textured_triangle();
    doc.json.erase("materials");
    doc.json["meshes"][0]["primitives"][0].erase("material");
    const std::string payload = base64(doc.data);
    const auto error = [&](const std::string& uri) {
        Json json = Json::parse(doc.text());
        json["buffers"][0]["uri"] = uri;
        return scene_error([&] { load_text(json.dump(), "m.gltf"); });
    };
    const std::string octet = "data:application/octet-stream;base64,";
    EXPECT_MENTIONS(error(octet + "AB!D" + payload.substr(4)),
                    "m.gltf: buffers[0].uri is a malformed data: URI: its base64 holds a character that is not "
                    "base64 at offset 2");
    EXPECT_MENTIONS(error(octet + "A=AA" + payload.substr(4)), "its base64 holds padding before its end");
    EXPECT_MENTIONS(error(octet + payload + "A"), "its base64 has a stray last character");
    EXPECT_MENTIONS(error(octet + payload + "==="), "is a malformed data: URI");
    EXPECT_MENTIONS(error("data:application/octet-stream," + payload), "is not base64");
    EXPECT_MENTIONS(error("data:application/octet-stream;base64"), "it has no ',' before its data");
    EXPECT_MENTIONS(error("data:text/plain;base64," + payload),
                    "buffers[0].uri is a data: URI of media type 'text/plain', but a buffer's must be "
                    "application/octet-stream or application/gltf-buffer");
    EXPECT_MENTIONS(error(octet + payload.substr(0, 8)), "declares byteLength");
}

TEST(LoaderDataUri, MalformedImageUrisAreRefusedByName) {
    const auto error = [](const std::string& uri) {
        GltfDoc doc = textured_triangle();
        doc.json["images"] = {{{"uri", uri}}};
        return scene_error([&] { load_text(doc.text(), "m.gltf"); });
    };
    EXPECT_MENTIONS(error("data:image/png;base64,"),
                    "m.gltf: images[0].uri is a malformed data: URI: it holds no data");
    EXPECT_MENTIONS(error("data:image/png;base64,!!!!"), "images[0].uri is a malformed data: URI");
    EXPECT_MENTIONS(error("data:image/png,rawbytes"), "is not base64");
    EXPECT_MENTIONS(error("data:application/octet-stream;base64," + base64(png(2, 2, kTexels))),
                    "images[0].uri is a data: URI of media type 'application/octet-stream', but an image's must be "
                    "an image type");
}

}  // namespace
}  // namespace rt
