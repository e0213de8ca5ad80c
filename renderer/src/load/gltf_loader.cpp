#include "load/gltf_loader.h"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <map>
#include <optional>
#include <string_view>

#include <nlohmann/json.hpp>

#include "load/gltf_approximations.h"
#include "load/gltf_accessor.h"
#include "load/gltf_compressed.h"
#include "load/gltf_data_uri.h"
#include "load/loader.h"

namespace rt {
namespace {

using Json = nlohmann::json;

// tinygltf converts `extras` and `extensions` recursively, so a deeply nested
// document would overflow the stack before any other check could run.
constexpr int kMaxJsonDepth = 64;

// The nesting depth of JSON text, found without parsing it.
int json_depth(std::string_view text) {
    int depth = 0, deepest = 0;
    bool in_string = false, escaped = false;
    for (const char c : text) {
        if (in_string) {
            if (escaped) escaped = false;
            else if (c == '\\') escaped = true;
            else if (c == '"') in_string = false;
        } else if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            deepest = std::max(deepest, ++depth);
            if (deepest > kMaxJsonDepth) break;
        } else if (c == ']' || c == '}') {
            --depth;
        }
    }
    return deepest;
}

uint32_t load_u32(const unsigned char* p) {
    return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}

// Checks the GLB container (header and chunk lengths) ourselves: tinygltf 2.7
// misses a chunk header in one bound and would read past the data. Returns the
// bytes the header declares and sets `json` to the JSON chunk.
std::span<const unsigned char> check_glb(std::span<const unsigned char> data, const std::string& name,
                                         std::string_view& json) {
    const auto fail = [&](const std::string& problem) { throw SceneError(name + ": " + problem); };
    if (data.size() < 12)
        fail("is too short for a GLB header (" + std::to_string(data.size()) + " bytes, need 12)");
    if (std::string_view(reinterpret_cast<const char*>(data.data()), 4) != "glTF")
        fail("is not a GLB file (its first bytes are not 'glTF')");
    if (load_u32(&data[4]) != 2)
        fail("GLB version " + std::to_string(load_u32(&data[4])) + " is not supported (only 2)");
    const size_t length = load_u32(&data[8]);
    if (length > data.size())
        fail("GLB header declares " + std::to_string(length) + " bytes, but there are only " +
             std::to_string(data.size()) + " (truncated file?)");
    if (length < 20) fail("GLB length " + std::to_string(length) + " leaves no room for the JSON chunk");
    const size_t json_length = load_u32(&data[12]);
    if (json_length > length - 20)
        fail("GLB JSON chunk length " + std::to_string(json_length) + " reaches past the end of the " +
             std::to_string(length) + "-byte GLB");
    if (load_u32(&data[16]) != 0x4E4F534Au) fail("GLB first chunk is not of type JSON");
    if (json_length == 0) fail("GLB JSON chunk is empty");
    json = std::string_view(reinterpret_cast<const char*>(&data[20]), json_length);

    const size_t rest = length - 20 - json_length;
    if (rest > 0) {
        if (rest < 8) fail("GLB chunk header after the JSON chunk is truncated");
        const size_t bin_length = load_u32(&data[20 + json_length]);
        if (bin_length > rest - 8)
            fail("GLB BIN chunk length " + std::to_string(bin_length) + " reaches past the end of the " +
                 std::to_string(length) + "-byte GLB");
        if (bin_length == 0 || bin_length % 4 != 0)
            fail("GLB BIN chunk length " + std::to_string(bin_length) + " is not a positive multiple of 4");
        if (load_u32(&data[24 + json_length]) != 0x004E4942u) fail("GLB second chunk is not of type BIN");
    }
    return data.first(length);
}

// The GLB `data` (checked by check_glb, its JSON chunk `json`) with `new_json`
// as its JSON chunk instead, padded with spaces as the container requires.
std::vector<unsigned char> replace_glb_json(std::span<const unsigned char> data, std::string_view json,
                                            std::string new_json, const std::string& name) {
    new_json.resize((new_json.size() + 3) / 4 * 4, ' ');
    const std::span<const unsigned char> rest = data.subspan(20 + json.size());
    const size_t length = 20 + new_json.size() + rest.size();
    if (length > UINT32_MAX) throw SceneError(name + ": GLB would grow past 4 GiB with its JSON completed");
    std::vector<unsigned char> glb(length);
    std::memcpy(glb.data(), data.data(), 20);
    const auto store_u32 = [&](size_t at, size_t value) {
        for (int i = 0; i < 4; ++i) glb[at + i] = static_cast<unsigned char>(value >> (8 * i));
    };
    store_u32(8, length);
    store_u32(12, new_json.size());
    std::memcpy(glb.data() + 20, new_json.data(), new_json.size());
    if (!rest.empty()) std::memcpy(glb.data() + 20 + new_json.size(), rest.data(), rest.size());
    return glb;
}

const Json* member(const Json& object, const char* key) {
    if (!object.is_object()) return nullptr;
    const auto it = object.find(key);
    return it == object.end() ? nullptr : &*it;
}

// A non-negative integer property as tinygltf reads it, or `fallback`.
uint64_t unsigned_or(const Json& object, const char* key, uint64_t fallback) {
    const Json* value = member(object, key);
    return value && value->is_number_unsigned() ? value->get<uint64_t>() : fallback;
}

// The element that references each file, by decoded URI, for messages.
using ReferenceNames = std::map<std::string, std::string>;

// Every buffer and image URI must be a well-formed data: URI (gltf_data_uri.h)
// or a file inside the scene folder; a buffer's data: URI must hold exactly its
// byteLength. Only a GLB's first buffer, its BIN chunk, has none.
void check_references(const Json& doc, const char* array, bool binary, const SceneFolder& folder,
                      ReferenceNames& names) {
    const Json* items = member(doc, array);
    if (!items || !items->is_array()) return;
    const bool buffers = std::string_view(array) == "buffers";
    for (size_t i = 0; i < items->size(); ++i) {
        const Json* uri = member((*items)[i], "uri");
        const std::string element = std::string(array) + "[" + std::to_string(i) + "]";
        if (uri && !uri->is_string()) throw SceneError(folder.scene_name() + ": " + element + ".uri is not a string");
        if (!uri && buffers && !(binary && i == 0))
            throw SceneError(folder.scene_name() + ": " + element + " has no uri (only the first buffer of a .glb, "
                             "its BIN chunk, may leave it out)");
        if (!uri) continue;
        const std::string& text = uri->get_ref<const std::string&>();
        if (!is_data_uri(text)) {
            const std::string decoded = decode_uri(text);
            folder.resolve(decoded, element + ".uri");
            names.emplace(decoded, element + ".uri");
        } else if (buffers) {
            const uint64_t declared = unsigned_or((*items)[i], "byteLength", 0);
            const size_t held = check_data_uri(text, true, folder.scene_name() + ": " + element + ".uri");
            if (held != declared)
                throw SceneError(folder.scene_name() + ": " + element + " declares byteLength " +
                                 std::to_string(declared) + " but its data: URI holds " +
                                 std::to_string(held) + " bytes");
        } else {
            check_data_uri(text, false, folder.scene_name() + ": " + element + ".uri");
        }
    }
}

// tinygltf hands an image's buffer view to the image loader without checking
// that the view lies inside its buffer; check that it does.
void check_image_views(const Json& doc, const std::string& name) {
    const Json* images = member(doc, "images");
    const Json* views = member(doc, "bufferViews");
    const Json* buffers = member(doc, "buffers");
    if (!images || !images->is_array()) return;
    for (size_t i = 0; i < images->size(); ++i) {
        const Json* view_index = member((*images)[i], "bufferView");
        if (!view_index) continue;
        const std::string what = name + ": images[" + std::to_string(i) + "].bufferView";
        if (!view_index->is_number_unsigned() || !views || !views->is_array() ||
            view_index->get<uint64_t>() >= views->size())
            throw SceneError(what + " does not exist");
        const Json& view = (*views)[view_index->get<size_t>()];
        const uint64_t buffer = unsigned_or(view, "buffer", UINT64_MAX);
        if (!buffers || !buffers->is_array() || buffer >= buffers->size())
            throw SceneError(what + " refers to a buffer that does not exist");
        const uint64_t size = unsigned_or((*buffers)[buffer], "byteLength", 0);
        const uint64_t offset = unsigned_or(view, "byteOffset", 0);
        const uint64_t length = unsigned_or(view, "byteLength", 0);
        if (length == 0 || offset > size || length > size - offset)
            throw SceneError(what + " (byteOffset " + std::to_string(offset) + ", byteLength " +
                             std::to_string(length) + ") does not lie inside buffers[" +
                             std::to_string(buffer) + "] (" + std::to_string(size) + " bytes)");
    }
}

// nlohmann's messages quote the whole token read last, which may be a data: URI
// of megabytes: only its start is kept.
std::string json_error(const Json::exception& e) {
    constexpr std::string_view kLastRead = "; last read: '";
    const std::string_view message = e.what();
    const size_t at = message.find(kLastRead);
    if (at == std::string_view::npos) return std::string(message);
    std::string_view token = message.substr(at + kLastRead.size());
    if (!token.empty() && token.back() == '\'') token.remove_suffix(1);
    return std::string(message.substr(0, at)) + "; last read: " + in_quotes(token);
}

void add_extras(const Json& object, const std::string& element, const std::string& name,
                std::vector<SceneAdditions>& extras) {
    const Json* all = member(object, "extras");
    const Json* rt = all ? member(*all, "rt") : nullptr;
    if (!rt) return;
    if (!rt->is_object()) throw SceneError(name + ": " + element + " must be a JSON object");
    try {
        extras.push_back(read_scene_extras(rt->dump(), name + ": " + element));
    } catch (const std::invalid_argument& e) {
        throw SceneError(e.what());
    }
}

// Everything about the document that must hold before tinygltf parses it: its
// depth, required extensions, the files it references (named in `names`), image
// buffer views. Returns the `extras.rt` objects of the asset and of the scene
// to render, parsed. Sets `rewritten` to the document tinygltf must parse
// instead when it had to change it (prepare_compressed_json).
std::vector<SceneAdditions> check_document(std::string_view text, bool binary, const SceneFolder& folder,
                                           ReferenceNames& names, std::string& rewritten) {
    const std::string& name = folder.scene_name();
    if (json_depth(text) > kMaxJsonDepth)
        throw SceneError(name + ": JSON nesting is deeper than " + std::to_string(kMaxJsonDepth) + " levels");
    Json doc;
    try {
        doc = Json::parse(text);
    } catch (const Json::exception& e) {
        throw SceneError(name + ": invalid JSON: " + json_error(e));
    }
    if (!doc.is_object()) throw SceneError(name + ": the glTF document is not a JSON object");
    if (prepare_compressed_json(doc, name)) rewritten = doc.dump();

    if (const Json* required = member(doc, "extensionsRequired"); required && required->is_array()) {
        for (const Json& extension : *required) {
            if (!extension.is_string()) throw SceneError(name + ": extensionsRequired holds a value that is not a name");
            const std::string& id = extension.get_ref<const std::string&>();
            if (std::find(std::begin(kSupportedGltfExtensions), std::end(kSupportedGltfExtensions), id) ==
                std::end(kSupportedGltfExtensions))
                throw SceneError(name + ": requires the glTF extension " + in_quotes(id) + ", which is not supported" +
                                 (id == "KHR_texture_basisu" ? std::string(": ") + kBasisuAdvice : std::string()));
        }
    }
    check_references(doc, "buffers", binary, folder, names);
    check_references(doc, "images", binary, folder, names);
    // Both run (`|`, not `||`): each fills in what tinygltf would refuse.
    if (relabel_image_data_uris(doc) | mark_viewless_indices(doc)) rewritten = doc.dump();
    check_image_views(doc, name);

    std::vector<SceneAdditions> extras;
    try {
        if (const Json* asset = member(doc, "asset")) add_extras(*asset, "asset.extras.rt", name, extras);
        const Json* scenes = member(doc, "scenes");
        const uint64_t scene = unsigned_or(doc, "scene", 0);
        if (scenes && scenes->is_array() && scene < scenes->size())
            add_extras((*scenes)[scene], "scenes[" + std::to_string(scene) + "].extras.rt", name, extras);
    } catch (const Json::exception& e) {
        throw SceneError(name + ": extras.rt: " + json_error(e));
    }
    return extras;
}

// tinygltf's view of the file system: only files the scene folder resolves to,
// so even a reference that slipped past check_document() cannot escape.
struct FileAccess {
    const SceneFolder& folder;
    const ReferenceNames& names;
    std::map<std::string, std::string> resolved;  // path handed out by expand() -> what names it
    std::optional<SceneError> error;  // the first refusal, thrown once tinygltf returns

