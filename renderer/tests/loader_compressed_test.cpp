// Compressed glTF geometry (EXT_meshopt_compression, KHR_draco_mesh_compression):
// streams encoded here with the libraries' own encoders must load as the data
// they encode, and each lie a hostile stream can tell must be refused with a
// SceneError naming it (these tests also run under ASan and UBSan).
#include <algorithm>
#include <array>
#include <cmath>

#include <draco/compression/encode.h>
#include <draco/mesh/triangle_soup_mesh_builder.h>
#include <draco/point_cloud/point_cloud_builder.h>
#include <gtest/gtest.h>
#include <meshoptimizer.h>

#include "loader_test_util.h"

namespace rt {
namespace {

using namespace rt::testing;

#define EXPECT_MENTIONS(error, part) EXPECT_TRUE(contains(error, part)) << (error)

// A bumpy n x n grid of vertices: enough of them that the codecs' blocks and
// tails are exercised, with no two triangles alike.
struct Grid {
    std::vector<float> positions, normals;
    std::vector<uint32_t> indices;
    explicit Grid(uint32_t n = 9) {
        for (uint32_t y = 0; y < n; ++y)
            for (uint32_t x = 0; x < n; ++x) {
                const float h = 0.1f * std::sin(float(x * 7 + y * 3));
                positions.insert(positions.end(), {float(x) * 0.25f, float(y) * 0.5f - 1.0f, h});
                const float l = std::sqrt(1.0f + h * h);
                normals.insert(normals.end(), {h / l, 0.0f, 1.0f / l});
            }
        for (uint32_t y = 0; y + 1 < n; ++y)
            for (uint32_t x = 0; x + 1 < n; ++x) {
                const uint32_t v = y * n + x;
                indices.insert(indices.end(), {v, v + 1, v + n, v + 1, v + n + 1, v + n});
            }
    }
    size_t vertices() const { return positions.size() / 3; }
};

using Corner = std::array<float, 3>;
using Face = std::array<Corner, 3>;

// The scene's triangles by their corners' positions, each rotated to start at
// its smallest corner (keeping its winding) and sorted: equal for two meshes
// that differ only in the order of their vertices and faces.
std::vector<Face> faces(const std::vector<vec3>& positions, const std::vector<uvec3>& triangles) {
    std::vector<Face> out;
    for (const uvec3& t : triangles) {
        Face f;
        for (int k = 0; k < 3; ++k) f[k] = {positions[t[k]].x, positions[t[k]].y, positions[t[k]].z};
        std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());
        out.push_back(f);
    }
    std::sort(out.begin(), out.end());
    return out;
}

std::vector<Face> faces(const Grid& grid) {
    std::vector<vec3> positions;
    for (size_t i = 0; i < grid.vertices(); ++i)
        positions.emplace_back(grid.positions[3 * i], grid.positions[3 * i + 1], grid.positions[3 * i + 2]);
    std::vector<uvec3> triangles;
    for (size_t i = 0; i < grid.indices.size(); i += 3)
        triangles.emplace_back(grid.indices[i], grid.indices[i + 1], grid.indices[i + 2]);
    return faces(positions, triangles);
}

Json fallback_buffer(size_t bytes) {
    return {{"byteLength", bytes}, {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}};
}

// A document whose views decode (meshopt) from the streams in buffers[0] into a
// fallback buffer without data, buffers[1].
struct MeshoptDoc {
    GltfDoc doc;
    Bytes streams;
    size_t fallback_bytes = 0;

    MeshoptDoc() { doc.json["extensionsRequired"] = {"EXT_meshopt_compression"}; }

    // A view of the fallback buffer decoded from `stream`; returns its index.
    int add_view(const Bytes& stream, size_t count, size_t stride, const char* mode, const char* filter = "NONE") {
        while (streams.size() % 4 != 0) streams.push_back(0);
        const Json extension = {{"buffer", 0}, {"byteOffset", streams.size()}, {"byteLength", stream.size()},
                                {"byteStride", stride}, {"count", count}, {"mode", mode}, {"filter", filter}};
        streams.insert(streams.end(), stream.begin(), stream.end());
        Json view = {{"buffer", 1}, {"byteOffset", fallback_bytes}, {"byteLength", count * stride},
                     {"extensions", {{"EXT_meshopt_compression", extension}}}};
        if (std::string(mode) == "ATTRIBUTES") view["byteStride"] = stride;
        fallback_bytes += (count * stride + 3) / 4 * 4;
        doc.json["bufferViews"].push_back(view);
        return int(doc.json["bufferViews"].size() - 1);
    }
    int add_accessor(int view, size_t count, int component_type, const char* type) {
        doc.json["accessors"].push_back(
            {{"bufferView", view}, {"componentType", component_type}, {"count", count}, {"type", type}});
        return int(doc.json["accessors"].size() - 1);
    }
    Json& extension(int view) { return doc.json["bufferViews"][size_t(view)]["extensions"]["EXT_meshopt_compression"]; }

