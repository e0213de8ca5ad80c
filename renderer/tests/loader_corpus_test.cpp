// The hostile corpus of renderer/fuzz/make_corpus.py, generated into the build
// tree (RT_CORPUS_DIR): every file is loaded and does what its manifest row says.
// "error": a SceneError naming the file (or its sidecar) and containing the
// row's text; "loads": a scene, with a warning containing the text; "any":
// either. Every message is one printable line of UTF-8 of bounded length. No
// file may crash or trip a sanitizer (this suite also runs under ASan+UBSan).
// RT_CORPUS_VERBOSE=1 prints what each file answered.
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <set>
#include <sstream>

#include <gtest/gtest.h>

#include "loader_test_util.h"
#include "load/scene_files.h"

namespace rt {
namespace {

namespace fs = std::filesystem;
using namespace rt::testing;

const fs::path kCorpus = RT_CORPUS_DIR;
const fs::path kScenes = kCorpus / "scenes";

struct Entry {
    std::string file;
    std::string expect;  // error, loads or any
    std::string mentions;
};

const std::vector<Entry>& manifest() {
    static const std::vector<Entry> entries = [] {
        std::vector<Entry> out;
        std::ifstream in(kCorpus / "manifest.tsv");
        for (std::string line; std::getline(in, line);) {
            if (line.empty() || line[0] == '#') continue;
            std::istringstream fields(line);
            Entry entry;
            std::getline(fields, entry.file, '\t');
            std::getline(fields, entry.expect, '\t');
            std::getline(fields, entry.mentions);
            out.push_back(entry);
        }
        return out;
    }();
    return entries;
}

// What one load did.
struct Outcome {
    bool loaded = false;
    std::string error;  // SceneError's message
    std::vector<std::string> warnings;
};

template <typename Load>
Outcome outcome_of(Load&& load) {
    Outcome out;
    try {
        out.warnings = load().warnings;
        out.loaded = true;
    } catch (const SceneError& e) {
        out.error = e.what();
    } catch (const std::exception& e) {
        ADD_FAILURE() << "an exception other than SceneError escaped: " << e.what();
    }
    return out;
}

// A message names the file (or its sidecar) first, says more than that, and is
// one printable line of UTF-8 of bounded length.
void expect_clear(const std::string& message, const std::string& file) {
    const std::string stem = fs::path(file).stem().string();
    bool named = false;
    for (const std::string& prefix : {file + ": ", stem + ".rt.json: "})
        named = named || (message.rfind(prefix, 0) == 0 && message.size() > prefix.size() + 1);
    EXPECT_TRUE(named) << "does not start with the file's name: " << message;
    EXPECT_EQ(printable(message), message) << "not one printable line of UTF-8 of at most " << kMaxMessageBytes
                                           << " bytes";
}

void check(const Entry& entry, const Outcome& out) {
    SCOPED_TRACE(entry.file);
    if (std::getenv("RT_CORPUS_VERBOSE")) {
        std::cout << entry.file << " [" << entry.expect << "]: " << (out.loaded ? "loaded" : out.error) << "\n";
        for (const std::string& warning : out.warnings) std::cout << "    warning: " << warning << "\n";
    }
    if (out.loaded) {
        EXPECT_NE(entry.expect, "error") << "loaded, but should have been refused";
        for (const std::string& warning : out.warnings) expect_clear(warning, entry.file);
        if (entry.expect == "loads" && !entry.mentions.empty()) {
            bool found = false;
            for (const std::string& warning : out.warnings) found = found || contains(warning, entry.mentions);
            EXPECT_TRUE(found) << "no warning mentions '" << entry.mentions << "'";
        }
    } else if (!out.error.empty()) {
        EXPECT_NE(entry.expect, "loads") << "refused: " << out.error;
        expect_clear(out.error, entry.file);
        if (entry.expect == "error") {
            EXPECT_TRUE(contains(out.error, entry.mentions)) << "does not mention '" << entry.mentions
                                                             << "': " << out.error;
        }
    }
}

// Every file of the manifest whose name starts with `prefix`, loaded from the corpus folder.
void load_all(const std::string& prefix) {
    size_t count = 0;
    for (const Entry& entry : manifest()) {
        if (entry.file.rfind(prefix, 0) != 0) continue;
        ++count;
        check(entry, outcome_of([&] { return load_scene(kScenes / entry.file); }));
    }
    EXPECT_GT(count, 0u) << "no " << prefix << "* files in " << kCorpus;
}

TEST(LoaderCorpus, ManifestCoversEveryScene) {
    ASSERT_FALSE(manifest().empty()) << kCorpus / "manifest.tsv" << " is missing or empty";
    std::set<std::string> listed;
    for (const Entry& entry : manifest()) {
        EXPECT_TRUE(entry.expect == "error" || entry.expect == "loads" || entry.expect == "any") << entry.file;
        EXPECT_TRUE(fs::is_regular_file(kScenes / entry.file)) << entry.file;
        listed.insert(entry.file);
    }
    for (const auto& item : fs::directory_iterator(kScenes)) {
        const std::string extension = item.path().extension().string();
        if (extension == ".gltf" || extension == ".glb" || extension == ".obj") {
            EXPECT_TRUE(listed.count(item.path().filename().string())) << item.path() << " is not in the manifest";
        }
    }
}

TEST(LoaderCorpus, GltfFiles) { load_all("gltf_"); }
TEST(LoaderCorpus, GlbFiles) { load_all("glb_"); }
TEST(LoaderCorpus, ObjFiles) { load_all("obj_"); }
TEST(LoaderCorpus, SidecarFiles) { load_all("sidecar_"); }

// The GLB files again as rtcore's Scene.from_bytes hands them over: no folder,
// so a reference to another file is refused too, and nothing else changes.
TEST(LoaderCorpus, GlbFilesFromMemory) {
    for (const Entry& entry : manifest()) {
        if (entry.file.rfind("glb_", 0) != 0) continue;
        std::ifstream in(kScenes / entry.file, std::ios::binary);
        const Bytes bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        const Outcome out = outcome_of([&] { return load_bytes(bytes, entry.file); });
        // From memory, a file reference is refused before anything else is said about it.
        const bool references = contains(entry.file, "buffer_external");
        const std::string expect = references ? "error" : entry.expect;
        check({entry.file, expect, references ? "loaded from memory" : expect == "error" ? "" : entry.mentions}, out);
    }
}

}  // namespace
}  // namespace rt
