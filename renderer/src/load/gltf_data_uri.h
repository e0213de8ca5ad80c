// glTF's data: URIs, which the spec has base64-encoded: each is checked before
// tinygltf sees it, so that a malformed one gets a message of its own, and an
// image of a media type tinygltf 2.7 does not decode (image/webp) is handed to
// it under one it does.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace rt {

// Whether `uri` is a data: URI at all (of any kind, well-formed or not).
inline bool is_data_uri(std::string_view uri) { return uri.substr(0, 5) == "data:"; }

// The number of bytes the data: URI `uri` of a buffer (`buffer`) or an image
// decodes to. Throws SceneError naming `what` (e.g. "scene.gltf: buffers[0].uri")
// unless it is `data:<media type>;base64,<base64>`, the base64 strict (its
// alphabet, padding only at the end), and the media type one the spec allows:
// application/octet-stream or application/gltf-buffer for a buffer, image/...
// for an image.
size_t check_data_uri(std::string_view uri, bool buffer, const std::string& what);

// Relabels each image's data: URI whose media type tinygltf does not decode as
// application/octet-stream, which it decodes without looking at the bytes (our
// decoder tells images apart by their content). Call after check_data_uri has
// passed them. Returns whether `doc` changed.
bool relabel_image_data_uris(nlohmann::json& doc);

}  // namespace rt