    static FileAccess& of(void* user) { return *static_cast<FileAccess*>(user); }

    static std::string expand(const std::string& reference, void* user) {
        FileAccess& access = of(user);
        // tinygltf tries the reference as is, then prefixed with "./".
        const std::string bare = reference.substr(0, 2) == "./" ? reference.substr(2) : reference;
        const auto named = access.names.find(bare);
        const std::string element = named != access.names.end() ? named->second : "referenced file";
        try {
            const std::string path = access.folder.resolve(reference, element).string();
            access.resolved[path] = access.folder.scene_name() + ": " + element + " " + in_quotes(bare);
            return path;
        } catch (const SceneError& e) {
            if (!access.error) access.error = e;
            return {};
        }
    }

    static bool exists(const std::string& path, void* user) {
        std::error_code error;
        return of(user).resolved.count(path) != 0 && std::filesystem::exists(path, error);
    }

    static bool read(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
        FileAccess& access = of(user);
        try {
            const auto what = access.resolved.find(path);
            if (what == access.resolved.end())
                throw SceneError(access.folder.scene_name() + ": tinygltf asked for unresolved file " +
                                 in_quotes(path));
            auto bytes = read_file(path, what->second);
            if (!bytes) {
                *err += "file not found: " + path + "\n";
                return false;
            }
            *out = std::move(*bytes);
            return true;
        } catch (const SceneError& e) {
            if (!access.error) access.error = e;
            *err += e.what();
            return false;
        }
    }
};

// Images stay encoded until a material uses one (gltf_scene.cpp decodes it with
// its size checked first); those in buffer views are read from there later.
bool keep_encoded_image(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                        const unsigned char* bytes, int size, void*) {
    if (image->bufferView < 0 && size > 0) image->image.assign(bytes, bytes + size);
    return true;
}

// tinygltf's messages, joined into one line of bounded length: some quote whole
// data: URIs.
std::string one_line(std::string text) {
    constexpr size_t kMaxLength = 400;
    std::replace(text.begin(), text.end(), '\n', ' ');
    if (text.size() > kMaxLength) text = text.substr(0, kMaxLength) + "...";
    while (!text.empty() && text.back() == ' ') text.pop_back();
    return text;
}

}  // namespace

