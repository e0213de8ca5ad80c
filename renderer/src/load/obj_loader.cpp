// Wavefront OBJ + MTL through tinyobjloader (obj_loader.h): the text checked
// where the parser would misread it, then parsed, with material libraries read
// through the scene folder (scene_files.h); obj_scene.cpp checks the rest.
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <map>
#include <optional>
#include <sstream>

#include "load/obj_loader.h"

namespace rt {
namespace {

// tinyobjloader's number parser adds exponent digits to an int, checking for
// overflow one digit too late: "1e2147483648" is undefined behaviour there.
// Numbers reach the exponent only after a digit or a dot, so any such exponent
// of ten or more significant digits is refused, in OBJ and MTL text alike.
void check_exponents(std::string_view text, const std::string& name) {
    const auto is_digit = [](char c) { return c >= '0' && c <= '9'; };
    for (size_t at = 1; at < text.size(); ++at) {
        if ((text[at] != 'e' && text[at] != 'E') || !(is_digit(text[at - 1]) || text[at - 1] == '.')) continue;
        size_t digit = at + 1;
        if (digit < text.size() && (text[digit] == '+' || text[digit] == '-')) ++digit;
        while (digit < text.size() && text[digit] == '0') ++digit;
        size_t end = digit;
        while (end < text.size() && is_digit(text[end])) ++end;
        if (end - digit < 10) continue;
        const size_t line = 1 + static_cast<size_t>(std::count(text.begin(), text.begin() + at, '\n'));
        const size_t space = text.find_last_of(" \t\r\n", at);
        const size_t from = space == std::string_view::npos ? 0 : space + 1;
        throw SceneError(name + ": line " + std::to_string(line) + ": the number '" +
                         std::string(text.substr(from, std::min<size_t>(end - from, 40))) +
                         "' has an exponent out of range");
    }
}

// tinyobjloader's only way to files: `mtllib` names resolved in the scene
// folder. A refusal is kept and thrown once the parser returns.
class FolderMaterialReader : public tinyobj::MaterialReader {
  public:
    explicit FolderMaterialReader(const SceneFolder& folder) : folder_(folder) {}

    bool operator()(const std::string& file, std::vector<tinyobj::material_t>* materials,
                    std::map<std::string, int>* names, std::string* warn, std::string* err) override {
        try {
            const auto bytes = folder_.read(file, "mtllib");
            if (!bytes) {
                *warn += "material library " + in_quotes(file) + " not found\n";
                return false;
            }
            std::string text(bytes->begin(), bytes->end());
            check_exponents(text, folder_.scene_name() + ": " + file);
            std::istringstream stream(std::move(text));
            tinyobj::LoadMtl(names, materials, &stream, warn, err);
            return true;
        } catch (const SceneError& e) {
            if (!error) error = e;
            return false;
        }
    }

    std::optional<SceneError> error;

