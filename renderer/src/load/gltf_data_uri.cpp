#include "load/gltf_data_uri.h"

#include <algorithm>
#include <cctype>

#include "load/loader.h"

namespace rt {
namespace {

constexpr std::string_view kBase64 = ";base64,";
constexpr std::string_view kOctetStream = "application/octet-stream";
// The media types tinygltf 2.7 decodes for images (IsDataURI, DecodeDataURI).
constexpr std::string_view kTinygltfImageTypes[] = {"image/png", "image/jpeg", "image/bmp", "image/gif"};

bool is_base64_digit(char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '+' || c == '/';
}

// What is wrong with `payload` as base64, or nothing.
std::string base64_problem(std::string_view payload) {
    size_t digits = payload.size();
    while (digits > 0 && payload[digits - 1] == '=' && payload.size() - digits < 2) --digits;
    const size_t padding = payload.size() - digits;
    const auto bad = std::find_if_not(payload.begin(), payload.begin() + std::ptrdiff_t(digits), is_base64_digit);
    if (bad != payload.begin() + std::ptrdiff_t(digits))
        return "its base64 holds " +
               (*bad == '=' ? std::string("padding before its end")
                            : "a character that is not base64 at offset " + std::to_string(bad - payload.begin()));
    if (digits % 4 == 1) return "its base64 has a stray last character (" + std::to_string(digits) + " digits)";
    if (padding > 0 && (digits + padding) % 4 != 0) return "its base64 padding is wrong";
    return "";
}

}  // namespace

size_t check_data_uri(std::string_view uri, bool buffer, const std::string& what) {
    const auto fail = [&](const std::string& problem) {
        throw SceneError(what + " is a malformed data: URI: " + problem);
    };
    const size_t comma = uri.find(',');
    if (comma == std::string_view::npos) fail("it has no ',' before its data");
    if (comma < 5 + kBase64.size() - 1 || uri.substr(comma + 1 - kBase64.size(), kBase64.size()) != kBase64)
        fail("it is not base64 (glTF embeds data as data:<media type>;base64,...)");
    const std::string_view media = uri.substr(5, comma + 1 - kBase64.size() - 5);
    if (buffer ? media != kOctetStream && media != "application/gltf-buffer" : media.substr(0, 6) != "image/")
        throw SceneError(what + " is a data: URI of media type " + in_quotes(media) + ", but " +
                         (buffer ? "a buffer's must be application/octet-stream or application/gltf-buffer"
                                 : "an image's must be an image type (image/png, image/jpeg, image/webp)"));
    const std::string_view payload = uri.substr(comma + 1);
    if (!buffer && payload.empty()) fail("it holds no data");
    if (const std::string problem = base64_problem(payload); !problem.empty()) fail(problem);
    size_t digits = payload.size();
    while (digits > 0 && payload[digits - 1] == '=') --digits;
    return digits / 4 * 3 + (digits % 4 > 1 ? digits % 4 - 1 : 0);
}

bool relabel_image_data_uris(nlohmann::json& doc) {
    const auto images = doc.find("images");
    if (!doc.is_object() || images == doc.end() || !images->is_array()) return false;
    bool changed = false;
    for (nlohmann::json& image : *images) {
        if (!image.is_object()) continue;
        const auto uri = image.find("uri");
        if (uri == image.end() || !uri->is_string()) continue;
        const std::string& text = uri->get_ref<const std::string&>();
        const size_t comma = text.find(',');
        if (!is_data_uri(text) || comma == std::string::npos || comma < 5 + kBase64.size()) continue;
        const std::string_view media = std::string_view(text).substr(5, comma + 1 - kBase64.size() - 5);
        if (std::find(std::begin(kTinygltfImageTypes), std::end(kTinygltfImageTypes), media) !=
            std::end(kTinygltfImageTypes))
            continue;
        *uri = "data:" + std::string(kOctetStream) + text.substr(comma + 1 - kBase64.size());
        changed = true;
    }
    return changed;
}

}  // namespace rt