    std::string text() const {
        Json out = doc.json;
        out["buffers"] = {{{"byteLength", streams.size()},
                           {"uri", "data:application/octet-stream;base64," + base64(streams)}},
                          fallback_buffer(fallback_bytes)};
        return out.dump();
    }
    // The document as a GLB: the streams in its BIN chunk, the fallback buffer beside it.
    Bytes glb() const {
        Json out = doc.json;
        out["buffers"] = {{{"byteLength", streams.size()}}, fallback_buffer(fallback_bytes)};
        return glb_container(out, streams);
    }
    std::string error() const { return scene_error([&] { load_text(text(), "m.gltf"); }); }
};

Bytes encode_vertices(const void* data, size_t count, size_t stride) {
    Bytes out(meshopt_encodeVertexBufferBound(count, stride));
    out.resize(meshopt_encodeVertexBuffer(out.data(), out.size(), data, count, stride));
    return out;
}

Bytes encode_triangles(const std::vector<uint32_t>& indices, size_t vertices) {
    Bytes out(meshopt_encodeIndexBufferBound(indices.size(), vertices));
    out.resize(meshopt_encodeIndexBuffer(out.data(), out.size(), indices.data(), indices.size()));
    return out;
}

// The grid as a meshopt document: positions (with `position_filter`), normals,
// and indices as TRIANGLES (32-bit) or INDICES (16-bit).
struct MeshoptGrid : MeshoptDoc {
    Grid grid;
    int positions = -1, normals = -1, indices = -1;  // views
    explicit MeshoptGrid(bool sequence = false) {
        const size_t n = grid.vertices();
        positions = add_view(encode_vertices(grid.positions.data(), n, 12), n, 12, "ATTRIBUTES");
        normals = add_view(encode_vertices(grid.normals.data(), n, 12), n, 12, "ATTRIBUTES");
        int index_accessor;
        if (sequence) {
            Bytes stream(meshopt_encodeIndexSequenceBound(grid.indices.size(), n));
            stream.resize(meshopt_encodeIndexSequence(stream.data(), stream.size(), grid.indices.data(),
                                                      grid.indices.size()));
            indices = add_view(stream, grid.indices.size(), 2, "INDICES");
            index_accessor = add_accessor(indices, grid.indices.size(), 5123, "SCALAR");
        } else {
            indices = add_view(encode_triangles(grid.indices, n), grid.indices.size(), 4, "TRIANGLES");
            index_accessor = add_accessor(indices, grid.indices.size(), 5125, "SCALAR");
        }
        doc.add_mesh_node({{"attributes", {{"POSITION", add_accessor(positions, n, 5126, "VEC3")},
                                           {"NORMAL", add_accessor(normals, n, 5126, "VEC3")}}},
                           {"indices", index_accessor}});
    }
};

TEST(LoaderCompressed, MeshoptViewsDecodeToTheEncodedData) {
    for (const bool sequence : {false, true}) {
        const MeshoptGrid m(sequence);
        for (const bool binary : {false, true}) {
            SCOPED_TRACE(std::string(binary ? "glb" : "gltf") + (sequence ? ", INDICES" : ", TRIANGLES"));
            const Scene scene = binary ? load_bytes(m.glb(), "m.glb") : load_text(m.text(), "m.gltf");
            EXPECT_EQ(faces(scene.positions, scene.triangles), faces(m.grid));
            // Each vertex keeps its normal (the finalisation may reorder vertices
            // and renormalises normals, hence the tolerance).
            ASSERT_EQ(scene.normals.size(), scene.positions.size());
            for (size_t i = 0; i < scene.positions.size(); ++i) {
                size_t j = 0;
                while (j < m.grid.vertices() && vec3(m.grid.positions[3 * j], m.grid.positions[3 * j + 1],
                                                     m.grid.positions[3 * j + 2]) != scene.positions[i])
                    ++j;
                ASSERT_LT(j, m.grid.vertices()) << "vertex " << i << " is none of the grid's";
                for (int k = 0; k < 3; ++k) EXPECT_NEAR(scene.normals[i][k], m.grid.normals[3 * j + k], 1e-6f);
            }
        }
    }
}

TEST(LoaderCompressed, MeshoptExponentialFilterIsUndone) {
    MeshoptGrid m;
    const size_t n = m.grid.vertices();
    std::vector<uint32_t> filtered(n * 3);
    meshopt_encodeFilterExp(filtered.data(), n, 12, 15, m.grid.positions.data());
    const int view = m.add_view(encode_vertices(filtered.data(), n, 12), n, 12, "ATTRIBUTES", "EXPONENTIAL");
    m.doc.json["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = m.add_accessor(view, n, 5126, "VEC3");
    const Scene scene = load_text(m.text(), "m.gltf");
    ASSERT_EQ(scene.positions.size(), n);
    // The exponent is shared by a vector's components, 15 bits of mantissa below
    // it. (The scene may reorder vertices: each is compared with the nearest of
    // the grid's.)
    bool any_inexact = false;
    for (const vec3& got : scene.positions) {
        float nearest = INFINITY, bound = 0.0f;
        for (size_t j = 0; j < n; ++j) {
            const vec3 want(m.grid.positions[3 * j], m.grid.positions[3 * j + 1], m.grid.positions[3 * j + 2]);
            const vec3 d = glm::abs(got - want);
            const float error = std::max({d.x, d.y, d.z});
            if (error < nearest) {
                nearest = error;
                // The encoder's exponent: the largest frexp() exponent of the
                // components (0 for a zero); rounding errs by half a step of 2^(e-14).
                int e = -100;
                for (int k = 0; k < 3; ++k) {
                    int ek;
                    std::frexp(want[k], &ek);
                    e = std::max(e, ek);
                }
                bound = std::ldexp(1.0f, e - 15);
            }
        }
        EXPECT_LE(nearest, bound);
        any_inexact |= nearest > 0.0f;
    }
    EXPECT_TRUE(any_inexact) << "the filter's quantization should show: was it applied?";
}

TEST(LoaderCompressed, HostileMeshoptStreamsAreRefused) {
    const auto broken = [](const std::function<void(MeshoptGrid&)>& change) {
        MeshoptGrid m;
        change(m);
        return m.error();
    };
    EXPECT_MENTIONS(broken([](MeshoptGrid& m) { m.extension(m.positions)["byteLength"] = 40; }),
                    "m.gltf: bufferViews[0].EXT_meshopt_compression cannot be decoded (meshoptimizer error -2");
    EXPECT_MENTIONS(broken([](MeshoptGrid& m) { m.streams[m.extension(m.normals)["byteOffset"].get<size_t>()] = 0x7f; }),
                    "bufferViews[1].EXT_meshopt_compression cannot be decoded (meshoptimizer error -1");
    // A count the view's byteLength backs but the stream cannot.
    EXPECT_MENTIONS(broken([](MeshoptGrid& m) {
                        m.extension(m.positions)["count"] = 1000000;
                        m.doc.json["bufferViews"][0]["byteLength"] = 12000000;
                    }),
                    "claims 1000000 elements of 12 bytes, more than its");
    EXPECT_MENTIONS(broken([](MeshoptGrid& m) { m.extension(m.positions)["count"] = 100; }),
                    "decodes to 1200 bytes, but the bufferView's byteLength is 972");
    EXPECT_MENTIONS(broken([](MeshoptGrid& m) { m.extension(m.positions)["count"] = 1e12; }),
                    "more than the 67108864 vertices a scene may have");
    EXPECT_MENTIONS(broken([](MeshoptGrid& m) { m.extension(m.indices)["count"] = 3000000; }),
                    "claims 3000000 indices, more than its");
    EXPECT_MENTIONS(broken([](MeshoptGrid& m) { m.extension(m.normals)["byteOffset"] = 1 << 20; }),
                    "reaches past the end of buffers[0]");
    EXPECT_MENTIONS(broken([](MeshoptGrid& m) { m.extension(m.normals)["buffer"] = 7; }),
                    "refers to buffer 7, which does not exist");
    // The fallback buffer holds no data to decode from.
    EXPECT_MENTIONS(broken([](MeshoptGrid& m) { m.extension(m.normals)["buffer"] = 1; }),
                    "reaches past the end of buffers[1] (4 bytes)");
    EXPECT_MENTIONS(broken([](MeshoptGrid& m) { m.extension(m.positions)["mode"] = "STRIPS"; }),
                    "has mode 'STRIPS', expected ATTRIBUTES");
    EXPECT_MENTIONS(broken([](MeshoptGrid& m) { m.extension(m.positions)["filter"] = "ZIGZAG"; }),
                    "has filter 'ZIGZAG'");
    EXPECT_MENTIONS(broken([](MeshoptGrid& m) { m.extension(m.positions)["filter"] = "QUATERNION"; }),
                    "has filter QUATERNION and byteStride 12, expected 8");
    EXPECT_MENTIONS(broken([](MeshoptGrid& m) { m.extension(m.positions)["filter"] = "OCTAHEDRAL"; }),
                    "has filter OCTAHEDRAL and byteStride 12, expected 4 or 8");
    EXPECT_MENTIONS(broken([](MeshoptGrid& m) { m.extension(m.indices)["filter"] = "EXPONENTIAL"; }),
                    "has a filter but mode is not ATTRIBUTES");
    EXPECT_MENTIONS(broken([](MeshoptGrid& m) { m.extension(m.indices)["byteStride"] = 3; }),
                    "has byteStride 3: TRIANGLES need 2 or 4");
    EXPECT_MENTIONS(broken([](MeshoptGrid& m) { m.extension(m.positions)["byteStride"] = 6; }),
                    "has byteStride 6: ATTRIBUTES need a multiple of 4");
    EXPECT_MENTIONS(broken([](MeshoptGrid& m) { m.extension(m.indices)["count"] = 383; }),
                    "count 383, not a multiple of 3");
    EXPECT_MENTIONS(broken([](MeshoptGrid& m) { m.extension(m.indices)["count"] = -3; }),
                    "has count that is not a non-negative integer");
    EXPECT_MENTIONS(broken([](MeshoptGrid& m) { m.extension(m.indices).erase("byteStride"); }), "has no byteStride");
}

TEST(LoaderCompressed, MeshoptRequiredWithoutFallbackDataLoadsOnlyDecoded) {
    // A fallback buffer that a plain (uncompressed) view reads: it has no data.
    MeshoptGrid m;
    m.doc.json["bufferViews"][0].erase("extensions");
    EXPECT_MENTIONS(m.error(), "reaches past the end of buffers[1] (4 bytes)");
}

// A Draco stream of the grid, with its attributes' unique ids.
struct DracoGrid {
    Grid grid;
    draco::EncoderBuffer stream;
    int position_id = -1, normal_id = -1;
    explicit DracoGrid(int position_bits = 0) {
        draco::TriangleSoupMeshBuilder builder;
        const int faces = int(grid.indices.size() / 3);
        builder.Start(faces);
        const int pos = builder.AddAttribute(draco::GeometryAttribute::POSITION, 3, draco::DT_FLOAT32);
        const int nor = builder.AddAttribute(draco::GeometryAttribute::NORMAL, 3, draco::DT_FLOAT32);
        for (int f = 0; f < faces; ++f) {
            const uint32_t* c = &grid.indices[size_t(f) * 3];
            builder.SetAttributeValuesForFace(pos, draco::FaceIndex(f), &grid.positions[c[0] * 3],
                                              &grid.positions[c[1] * 3], &grid.positions[c[2] * 3]);
            builder.SetAttributeValuesForFace(nor, draco::FaceIndex(f), &grid.normals[c[0] * 3],
                                              &grid.normals[c[1] * 3], &grid.normals[c[2] * 3]);
        }
        const std::unique_ptr<draco::Mesh> mesh = builder.Finalize();
        position_id = int(mesh->attribute(pos)->unique_id());
        normal_id = int(mesh->attribute(nor)->unique_id());
        draco::Encoder encoder;
        if (position_bits > 0) encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, position_bits);
        const draco::Status status = encoder.EncodeMeshToBuffer(*mesh, &stream);
        if (!status.ok()) throw std::runtime_error(status.error_msg_string());
        points = mesh->num_points();
    }
    size_t points = 0;

    // A document with the stream in a view and accessors without data.
    GltfDoc doc() const {
        GltfDoc d;
        d.data.assign(stream.data(), stream.data() + stream.size());
        d.json["extensionsRequired"] = {"KHR_draco_mesh_compression"};
        d.json["bufferViews"].push_back({{"buffer", 0}, {"byteLength", stream.size()}});
        const auto accessor = [&](size_t count, int component_type, const char* type) {
            d.json["accessors"].push_back({{"componentType", component_type}, {"count", count}, {"type", type}});
            return d.json["accessors"].size() - 1;
        };
        const Json extension = {{"bufferView", 0}, {"attributes", {{"POSITION", position_id}, {"NORMAL", normal_id}}}};
        d.add_mesh_node({{"attributes", {{"POSITION", accessor(points, 5126, "VEC3")},
                                         {"NORMAL", accessor(points, 5126, "VEC3")}}},
                         {"indices", accessor(grid.indices.size(), 5125, "SCALAR")},
                         {"extensions", {{"KHR_draco_mesh_compression", extension}}}});
        return d;
    }
};

TEST(LoaderCompressed, DracoRoundTripIsLossless) {
    const DracoGrid draco;
    const GltfDoc doc = draco.doc();
    for (const bool binary : {false, true}) {
        SCOPED_TRACE(binary ? "glb" : "gltf");
        const Scene scene = binary ? load_bytes(doc.glb(), "d.glb") : load_text(doc.text(), "d.gltf");
        EXPECT_EQ(faces(scene.positions, scene.triangles), faces(draco.grid));
        EXPECT_EQ(scene.normals.size(), scene.positions.size());
    }
}

TEST(LoaderCompressed, DracoQuantizedPositionsStayWithinTheirStep) {
    const DracoGrid draco(11);
    const Scene scene = load_text(draco.doc().text(), "d.gltf");
    const std::vector<Face> got = faces(scene.positions, scene.triangles), want = faces(draco.grid);
    ASSERT_EQ(got.size(), want.size());
    // 11 bits over the grid's largest extent (4 units in y): steps of 4/2047.
    const float step = 4.0f / 2047.0f;
    float worst = 0.0f;
    for (const Face& f : want) {
        // Rotation and order may differ once quantized: match each face to the nearest.
        float best = INFINITY;
        for (const Face& g : got) {
            float d = 0.0f;
            for (int c = 0; c < 3; ++c)
                for (int k = 0; k < 3; ++k) d = std::max(d, std::abs(f[c][k] - g[c][k]));
            best = std::min(best, d);
        }
        worst = std::max(worst, best);
    }
    EXPECT_LE(worst, step * 0.5f + 1e-6f);
    EXPECT_GT(worst, 0.0f) << "11-bit quantization should move some vertex";
}

TEST(LoaderCompressed, HostileDracoStreamsAreRefused) {
    const DracoGrid draco;
    const auto broken = [&](const std::function<void(GltfDoc&)>& change) {
        GltfDoc doc = draco.doc();
        change(doc);
        return scene_error([&] { load_text(doc.text(), "d.gltf"); });
    };
    const auto extension = [](GltfDoc& d) -> Json& {
        return d.json["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"];
    };
    EXPECT_MENTIONS(broken([&](GltfDoc& d) { d.json["bufferViews"][0]["byteLength"] = draco.stream.size() / 2; }),
                    "d.gltf: meshes[0].primitives[0].KHR_draco_mesh_compression cannot be decoded: Draco: ");
    EXPECT_MENTIONS(broken([&](GltfDoc& d) { std::fill(d.data.begin(), d.data.begin() + 5, 'x'); }),
                    "cannot be decoded: Draco: ");
    EXPECT_MENTIONS(broken([&](GltfDoc& d) { extension(d)["attributes"]["POSITION"] = 7; }),
                    "attribute POSITION names Draco attribute 7, which the mesh lacks");
    EXPECT_MENTIONS(broken([&](GltfDoc& d) { extension(d)["attributes"]["TEXCOORD_0"] = draco.normal_id; }),
                    "attribute TEXCOORD_0 is not one of the primitive's attributes");
    EXPECT_MENTIONS(broken([&](GltfDoc& d) { d.json["accessors"][0]["count"] = 5; }),
                    "attribute POSITION: its accessor has count 5, but Draco decoded");
    EXPECT_MENTIONS(broken([&](GltfDoc& d) { d.json["accessors"][2]["count"] = 9; }),
                    "indices: its accessor has count 9, but Draco decoded 128 triangles");
    EXPECT_MENTIONS(broken([&](GltfDoc& d) { d.json["accessors"][0]["count"] = 1u << 30; }),
                    "more than a scene may have");
    EXPECT_MENTIONS(broken([&](GltfDoc& d) { d.json["accessors"][1]["type"] = "VEC2"; }),
                    "attribute NORMAL: the Draco attribute has 3 components, its accessor 2");
    EXPECT_MENTIONS(broken([&](GltfDoc& d) { extension(d)["bufferView"] = 9; }),
                    "has no bufferView, or one that does not exist");
    EXPECT_MENTIONS(broken([&](GltfDoc& d) { d.json["bufferViews"][0]["byteOffset"] = 64; }),
                    "uses bufferViews[0], which reaches past the end of buffers[0]");
    EXPECT_MENTIONS(broken([&](GltfDoc& d) { d.json["meshes"][0]["primitives"][0]["mode"] = 0; }),
                    "only TRIANGLES are supported");
    EXPECT_MENTIONS(broken([&](GltfDoc& d) { d.json["meshes"][0]["primitives"][0].erase("indices"); }),
                    "on a primitive without indices");
}

TEST(LoaderCompressed, DracoPointCloudsAreRefused) {
    draco::PointCloudBuilder builder;
    builder.Start(4);
    const int pos = builder.AddAttribute(draco::GeometryAttribute::POSITION, 3, draco::DT_FLOAT32);
    for (uint32_t i = 0; i < 4; ++i) {
        const float p[3] = {float(i), float(i * i), 1.0f};
        builder.SetAttributeValueForPoint(pos, draco::PointIndex(i), p);
    }
    const std::unique_ptr<draco::PointCloud> cloud = builder.Finalize(false);
    draco::EncoderBuffer stream;
    ASSERT_TRUE(draco::Encoder().EncodePointCloudToBuffer(*cloud, &stream).ok());
    DracoGrid grid;
    GltfDoc doc = grid.doc();
    doc.data.assign(stream.data(), stream.data() + stream.size());
    doc.json["bufferViews"][0]["byteLength"] = stream.size();
    EXPECT_MENTIONS(scene_error([&] { load_text(doc.text(), "p.gltf"); }),
                    "holds a Draco point cloud, not a triangle mesh");
}

TEST(LoaderCompressed, DracoSharedAccessorsAreDecodedOnceOrRefused) {
    const DracoGrid draco;
    GltfDoc doc = draco.doc();
    // A second primitive of the same stream and accessors (as gltf-pipeline writes
    // instances): decoded once.
    doc.json["meshes"][0]["primitives"].push_back(doc.json["meshes"][0]["primitives"][0]);
    const Scene scene = load_text(doc.text(), "s.gltf");
    EXPECT_EQ(scene.triangles.size(), 2 * draco.grid.indices.size() / 3);
    // The same accessors claimed by another stream.
    doc.json["bufferViews"].push_back(doc.json["bufferViews"][0]);
    doc.json["meshes"][0]["primitives"][1]["extensions"]["KHR_draco_mesh_compression"]["bufferView"] = 1;
    EXPECT_MENTIONS(scene_error([&] { load_text(doc.text(), "s.gltf"); }),
                    "which another Draco stream decoded into already");
}

TEST(LoaderCompressed, DracoStreamNamedByAHugeNumberIsRefused) {
    // Found by fuzz_gltf: the number was cast to int before it was checked (UB).
    for (const double view : {1.11111e83, -1e20, 0.5}) {
        SCOPED_TRACE(view);
        GltfDoc doc = DracoGrid().doc();
        doc.json["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]["bufferView"] = view;
        EXPECT_MENTIONS(scene_error([&] { load_text(doc.text(), "h.gltf"); }),
                        "has no bufferView, or one that does not exist");
    }
}

}  // namespace
}  // namespace rt
