// What the libFuzzer targets share: a scene folder of fixed companion files,
// created once per process, into which each input is written under the scene's
// name before it is loaded through load_scene(), the path the CLI and the
// service take; and the loaders' contract, checked on every input.
//
// The folder lives in $RT_FUZZ_TMP (run_fuzz.py makes one in /dev/shm and
// removes it afterwards, crash or not), else in /dev/shm when there is one
// (memory: no disk I/O). It holds the same companion files as the corpus of
// make_corpus.py, so that corpus files are good seeds: a valid buffer and
// image, a subfolder, a symbolic link and a FIFO leading nowhere good, a folder
// named like a file, and a file outside the folder.
#pragma once

#include <sys/stat.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

#include "load/loader.h"

namespace rt::fuzz {

namespace fs = std::filesystem;

[[noreturn]] inline void contract_broken(const std::string& problem) {
    std::fprintf(stderr, "\n==== loader contract broken: %s\n", problem.c_str());
    std::fflush(stderr);
    std::abort();  // libFuzzer keeps the input as a crash
}

inline void write_file(const fs::path& file, std::string_view content) {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(content.data(), std::streamsize(content.size()));
    if (!out) contract_broken("cannot write " + file.string());
}

// One triangle (0,0,0) (1,0,0) (0,1,0): positions, normals +Z, indices 0 1 2,
// 84 bytes; make_corpus.py's buffer.bin.
inline std::string triangle_buffer() {
    const float floats[18] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    const unsigned indices[3] = {0, 1, 2};
    std::string out(sizeof floats + sizeof indices, '\0');
    std::memcpy(out.data(), floats, sizeof floats);
    std::memcpy(out.data() + sizeof floats, indices, sizeof indices);
    return out;
}

// A 2x2 RGB PNG; make_corpus.py's image.png.
inline std::string small_png() {
    static const unsigned char png[] = {
        0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44, 0x52,
        0x00, 0x00, 0x00, 0x02, 0x00, 0x00, 0x00, 0x02, 0x08, 0x02, 0x00, 0x00, 0x00, 0xfd, 0xd4, 0x9a,
        0x73, 0x00, 0x00, 0x00, 0x12, 0x49, 0x44, 0x41, 0x54, 0x78, 0xda, 0x63, 0xf8, 0xcf, 0xc0, 0xc0,
        0x00, 0xc2, 0x0c, 0xff, 0x81, 0x00, 0x00, 0x1f, 0xee, 0x05, 0xfb, 0xf1, 0xab, 0xba, 0x77, 0x00,
        0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82};
    return std::string(reinterpret_cast<const char*>(png), sizeof png);
}

class FuzzFolder {
  public:
    // <tmp>/rt_fuzz_XXXXXX/outside.bin beside <tmp>/rt_fuzz_XXXXXX/scene/, which holds
    // buffer.bin, image.png, sub/buffer.bin, escape -> .., pipe (a FIFO) and
    // folder.bin (a folder).
    FuzzFolder() {
        const char* chosen = std::getenv("RT_FUZZ_TMP");
        const fs::path tmp = chosen && *chosen            ? fs::path(chosen)
                             : fs::is_directory("/dev/shm") ? fs::path("/dev/shm")
                                                            : fs::temp_directory_path();
        std::string pattern = (tmp / "rt_fuzz_XXXXXX").string();
        if (!mkdtemp(pattern.data())) contract_broken("mkdtemp failed");
        root_ = pattern;
        scene_ = root_ / "scene";
        fs::create_directories(scene_ / "sub");
        fs::create_directories(scene_ / "folder.bin");
        write_file(root_ / "outside.bin", triangle_buffer());
        write_file(scene_ / "buffer.bin", triangle_buffer());
        write_file(scene_ / "sub" / "buffer.bin", triangle_buffer());
        write_file(scene_ / "image.png", small_png());
        fs::create_symlink("..", scene_ / "escape");
        if (mkfifo((scene_ / "pipe").c_str(), 0600) != 0) contract_broken("mkfifo failed");
    }
    ~FuzzFolder() {
        std::error_code ignored;
        fs::remove_all(root_, ignored);
    }
    FuzzFolder(const FuzzFolder&) = delete;
    FuzzFolder& operator=(const FuzzFolder&) = delete;

    // Writes `content` as `name` in the scene folder; returns its path.
    fs::path put(const std::string& name, std::string_view content) const {
        const fs::path file = scene_ / name;
        write_file(file, content);
        return file;
    }

  private:
    fs::path root_, scene_;
};

// The folder of this process, removed at exit.
inline const FuzzFolder& folder() {
    static const FuzzFolder instance;
    return instance;
}

// Whether `text` is well-formed UTF-8 without control characters.
inline bool printable_utf8(std::string_view text) {
    for (size_t i = 0; i < text.size();) {
        const unsigned char c = static_cast<unsigned char>(text[i]);
        if (c < 0x80) {
            if (c < 0x20 || c == 0x7f) return false;
            ++i;
            continue;
        }
        const size_t length = c >= 0xF0 ? 4 : c >= 0xE0 ? 3 : c >= 0xC0 ? 2 : 0;
        if (length == 0 || i + length > text.size()) return false;
        uint32_t code = c & (0x7f >> length);
        for (size_t k = 1; k < length; ++k) {
            const unsigned char next = static_cast<unsigned char>(text[i + k]);
            if ((next & 0xC0) != 0x80) return false;
            code = code << 6 | (next & 0x3f);
        }
        const uint32_t smallest[5] = {0, 0, 0x80, 0x800, 0x10000};
        if (code < smallest[length] || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF)) return false;
        i += length;
    }
    return true;
}

// A message from the loaders: it starts with one of `prefixes` (the scene's or
// its sidecar's name), says more than that, is one printable line of UTF-8 and
// stays short.
inline void check_message(std::string_view kind, std::string_view message,
                          std::initializer_list<std::string_view> prefixes) {
    constexpr size_t kMaxMessage = 2000;
    const auto quoted = [&] { return std::string(kind) + " '" + std::string(message.substr(0, 300)) + "'"; };
    bool named = false;
    for (std::string_view prefix : prefixes)
        named = named || (message.size() > prefix.size() + 1 && message.substr(0, prefix.size()) == prefix);
    if (!named) contract_broken(quoted() + " does not start with the file's name");
    if (message.size() > kMaxMessage)
        contract_broken(quoted() + "... has " + std::to_string(message.size()) + " bytes");
    if (!printable_utf8(message)) contract_broken(quoted() + " is not one printable line of UTF-8");
}

// The loaders' contract: a scene loads (with messages as above for warnings), or
// throws SceneError with such a message. Anything else (another exception, a
// crash, a sanitizer report) ends the run with the input kept.
template <typename Load>
void expect_scene_or_clear_error(Load&& load, std::initializer_list<std::string_view> prefixes) {
    try {
        const Scene scene = load();
        for (const std::string& warning : scene.warnings) check_message("warning", warning, prefixes);
    } catch (const SceneError& e) {
        check_message("SceneError", e.what(), prefixes);
    } catch (const std::exception& e) {
        contract_broken(std::string("an exception other than SceneError escaped: ") + e.what());
    }
}

}  // namespace rt::fuzz