LoadedScene load_gltf(std::span<const unsigned char> data, bool binary, const SceneFolder& folder,
                      std::span<const SceneAdditions::Motion> motions) {
    const std::string& name = folder.scene_name();
    std::string_view json(reinterpret_cast<const char*>(data.data()), data.size());
    if (binary) data = check_glb(data, name, json);
    ReferenceNames names;
    std::string rewritten;
    std::vector<SceneAdditions> extras = check_document(json, binary, folder, names, rewritten);
    std::vector<unsigned char> rewritten_glb;
    if (!rewritten.empty()) {
        if (binary) {
            rewritten_glb = replace_glb_json(data, json, rewritten, name);
            data = rewritten_glb;
        }
        json = rewritten;
    }

    FileAccess access{folder, names, {}, std::nullopt};
    tinygltf::TinyGLTF parser;
    parser.SetFsCallbacks({&FileAccess::exists, &FileAccess::expand, &FileAccess::read, nullptr, &access});
    parser.SetImageLoader(&keep_encoded_image, nullptr);
    tinygltf::Model model;
    std::string error, warning;
    bool ok = false;
    try {
        ok = binary ? parser.LoadBinaryFromMemory(&model, &error, &warning, data.data(),
                                                  unsigned(data.size()), "")
                    : parser.LoadASCIIFromString(&model, &error, &warning, json.data(),
                                                 unsigned(json.size()), "");
    } catch (const std::exception& e) {
        throw SceneError(name + ": " + e.what());
    }
    if (access.error) throw *access.error;
    if (!ok) throw SceneError(name + ": " + one_line(error.empty() ? "cannot be parsed" : error));
    DecodeBudget budget;
    decode_meshopt(model, name, budget);
    decode_draco(model, name, budget);

    std::vector<SceneAdditions::Motion> all_motions;
    for (const SceneAdditions& additions : extras)
        all_motions.insert(all_motions.end(), additions.motions.begin(), additions.motions.end());
    all_motions.insert(all_motions.end(), motions.begin(), motions.end());
    LoadedScene loaded = build_gltf_scene(model, name, all_motions);
    loaded.extras = std::move(extras);
    for (std::string& approximation : approximation_warnings(model, name))
        loaded.scene.warnings.push_back(std::move(approximation));
    if (!warning.empty())
        loaded.scene.warnings.insert(loaded.scene.warnings.begin(), name + ": " + one_line(warning));
    return loaded;
}

}  // namespace rt
