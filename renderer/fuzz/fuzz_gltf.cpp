// libFuzzer target: the text of a .gltf file, loaded from a folder whose
// companion files (fuzz_folder.h) its buffers and images may name.
#include <cstddef>
#include <cstdint>

#include "fuzz_folder.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const auto file = rt::fuzz::folder().put("fuzz.gltf", {reinterpret_cast<const char*>(data), size});
    rt::fuzz::expect_scene_or_clear_error([&] { return rt::load_scene(file); }, {"fuzz.gltf: "});
    return 0;
}