  private:
    const SceneFolder& folder_;
};

// tinyobjloader repeats some warnings once per line; keep each once, and few.
// Lines that say nothing go: one of its warnings ends in "\n.".
void add_warnings(const std::string& text, const std::string& name, std::vector<std::string>& warnings) {
    constexpr size_t kMaxWarnings = 20;
    std::istringstream lines(text);
    std::vector<std::string> seen;
    size_t dropped = 0;
    const auto says_something = [](const std::string& line) {
        return std::any_of(line.begin(), line.end(), [](unsigned char c) { return std::isalnum(c); });
    };
    for (std::string line; std::getline(lines, line);) {
        if (!says_something(line) || std::find(seen.begin(), seen.end(), line) != seen.end()) continue;
        if (seen.size() == kMaxWarnings) {
            ++dropped;
            continue;
        }
        seen.push_back(line);
        warnings.push_back(name + ": " + line);
    }
    if (dropped > 0) warnings.push_back(name + ": " + std::to_string(dropped) + " more parser warnings");
}

// tinyobjloader's skin-weight extension (`vw` lines) converts unchecked doubles
// to int; we read no skin weights, so those lines become comments.
std::string without_skin_weights(std::span<const unsigned char> data) {
    std::string text(data.begin(), data.end());
    for (size_t line = 0; line < text.size();) {
        const size_t end = std::min(text.find_first_of("\r\n", line), text.size());
        const size_t start = text.find_first_not_of(" \t", line);
        const bool skin_weights = start < end && start + 2 < end && text.compare(start, 2, "vw") == 0 &&
                                  (text[start + 2] == ' ' || text[start + 2] == '\t');
        if (skin_weights) text[start] = '#';
        line = end + 1;
    }
    return text;
}

// tinyobjloader reads a number it cannot parse ("nan", "1e999", "x") as 0, so a
// broken vertex would silently move to the origin: vertex lines are checked here.
void check_vertex_numbers(std::string_view text, const std::string& name) {
    size_t number = 0;
    for (size_t line = 0; line < text.size(); ++number) {
        const size_t end = std::min(text.find_first_of("\r\n", line), text.size());
        std::string_view rest = text.substr(line, end - line);
        line = end + (end < text.size() && text[end] == '\r' && end + 1 < text.size() && text[end + 1] == '\n' ? 2 : 1);
        const size_t start = rest.find_first_not_of(" \t");
        if (start == std::string_view::npos) continue;
        rest.remove_prefix(start);
        const size_t keyword_end = rest.find_first_of(" \t");
        const std::string_view keyword = rest.substr(0, keyword_end);
        if (keyword != "v" && keyword != "vn" && keyword != "vt") continue;
        rest.remove_prefix(std::min(keyword_end, rest.size()));
        while (true) {
            const size_t token_start = rest.find_first_not_of(" \t");
            if (token_start == std::string_view::npos || rest[token_start] == '#') break;
            rest.remove_prefix(token_start);
            const std::string_view token = rest.substr(0, rest.find_first_of(" \t"));
            double value = 0.0;
            const char* first = token.data() + (token.front() == '+' ? 1 : 0);
            const auto [ptr, ec] = std::from_chars(first, token.data() + token.size(), value);
            if (ec != std::errc() || ptr != token.data() + token.size() || !std::isfinite(value))
                throw SceneError(name + ": line " + std::to_string(number + 1) + ": " + std::string(keyword) +
                                 " value '" + std::string(token.substr(0, 32)) + "' is not a finite number");
            rest.remove_prefix(token.size());
        }
    }
}

}  // namespace

LoadedScene load_obj(std::span<const unsigned char> data, const SceneFolder& folder,
                     std::span<const SceneAdditions::Motion> motions) {
    const std::string& name = folder.scene_name();
    const std::string text = without_skin_weights(data);
    check_vertex_numbers(text, name);
    check_exponents(text, name);
    std::istringstream stream(text);
    FolderMaterialReader reader(folder);
    tinyobj::attrib_t attrib;
    std::vector<tinyobj::shape_t> shapes;
    std::vector<tinyobj::material_t> materials;
    std::string warning, error;
    bool ok = false;
    try {
        // Triangulated below, as fans; tinyobjloader's triangulation silently drops
        // faces whose indices are out of range, which we refuse instead.
        ok = tinyobj::LoadObj(&attrib, &shapes, &materials, &warning, &error, &stream, &reader,
                              /*triangulate=*/false, /*default_vcols_fallback=*/false);
    } catch (const std::exception& e) {
        throw SceneError(name + ": " + e.what());
    }
    if (reader.error) throw *reader.error;
    if (!ok) throw SceneError(name + ": " + error.substr(0, error.find_last_not_of(" \t\r\n") + 1));

    LoadedScene loaded = build_obj_scene(folder, attrib, shapes, materials, motions);
    std::vector<std::string> parser_warnings;
    add_warnings(warning + error, name, parser_warnings);
    loaded.scene.warnings.insert(loaded.scene.warnings.begin(), parser_warnings.begin(), parser_warnings.end());
    return loaded;
}

}  // namespace rt
