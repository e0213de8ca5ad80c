// libFuzzer target: a .glb file held in memory, as rtcore's Scene.from_bytes
// loads it (no folder: any reference to another file is refused).
#include <cstddef>
#include <cstdint>
#include <span>

#include "fuzz_folder.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const auto bytes = std::as_bytes(std::span(data, size));
    rt::fuzz::expect_scene_or_clear_error([&] { return rt::load_scene_from_memory(bytes, "fuzz.glb"); },
                                          {"fuzz.glb: "});
    return 0;
}
