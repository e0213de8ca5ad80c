// libFuzzer target: a sidecar sidecar.rt.json (rt.SceneExtras as JSON), loaded
// beside two small fixed scenes it may move: sidecar.obj (objects 'a', 'b') and
// sidecar.gltf (nodes 'a', 'b' and 'c', a child of 'b').
#include <cstddef>
#include <cstdint>

#include "fuzz_folder.h"

namespace {

constexpr const char* kObj = R"(mtllib sidecar.mtl
o a
usemtl m
v 0 0 0
v 1 0 0
v 0 1 0
f 1 2 3
o b
v 0 0 1
v 1 0 1
v 0 1 1
vn 0 0 1
f 4//1 5//1 6//1
)";

constexpr const char* kMtl = "newmtl m\nKd 0.5 0.5 0.5\nKs 0.1 0.1 0.1\nNs 10\n";

constexpr const char* kGltf = R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 1]}],
  "nodes": [{"name": "a", "mesh": 0}, {"name": "b", "children": [2], "translation": [0, 0, 1]},
            {"name": "c", "mesh": 0, "rotation": [0, 0, 0.7071068, 0.7071068]}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2}]}],
  "buffers": [{"byteLength": 84, "uri": "buffer.bin"}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                  {"buffer": 0, "byteOffset": 36, "byteLength": 36},
                  {"buffer": 0, "byteOffset": 72, "byteLength": 12}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                 "min": [0, 0, 0], "max": [1, 1, 0]},
                {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3"},
                {"bufferView": 2, "componentType": 5125, "count": 3, "type": "SCALAR"}]})";

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const rt::fuzz::FuzzFolder& folder = rt::fuzz::folder();
    static const auto obj = (folder.put("sidecar.mtl", kMtl), folder.put("sidecar.obj", kObj));
    static const auto gltf = folder.put("sidecar.gltf", kGltf);
    folder.put("sidecar.rt.json", {reinterpret_cast<const char*>(data), size});
    using rt::fuzz::expect_scene_or_clear_error;
    expect_scene_or_clear_error([&] { return rt::load_scene(obj); }, {"sidecar.obj: ", "sidecar.rt.json: "});
    expect_scene_or_clear_error([&] { return rt::load_scene(gltf); }, {"sidecar.gltf: ", "sidecar.rt.json: "});
    return 0;
}
