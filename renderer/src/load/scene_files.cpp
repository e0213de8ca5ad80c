#include "load/scene_files.h"

#include <algorithm>
#include <fstream>
#include <system_error>

namespace rt {
namespace {

namespace fs = std::filesystem;

// True when `path` lies strictly below `folder`; both are canonical, so comparing
// whole components is enough ("/a/scene2" is not below "/a/scene").
bool is_below(const fs::path& path, const fs::path& folder) {
    auto p = path.begin();
    for (auto f = folder.begin(); f != folder.end(); ++f, ++p) {
        // A trailing separator shows up as an empty last component.
        if (f->empty() && std::next(f) == folder.end()) break;
        if (p == path.end() || *p != *f) return false;
    }
    return p != path.end() && !p->empty();
}

[[noreturn]] void fail(std::string_view what, const std::string& problem) {
    throw SceneError(std::string(what) + " " + problem);
}

}  // namespace

SceneFolder SceneFolder::of_file(const fs::path& scene_file) {
    std::error_code error;
    fs::path folder = fs::weakly_canonical(fs::absolute(scene_file).parent_path(), error);
    if (error)
        throw SceneError(scene_file.filename().string() + ": cannot resolve its folder: " +
                         error.message());
    return SceneFolder(scene_file.filename().string(), std::move(folder));
}

SceneFolder SceneFolder::none(std::string_view scene_name) {
    return SceneFolder(std::string(scene_name), fs::path());
}

fs::path SceneFolder::resolve(std::string_view reference, std::string_view element) const {
    const std::string what = scene_name_ + ": " + std::string(element) + " " + in_quotes(reference);
    if (reference.empty()) fail(what, "is empty");
    if (reference.find('\0') != std::string_view::npos) fail(what, "contains a NUL character");
    if (reference.substr(0, 5) == "data:")
        fail(what, "is a data: URI of a kind we cannot decode (only base64 with a glTF media type)");
    if (reference.find("://") != std::string_view::npos)
        fail(what, "is a URL: a scene may only reference files inside its own folder");
    if (folder_.empty())
        fail(what, "names another file, but a scene loaded from memory can reference none "
                   "(embed it as a data: URI, or use .glb)");

    const fs::path relative(reference);
    if (relative.has_root_name() || relative.has_root_directory())
        fail(what, "is an absolute path: a scene may only reference files inside its own folder");
    std::error_code error;
    const fs::path file = fs::weakly_canonical(folder_ / relative, error);
    if (error) fail(what, "cannot be resolved: " + error.message());
    if (!is_below(file, folder_))
        fail(what, "leads outside the scene folder (through '..' or a symbolic link)");
    return file;
}

std::optional<std::vector<unsigned char>> SceneFolder::read(std::string_view reference,
                                                            std::string_view element) const {
    const fs::path file = resolve(reference, element);
    return read_file(file, scene_name_ + ": " + std::string(element) + " " + in_quotes(reference));
}

std::optional<std::vector<unsigned char>> read_file(const fs::path& file, std::string_view what) {
    std::error_code error;
    const fs::file_status status = fs::status(file, error);
    if (status.type() == fs::file_type::not_found) return std::nullopt;
    if (error) fail(what, "cannot be read: " + error.message());
    // A FIFO or device would block or never end; only plain files are scene data.
    if (status.type() != fs::file_type::regular) fail(what, "is not a regular file");
    const std::uintmax_t size = fs::file_size(file, error);
    if (error) fail(what, "cannot be read: " + error.message());
    if (size > kMaxSceneFileBytes)
        fail(what, "is " + std::to_string(size) + " bytes, more than the limit of " +
                       std::to_string(kMaxSceneFileBytes));

    std::ifstream in(file, std::ios::binary);
    std::vector<unsigned char> bytes(size);
    if (in && size > 0) in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(size));
    if (!in || (size > 0 && std::uintmax_t(in.gcount()) != size)) fail(what, "cannot be read");
    return bytes;
}

std::string decode_uri(std::string_view uri) {
    const auto hex = [](char c) -> int {
        if (c >= '0' && c <= '9') return c - '0';
        if (c >= 'a' && c <= 'f') return c - 'a' + 10;
        if (c >= 'A' && c <= 'F') return c - 'A' + 10;
        return 0;  // as tinygltf: an invalid digit counts as zero
    };
    std::string out;
    out.reserve(uri.size());
    for (size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] == '+') {
            out += ' ';
        } else if (uri[i] == '%' && i + 2 < uri.size()) {
            out += char((hex(uri[i + 1]) << 4) | hex(uri[i + 2]));
            i += 2;
        } else {
            out += uri[i];
        }
    }
    return out;
}

namespace {

// The length of the well-formed UTF-8 character at text[i] (RFC 3629: no
// overlong forms, no surrogates, nothing above U+10FFFF), or 0.
size_t utf8_length(std::string_view text, size_t i) {
    const auto byte = [&](size_t k) { return static_cast<unsigned char>(text[k]); };
    const unsigned char lead = byte(i);
    size_t length = 0;
    unsigned char low = 0x80, high = 0xBF;  // the range of the second byte
    if (lead >= 0xC2 && lead <= 0xDF) {
        length = 2;
    } else if (lead >= 0xE0 && lead <= 0xEF) {
        length = 3;
        if (lead == 0xE0) low = 0xA0;   // overlong
        if (lead == 0xED) high = 0x9F;  // surrogates
    } else if (lead >= 0xF0 && lead <= 0xF4) {
        length = 4;
        if (lead == 0xF0) low = 0x90;   // overlong
        if (lead == 0xF4) high = 0x8F;  // above U+10FFFF
    }
    if (length == 0 || i + length > text.size()) return 0;
    if (byte(i + 1) < low || byte(i + 1) > high) return 0;
    for (size_t k = 2; k < length; ++k)
        if (byte(i + k) < 0x80 || byte(i + k) > 0xBF) return 0;
    return length;
}

}  // namespace

SceneError::SceneError(std::string_view message) : std::runtime_error(printable(message)) {}

std::string printable(std::string_view text, size_t max_bytes) {
    std::string out;
    out.reserve(std::min(text.size(), max_bytes) + 3);
    for (size_t i = 0; i < text.size();) {
        const unsigned char c = static_cast<unsigned char>(text[i]);
        size_t length = 1;
        char replacement = 0;  // 0: the character itself
        if (c >= 0x80) {
            length = utf8_length(text, i);
            if (length == 0) length = 1, replacement = '?';
        } else if (c == '\n' || c == '\r' || c == '\t') {
            replacement = ' ';
        } else if (c < 0x20 || c == 0x7f) {
            replacement = '?';
        }
        const size_t added = replacement ? 1 : length;
        if (out.size() + added > max_bytes) {
            out += "...";
            break;
        }
        if (replacement) out += replacement;
        else out.append(text.substr(i, length));
        i += length;
    }
    return out;
}

std::string in_quotes(std::string_view text) {
    std::string out = "'";  // appended, not "'" + ...: GCC 12 warns wrongly of an overlap (-Wrestrict)
    out += printable(text, 120);
    out += '\'';
    return out;
}

}  // namespace rt
