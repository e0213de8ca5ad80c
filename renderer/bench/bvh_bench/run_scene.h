// One scene's measurements: builds, then for each ray kind the answers
// checked and both sides timed.
#pragma once

#include <algorithm>
#include <filesystem>
#include <iterator>
#include <set>
#include <string>
#include <vector>

#include "report.h"

namespace rt::bench {

// What --kinds may name; "packets" names the three packet kinds at once.
inline const char* const kPacketKinds[] = {"camera-packets", "shadow-packets", "soft-shadows"};
inline const char* const kKinds[] = {"primary",        "shadow",       "random", "diffuse", "camera-packets",
                                     "shadow-packets", "soft-shadows", "build",  "memory"};

struct Options {
    std::filesystem::path scenes;
    std::vector<std::string> only;
    uint32_t size = 1024;
    double min_seconds = 0.2;
    unsigned threads = 1;       // "all threads": both sides run on this many
    std::set<std::string> kinds;  // of kKinds

    bool wants(const std::string& kind) const { return kinds.count(kind) != 0; }
    bool wants_rays() const {
        return wants("primary") || wants("shadow") || wants("random") || wants("diffuse") ||
               std::any_of(std::begin(kPacketKinds), std::end(kPacketKinds), [&](const char* k) { return wants(k); });
    }
    // Random rays per scene: a quarter of the primary count. They are the
    // slowest kind, and a quarter million already covers the scene's box.
    size_t random_rays() const { return size_t(size) * size / 4; }
};

SceneResult run_scene(const std::filesystem::path& file, const Options& options);

}  // namespace rt::bench
