// Malformed and hostile files: each must fail with a SceneError that names the
// element at fault, without reading out of bounds or allocating what a count
// asks for (these tests also run under AddressSanitizer and UBSan).
#include <cmath>
#include <limits>
#include <sstream>

#include <gtest/gtest.h>

#include "loader_test_util.h"
#include "load/scene_files.h"

namespace rt {
namespace {

using namespace rt::testing;

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// One indexed triangle, with normals; tests break one thing in it.
struct Triangle {
    GltfDoc doc;
    Triangle(std::vector<float> positions = {0, 0, 0, 1, 0, 0, 0, 1, 0},
             std::vector<float> normals = {0, 0, 1, 0, 0, 1, 0, 0, 1}) {
        doc.add_mesh_node({{"attributes", {{"POSITION", doc.add_vec3(positions)}, {"NORMAL", doc.add_vec3(normals)}}},
                           {"indices", doc.add_indices({0, 1, 2})}});
    }
    Json& primitive() { return doc.json["meshes"][0]["primitives"][0]; }
    std::string error() const { return scene_error([&] { load_text(doc.text(), "h.gltf"); }); }
    std::string glb_error() const { return scene_error([&] { load_bytes(doc.glb(), "h.glb"); }); }
};

#define EXPECT_MENTIONS(error, part) EXPECT_TRUE(contains(error, part)) << (error)

TEST(LoaderHostile, NanPositionNamesAccessorAndElement) {
    EXPECT_MENTIONS(Triangle({0, 0, 0, kNaN, 0, 0, 0, 1, 0}).error(),
                    "h.gltf: meshes[0].primitives[0] POSITION (accessors[0]) element 1 is not finite");
}

TEST(LoaderHostile, InfiniteNormalNamesAccessorAndElement) {
    const float inf = std::numeric_limits<float>::infinity();
    EXPECT_MENTIONS(Triangle({0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 0, 1, 0, 0, 1, 0, inf, 1}).error(),
                    "NORMAL (accessors[1]) element 2 is not finite");
}

TEST(LoaderHostile, TransformsThatLeaveFloatRangeAreRefused) {
    Triangle huge;
    huge.doc.json["nodes"][0]["scale"] = {1e300, 1, 1};
    EXPECT_MENTIONS(huge.error(), "element 1 is not finite after the node transform");
    Triangle nested;
    nested.doc.json["nodes"][0]["scale"] = {1e200, 1e200, 1e200};
    nested.doc.json["scenes"][0]["nodes"] = {1};
    nested.doc.json["nodes"].push_back({{"scale", {1e200, 1e200, 1e200}}, {"children", {0}}});
    EXPECT_MENTIONS(nested.error(), "nodes[0]: its world transform is not finite");
    Triangle matrix;
    matrix.doc.json["nodes"][0]["matrix"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0};
    EXPECT_MENTIONS(matrix.error(), "nodes[0].matrix has 15 values, expected 16");
}

TEST(LoaderHostile, LightPositionOutOfRangeIsRefused) {
    Triangle t;
    t.doc.json["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}}};
    t.doc.add_root({{"translation", {0, 1e300, 0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    EXPECT_MENTIONS(t.error(), "nodes[1]: the position of KHR_lights_punctual.lights[0] is not finite");
    Triangle missing;
    missing.doc.add_root({{"extensions", {{"KHR_lights_punctual", {{"light", 3}}}}}});
    EXPECT_MENTIONS(missing.error(), "nodes[1].extensions.KHR_lights_punctual.light refers to light 3");
}

TEST(LoaderHostile, IndexOutOfRangeNamesTheIndex) {
    Triangle t;
    t.primitive()["indices"] = t.doc.add_indices({0, 1, 3});
    EXPECT_MENTIONS(t.error(), "meshes[0].primitives[0] index 3 (element 2) is out of range");
}

TEST(LoaderHostile, TruncatedDataUriBufferIsRefused) {
    Triangle t;
    Json json = Json::parse(t.doc.text());
    json["buffers"][0]["byteLength"] = 100;
    const std::string error = scene_error([&] { load_text(json.dump(), "h.gltf"); });
    EXPECT_MENTIONS(error, "buffers[0] declares byteLength 100 but its data: URI holds");
}

TEST(LoaderHostile, TruncatedExternalBufferIsRefused) {
    TempDir dir;
    Triangle t;
    dir.write("mesh.bin", Bytes(t.doc.data.begin(), t.doc.data.end() - 4));
    Json json = t.doc.json;
    json["buffers"] = {{{"byteLength", t.doc.data.size()}, {"uri", "mesh.bin"}}};
    const std::string error = scene_error([&] { load_scene(dir.write("h.gltf", json.dump())); });
    EXPECT_MENTIONS(error, "mesh.bin");
    EXPECT_MENTIONS(error, "size mismatch");
}

TEST(LoaderHostile, MissingExternalBufferIsRefused) {
    TempDir dir;
    Json json = Triangle().doc.json;
    json["buffers"] = {{{"byteLength", 84}, {"uri", "gone.bin"}}};
    EXPECT_MENTIONS(scene_error([&] { load_scene(dir.write("h.gltf", json.dump())); }), "gone.bin");
}

TEST(LoaderHostile, AccessorPastItsBufferViewIsRefused) {
    Triangle t;
    t.doc.json["accessors"][0]["count"] = 4;
    EXPECT_MENTIONS(t.error(), "POSITION (accessors[0]) has 4 elements from byteOffset 0, which reach past the end of "
                               "bufferViews[0] (36 bytes)");
    Triangle offset;
    offset.doc.json["accessors"][0]["byteOffset"] = 4;
    EXPECT_MENTIONS(offset.error(), "reach past the end of bufferViews[0]");
}

TEST(LoaderHostile, BufferViewPastItsBufferIsRefused) {
    Triangle t;
    t.doc.json["bufferViews"][1]["byteLength"] = 1000;
    EXPECT_MENTIONS(t.error(), "NORMAL (accessors[1]) uses bufferViews[1] (byteOffset 36, byteLength 1000), which "
                               "reaches past the end of buffers[0]");
}

TEST(LoaderHostile, HugeCountsAreRefusedWithoutAllocating) {
    for (const uint64_t count : {uint64_t(4294967295u), uint64_t(1) << 62, UINT64_MAX / 3}) {
        Triangle positions;
        positions.doc.json["accessors"][0]["count"] = count;
        EXPECT_MENTIONS(positions.error(), "reach past the end of bufferViews[0]");
        Triangle indices;
        indices.doc.json["accessors"][2]["count"] = count;
        EXPECT_MENTIONS(indices.error(), "indices (accessors[2]) has");
        Triangle offset;
        offset.doc.json["accessors"][0]["byteOffset"] = count;
        EXPECT_MENTIONS(offset.error(), "reach past the end of bufferViews[0]");
    }
}

TEST(LoaderHostile, StrideSmallerThanAnElementIsRefused) {
    Triangle t;
    t.doc.json["bufferViews"][0]["byteStride"] = 4;
    EXPECT_MENTIONS(t.error(), "has elements of 12 bytes, more than the byteStride 4 of bufferViews[0]");
}

TEST(LoaderHostile, UnsupportedComponentTypeIsNamed) {
    Triangle t;
    t.doc.json["accessors"][0]["componentType"] = 5124;  // INT, which not even KHR_mesh_quantization allows
    EXPECT_MENTIONS(t.error(), "POSITION (accessors[0]) has unsupported component type INT, expected FLOAT or BYTE or "
                               "UNSIGNED_BYTE or SHORT or UNSIGNED_SHORT");
    Triangle indices;
    indices.doc.json["accessors"][2]["componentType"] = 5126;
    EXPECT_MENTIONS(indices.error(), "indices (accessors[2]) has unsupported component type FLOAT");
    Triangle type;
    type.doc.json["accessors"][0]["type"] = "VEC4";
    EXPECT_MENTIONS(type.error(), "POSITION (accessors[0]) has type VEC4, expected VEC3");
}

TEST(LoaderHostile, UnknownPrimitiveModeIsRefused) {
    Triangle t;
    t.primitive()["mode"] = 7;
    EXPECT_MENTIONS(t.error(), "meshes[0].primitives[0] has unknown primitive mode 7");
    Triangle odd;
    odd.primitive()["indices"] = odd.doc.add_indices({0, 1, 2, 0});
    EXPECT_MENTIONS(odd.error(), "meshes[0].primitives[0] has 4 corners, not a multiple of 3");
}

TEST(LoaderHostile, SparseAccessorsAreChecked) {
    // Sparse over POSITION: indices from the index view (0, 1, 2), values from the positions' view.
    const auto sparse = [](int count, const std::string& indices_type = "UINT") {
        Triangle t;
        t.doc.json["accessors"][0]["sparse"] = {
            {"count", count},
            {"indices", {{"bufferView", 2}, {"componentType", indices_type == "UINT" ? 5125 : 5123}}},
            {"values", {{"bufferView", 0}}}};
        return t;
    };
    EXPECT_EQ(load_text(sparse(3).doc.text(), "h.gltf").positions.size(), 3u) << "a valid sparse accessor loads";
    EXPECT_MENTIONS(sparse(4).error(), "h.gltf: meshes[0].primitives[0] POSITION (accessors[0]) has sparse.count 4, "
                                       "which is not between 1 and its count 3");
    EXPECT_MENTIONS(sparse(0).error(), "has sparse.count 0");
    // As UNSIGNED_SHORT, the indices (0, 1, 2) read 0, 0, 1, 0, ...: not increasing.
    EXPECT_MENTIONS(sparse(2, "USHORT").error(), "sparse.indices element 1 = 0 after 0: sparse indices must be "
                                                 "strictly increasing");
    Triangle range = sparse(1);
    range.doc.add_indices({3});  // bufferViews[3]
    range.doc.json["accessors"][0]["sparse"]["indices"]["bufferView"] = 3;
    EXPECT_MENTIONS(range.error(), "sparse.indices element 0 = 3, out of range: the accessor has 3 elements");
    Triangle values = sparse(2);
    values.doc.json["accessors"][0]["sparse"]["values"]["byteOffset"] = 24;
    EXPECT_MENTIONS(values.error(), "sparse.values has 2 elements from byteOffset 24, which reach past the end of "
                                    "bufferViews[0] (36 bytes)");
    Triangle huge;
    huge.doc.json["accessors"][1].erase("bufferView");
    huge.doc.json["accessors"][1]["count"] = uint64_t(1) << 40;
    EXPECT_MENTIONS(huge.error(), "NORMAL (accessors[1]) has 1099511627776 elements without a bufferView: held in "
                                  "memory they would take more than the limit of 256 MiB");
}

TEST(LoaderHostile, NodeCyclesAndSharedChildrenAreRefused) {
    Triangle cycle;
    cycle.doc.json["nodes"][0]["children"] = {1};
    cycle.doc.json["nodes"].push_back({{"children", {0}}});
    EXPECT_MENTIONS(cycle.error(), "nodes[0] is reached twice (again from nodes[1].children)");
    Triangle self;
    self.doc.json["nodes"][0]["children"] = {0};
    EXPECT_MENTIONS(self.error(), "nodes[0] is reached twice");
    Triangle missing;
    missing.doc.json["nodes"][0]["children"] = {42};
    EXPECT_MENTIONS(missing.error(), "nodes[0].children refers to node 42, which does not exist");
}

TEST(LoaderHostile, DanglingReferencesAreNamed) {
    Triangle mesh;
    mesh.doc.json["nodes"][0]["mesh"] = 5;
    EXPECT_MENTIONS(mesh.error(), "nodes[0].mesh refers to mesh 5, which does not exist");
    Triangle material;
    material.primitive()["material"] = 2;
    EXPECT_MENTIONS(material.error(), "meshes[0].primitives[0].material refers to material 2");
    Triangle camera;
    camera.doc.json["nodes"][0]["camera"] = 0;
    EXPECT_MENTIONS(camera.error(), "nodes[0].camera refers to camera 0, which does not exist");
    Triangle scene;
    scene.doc.json["scene"] = 3;
    EXPECT_MENTIONS(scene.error(), "scene 3 does not exist");
    Triangle accessor;
    accessor.primitive()["attributes"]["NORMAL"] = 9;
    EXPECT_MENTIONS(accessor.error(), "NORMAL refers to accessor 9, which does not exist");
    Triangle count;
    count.primitive()["attributes"]["NORMAL"] = count.doc.add_vec3({0, 0, 1});
    EXPECT_MENTIONS(count.error(), "NORMAL (accessors[3]) has 1 elements, but POSITION has 3");
}

TEST(LoaderHostile, DeeplyNestedJsonIsRefusedBeforeParsing) {
    Triangle t;
    std::string text = t.doc.text();
    const std::string nest = std::string(100000, '[') + std::string(100000, ']');
    text.insert(text.rfind('}'), ", \"extras\": " + nest);
    EXPECT_MENTIONS(scene_error([&] { load_text(text, "deep.gltf"); }), "deep.gltf: JSON nesting is deeper than");
    EXPECT_MENTIONS(scene_error([] { load_text("{\"asset\": ", "bad.gltf"); }), "bad.gltf: invalid JSON");
}

TEST(LoaderHostile, TruncatedOrLyingGlbHeadersAreRefused) {
    const Bytes good = Triangle().doc.glb();
    const auto error_of = [](Bytes bytes) { return scene_error([&] { load_bytes(bytes, "h.glb"); }); };
    const auto put_u32 = [](Bytes& bytes, size_t offset, uint32_t value) { std::memcpy(&bytes[offset], &value, 4); };
    const auto with_u32 = [&](size_t offset, uint32_t value) {
        Bytes bytes = good;
        put_u32(bytes, offset, value);
        return bytes;
    };
    uint32_t json_length;
    std::memcpy(&json_length, &good[12], 4);
    const size_t bin_header = 20 + json_length;

    EXPECT_MENTIONS(error_of(Bytes(good.begin(), good.begin() + 10)), "too short for a GLB header");
    EXPECT_MENTIONS(error_of(with_u32(0, 0x12345678u)), "is not a GLB file");
    EXPECT_MENTIONS(error_of(with_u32(4, 1)), "GLB version 1 is not supported");
    EXPECT_MENTIONS(error_of(Bytes(good.begin(), good.end() - 8)), "(truncated file?)");
    EXPECT_MENTIONS(error_of(with_u32(8, 12)), "leaves no room for the JSON chunk");
    EXPECT_MENTIONS(error_of(with_u32(12, 0xFFFFFFF0u)), "GLB JSON chunk length 4294967280 reaches past the end");
    EXPECT_MENTIONS(error_of(with_u32(16, 0)), "first chunk is not of type JSON");
    // A BIN length that ends within the header's reach but past the data: tinygltf
    // 2.7's own bound forgets the 8-byte chunk header and would read beyond it.
    EXPECT_MENTIONS(error_of(with_u32(bin_header, uint32_t(good.size() - bin_header - 4))),
                    "GLB BIN chunk length");
    EXPECT_MENTIONS(error_of(with_u32(bin_header, 6)), "is not a positive multiple of 4");
    EXPECT_MENTIONS(error_of(with_u32(bin_header + 4, 0x41424344u)), "second chunk is not of type BIN");
    Bytes short_chunk(good.begin(), good.begin() + long(bin_header) + 4);
    put_u32(short_chunk, 8, uint32_t(short_chunk.size()));
    EXPECT_MENTIONS(error_of(short_chunk), "GLB chunk header after the JSON chunk is truncated");
    // The buffer claims more than the BIN chunk holds.
    Triangle big;
    big.doc.data.resize(big.doc.data.size() + 4);
    Bytes lying = big.doc.glb();
    EXPECT_NO_THROW(load_bytes(lying, "ok.glb"));
    put_u32(lying, bin_header, 84);  // fewer bytes than its byteLength of 88
    EXPECT_MENTIONS(error_of(lying), "byteLength");
}

// The 33 bytes of a PNG signature and IHDR chunk, claiming width x height.
Bytes png_header(uint32_t width, uint32_t height) {
    Bytes bytes = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n', 0, 0, 0, 13, 'I', 'H', 'D', 'R'};
    for (uint32_t v : {width, height})
        for (int shift = 24; shift >= 0; shift -= 8) bytes.push_back(uint8_t(v >> shift));
    bytes.insert(bytes.end(), {8, 2, 0, 0, 0, 0, 0, 0, 0});
    return bytes;
}

TEST(LoaderHostile, HugeImageIsRefusedFromItsHeader) {
    Triangle t;
    t.doc.json["images"] = {{{"uri", "data:image/png;base64," + base64(png_header(16000, 16000))}}};
    t.doc.json["textures"] = {{{"source", 0}}};
    t.doc.json["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
    t.primitive()["material"] = 0;
    EXPECT_MENTIONS(t.error(), "h.gltf: images[0] is 16000x16000 texels");
    // A broken image is only a warning: the surface keeps its colour.
    t.doc.json["images"] = {{{"uri", "data:image/png;base64," + base64(Bytes(40, 7))}}};
    const Scene scene = load_text(t.doc.text(), "h.gltf");
    EXPECT_TRUE(has_warning(scene, "images[0] is not a PNG, JPEG, BMP, TGA or WebP image"));
}

TEST(LoaderHostile, IntegerAttributesOutsideKhrMeshQuantizationAreRefused) {
    // Unnormalized integer texture coordinates are allowed (KHR_mesh_quantization); BYTE colours are not.
    Triangle t;
    t.primitive()["attributes"]["TEXCOORD_0"] = t.doc.add_accessor(std::vector<uint8_t>{0, 0, 7, 0, 0, 9}, 5121,
                                                                    "VEC2", 2);
    EXPECT_EQ(load_text(t.doc.text(), "h.gltf").texcoords[1], vec2(7, 0));
    t.primitive()["attributes"]["COLOR_0"] = t.doc.add_accessor(std::vector<int8_t>(12, 0), 5120, "VEC4", 4);
    EXPECT_MENTIONS(t.error(), "COLOR_0 (accessors[4]) has unsupported component type BYTE, expected FLOAT or "
                               "UNSIGNED_BYTE or UNSIGNED_SHORT");
    Triangle tangent;
    tangent.primitive()["attributes"]["TANGENT"] = tangent.doc.add_accessor(std::vector<int16_t>(12, 1), 5122,
                                                                            "VEC4", 4);
    EXPECT_MENTIONS(tangent.error(), "TANGENT (accessors[3]) has SHORT components that are not normalized");
}

TEST(LoaderHostile, ObjNonFiniteCoordinatesAreRefused) {
    // tinyobjloader reads 0e999 as 0 * inf: NaN. 1e39 is beyond float.
    EXPECT_MENTIONS(scene_error([] { load_text("v 0 0 0\nv 0e999 0 0\nv 0 1 0\nf 1 2 3\n", "n.obj"); }),
                    "n.obj: v #2 is not a finite float");
    const std::string huge_normal = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 1e39 0 0\nf 1//1 2//1 3//1\n";
    EXPECT_MENTIONS(scene_error([&] { load_text(huge_normal, "n.obj"); }), "n.obj: vn #1 is not a finite float");
    // tinyobjloader reads what it cannot parse as 0; we refuse it by line.
    EXPECT_MENTIONS(scene_error([] { load_text("v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n", "n.obj"); }),
                    "n.obj: line 2: v value 'nan' is not a finite number");
    EXPECT_MENTIONS(scene_error([] { load_text("v 0 0 0\r\nv 1 0 0\r\nvt 0.5 x\r\n", "n.obj"); }),
                    "n.obj: line 3: vt value 'x' is not a finite number");
    EXPECT_MENTIONS(scene_error([] { load_text("v 0 0 1e999\n", "n.obj"); }), "line 1: v value '1e999'");
    EXPECT_NO_THROW(load_text("v +1 -2 3e-2 # comment\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "ok.obj"));
}

TEST(LoaderHostile, ObjAndMtlExponentsThatOverflowTheParsersIntAreRefused) {
    // tinyobjloader sums exponent digits into an int: 2147483648 overflows it
    // (a fuzzer's find, in an MTL's Ns line).
    EXPECT_MENTIONS(scene_error([] { load_text("vp 1e2147483648\nv 0 0 0\n", "x.obj"); }),
                    "x.obj: line 1: the number '1e2147483648' has an exponent out of range");
    TempDir dir;
    dir.write("m.mtl", "newmtl a\nKd 1 0 0\nNs 5.E-0002147483649\n");
    const auto obj = dir.write("m.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n");
    EXPECT_MENTIONS(scene_error([&] { load_scene(obj); }), "m.obj: m.mtl: line 3: the number '5.E-0002147483649'");
    // Leading zeros are no overflow, and words with an 'e' are no numbers.
    dir.write("m.mtl", "newmtl e1234567890123\nNs 1e0000000000002\n");
    EXPECT_NO_THROW(load_scene(obj));
}

TEST(LoaderHostile, ObjIndicesOutOfRangeAreRefused) {
    const std::string vertices = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    EXPECT_MENTIONS(scene_error([&] { load_text(vertices + "f 1 2 9\n", "i.obj"); }),
                    "i.obj: object '' face 1: vertex index is out of range (3 vertices)");
    EXPECT_MENTIONS(scene_error([&] { load_text(vertices + "f 1 2 -4\n", "i.obj"); }), "vertex index is out of range");
    EXPECT_MENTIONS(scene_error([&] { load_text(vertices + "vn 0 0 1\nf 1//1 2//2 3//1\n", "i.obj"); }),
                    "normal index is out of range");
    EXPECT_MENTIONS(scene_error([&] { load_text(vertices + "f 1 2 0\n", "i.obj"); }), "i.obj: Failed parse `f' line");
}

TEST(LoaderHostile, ObjFaceWithMoreThan255CornersIsRefused) {
    // tinyobjloader counts corners in a byte: 256 wraps to 0, 258 to 2, 300 to 44.
    for (int corners : {256, 258, 300}) {
        std::ostringstream obj;
        for (int i = 0; i < corners; ++i) obj << "v " << std::cos(i * 0.02) << " " << std::sin(i * 0.02) << " 0\n";
        obj << "f";
        for (int i = 1; i <= corners; ++i) obj << " " << i;
        obj << "\n";
        EXPECT_MENTIONS(scene_error([&] { load_text(obj.str(), "big.obj"); }), "a face with more than 255 vertices");
    }
}

TEST(LoaderHostile, MtlNegativeOrNonFiniteValuesAreRefused) {
    TempDir dir;
    dir.write("m.mtl", "newmtl bad\nKd 0.5 -1 0.5\n");
    const std::string obj = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl bad\nf 1 2 3\n";
    EXPECT_MENTIONS(scene_error([&] { load_scene(dir.write("m.obj", obj)); }), "material 'bad' has a negative Kd");
    dir.write("m.mtl", "newmtl bad\nNs 1e400\n");
    EXPECT_MENTIONS(scene_error([&] { load_scene(dir.write("m.obj", obj)); }), "material 'bad' has a Kd, Ks or Ns");
}

TEST(LoaderHostile, MessagesAreOnePrintableLineOfUtf8) {
    // Messages quote what files hold and reach Python and JSON as text.
    EXPECT_EQ(printable("caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x98\x80"), "caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x98\x80");
    EXPECT_EQ(printable("a\xff\xfe\x1b[31mb\x7f"), "a???[31mb?");
    EXPECT_EQ(printable("line 1.)\nnext\tcolumn\r"), "line 1.) next column ");
    // Overlong forms, surrogates, code points past U+10FFFF, a character cut short.
    EXPECT_EQ(printable("\xc0\xaf \xed\xa0\x80 \xf4\x90\x80\x80 \xe2\x82"), "?? ??? ???? ??");
    // Cut at a character boundary, never inside one.
    EXPECT_EQ(printable("\xc3\xa9\xc3\xa9\xc3\xa9", 5), "\xc3\xa9\xc3\xa9...");
    EXPECT_EQ(in_quotes(std::string(200, 'x')), "'" + std::string(120, 'x') + "...'");
    // The loaders' messages go through it: a SceneError, a warning.
    EXPECT_EQ(std::string(SceneError("m.obj: 'n\xff'\n").what()), "m.obj: 'n?' ");
    const Scene scene = load_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl \xff\xfe\nf 1 2 3\n", "u.obj");
    for (const std::string& warning : scene.warnings) EXPECT_EQ(printable(warning), warning);
    EXPECT_MENTIONS(scene_error([] { load_text("{\"asset\": \"" + std::string(100000, 'A') + "\xff\"}", "u.gltf"); }),
                    "u.gltf: invalid JSON");
    EXPECT_LE(scene_error([] { load_text("{\"asset\": \"" + std::string(100000, 'A') + "\xff\"}", "u.gltf"); }).size(),
              kMaxMessageBytes);
}

}  // namespace
}  // namespace rt
