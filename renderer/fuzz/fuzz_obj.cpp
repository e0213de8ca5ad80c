// libFuzzer target: an .obj file and the material library it may name. The
// input is the OBJ text, then optionally a line "#%mtl" and the text of
// fuzz.mtl; both are written into the fuzzing folder (fuzz_folder.h), whose
// image.png a map_Kd may name.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_folder.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    constexpr std::string_view kSeparator = "\n#%mtl\n";
    const std::string_view input(reinterpret_cast<const char*>(data), size);
    const size_t split = input.find(kSeparator);
    const std::string_view obj = input.substr(0, split);
    const std::string_view mtl = split == std::string_view::npos ? "" : input.substr(split + kSeparator.size());
    const rt::fuzz::FuzzFolder& folder = rt::fuzz::folder();
    folder.put("fuzz.mtl", mtl);
    const auto file = folder.put("fuzz.obj", obj);
    rt::fuzz::expect_scene_or_clear_error([&] { return rt::load_scene(file); }, {"fuzz.obj: "});
    return 0;
}
