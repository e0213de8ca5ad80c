// References from a scene to other files (glTF buffers and images, OBJ material
// libraries and textures), resolved so that a scene reads nothing outside its own
// folder: no URL, no absolute path, no `..` or symbolic link leading out.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace rt {

// What every loader throws for a file it refuses. Its message is made one line
// of valid UTF-8 of bounded length (printable() below), whatever the file it
// quotes holds.
class SceneError : public std::runtime_error {
  public:
    explicit SceneError(std::string_view message);
};

// The largest file a scene may be or reference. tinygltf takes sizes as 32-bit
// integers, and no scene this renderer can hold in memory needs more.
inline constexpr std::uintmax_t kMaxSceneFileBytes = std::uintmax_t(1) << 30;

class SceneFolder {
  public:
    // The folder holding `scene_file`; the file's name names the scene in messages.
    static SceneFolder of_file(const std::filesystem::path& scene_file);
    // A scene held in memory has no folder: it may reference no file at all.
    static SceneFolder none(std::string_view scene_name);

    const std::string& scene_name() const { return scene_name_; }

    // The file `reference` names, which need not exist. Throws SceneError naming
    // `element` (e.g. "buffers[2].uri") when the reference is a URL, an absolute
    // path, or leads outside the folder, or when the scene has no folder.
    std::filesystem::path resolve(std::string_view reference, std::string_view element) const;

    // resolve() then read_file(); std::nullopt when the file does not exist.
    std::optional<std::vector<unsigned char>> read(std::string_view reference,
                                                   std::string_view element) const;

  private:
    SceneFolder(std::string scene_name, std::filesystem::path folder)
        : scene_name_(std::move(scene_name)), folder_(std::move(folder)) {}

    std::string scene_name_;
    std::filesystem::path folder_;  // canonical; empty for a scene held in memory
};

// The whole content of `file`, or std::nullopt when it does not exist. Throws
// SceneError (prefixed with `what`) when it is not a regular file, is larger than
// kMaxSceneFileBytes or cannot be read.
std::optional<std::vector<unsigned char>> read_file(const std::filesystem::path& file,
                                                    std::string_view what);

// Percent-decodes a URI reference exactly as tinygltf does before it opens the
// file, so that the path we check is the path it reads.
std::string decode_uri(std::string_view uri);

// The longest message (SceneError, warning) the loaders hand out.
inline constexpr size_t kMaxMessageBytes = 1000;

// `text` as one line of valid UTF-8, whatever a hostile file put into it:
// malformed bytes and control characters become '?', line breaks and tabs
// spaces; beyond `max_bytes` it is cut at a character boundary and ends "...".
// Messages quote what files hold, and reach Python and JSON as text.
std::string printable(std::string_view text, size_t max_bytes = kMaxMessageBytes);

// A reference as it may appear in a message: printable() in quotes, at most
// 120 bytes of it.
std::string in_quotes(std::string_view text);

}  // namespace rt
