// EXT_meshopt_compression: each compressed bufferView is decoded into a buffer
// of its own. The extension's semantics are those of meshoptimizer's reference
// decoder (js/meshopt_decoder.js) and gltf/README.md of zeux/meshoptimizer.
#include <cmath>
#include <optional>

#include <meshoptimizer.h>

#include "load/gltf_compressed.h"
#include "load/loader.h"

namespace rt {
namespace {

constexpr const char* kExtension = "EXT_meshopt_compression";

// The largest decoded/encoded ratio of version 0 of the vertex codec: a block's
// header spends 2 bits on each group of 16 bytes of one byte channel, so 16
// bytes cost at least a quarter of a byte.
constexpr size_t kMaxVertexCodecRatio = 64;

enum class Mode { kAttributes, kTriangles, kIndices };
enum class Filter { kNone, kOctahedral, kQuaternion, kExponential };

// The extension object of one bufferView, as read from the file.
struct Compressed {
    size_t buffer = 0, byte_offset = 0, byte_length = 0, byte_stride = 0, count = 0;
    Mode mode = Mode::kAttributes;
    Filter filter = Filter::kNone;
};

class ViewReader {
  public:
    ViewReader(const tinygltf::Value& object, std::string what) : object_(object), what_(std::move(what)) {}

    [[noreturn]] void fail(const std::string& problem) const { throw SceneError(what_ + " " + problem); }

    // A non-negative integer property; `fallback` when left out, if it may be.
    size_t number(const char* key, std::optional<size_t> fallback = std::nullopt) const {
        if (!object_.Has(key)) {
            if (!fallback) fail("has no " + std::string(key));
            return *fallback;
        }
        const tinygltf::Value& value = object_.Get(key);
        // tinygltf keeps integers that do not fit an int as doubles; 2^53 bounds
        // those a double holds exactly, far above any size we accept.
        const double number = value.IsNumber() ? value.GetNumberAsDouble() : -1.0;
        if (!(number >= 0.0 && number <= 9007199254740992.0 && std::floor(number) == number))
            fail("has " + std::string(key) + " that is not a non-negative integer");
        return size_t(number);
    }

    std::string text(const char* key, const char* fallback) const {
        if (!object_.Has(key)) return fallback;
        const tinygltf::Value& value = object_.Get(key);
        if (!value.IsString()) fail("has " + std::string(key) + " that is not a string");
        return value.Get<std::string>();
    }

  private:
    const tinygltf::Value& object_;
    std::string what_;
};

Compressed read_extension(const tinygltf::Value& object, const std::string& what) {
    const ViewReader read(object, what);
    if (!object.IsObject()) read.fail("is not a JSON object");
    Compressed c;
    c.buffer = read.number("buffer");
    c.byte_offset = read.number("byteOffset", 0);
    c.byte_length = read.number("byteLength");
    c.byte_stride = read.number("byteStride");
    c.count = read.number("count");
    const std::string mode = read.text("mode", "");
    if (mode == "ATTRIBUTES") c.mode = Mode::kAttributes;
    else if (mode == "TRIANGLES") c.mode = Mode::kTriangles;
    else if (mode == "INDICES") c.mode = Mode::kIndices;
    else read.fail("has mode " + in_quotes(mode) + ", expected ATTRIBUTES, TRIANGLES or INDICES");
    const std::string filter = read.text("filter", "NONE");
    if (filter == "NONE") c.filter = Filter::kNone;
    else if (filter == "OCTAHEDRAL") c.filter = Filter::kOctahedral;
    else if (filter == "QUATERNION") c.filter = Filter::kQuaternion;
    else if (filter == "EXPONENTIAL") c.filter = Filter::kExponential;
    else read.fail("has filter " + in_quotes(filter) + ", expected NONE, OCTAHEDRAL, QUATERNION or EXPONENTIAL");
    return c;
}

// The strides and counts each mode and filter allows (meshoptimizer asserts
// them rather than checking), and the shortest stream that can hold `count`
// elements, so that a stream claiming far more than it can hold is refused
// before its output is allocated.
void check_shape(const Compressed& c, const ViewReader& read) {
    const std::string stride = "byteStride " + std::to_string(c.byte_stride);
    if (c.count == 0) read.fail("has count 0");
    if (c.mode == Mode::kAttributes) {
        if (c.byte_stride == 0 || c.byte_stride > 256 || c.byte_stride % 4 != 0)
            read.fail("has " + stride + ": ATTRIBUTES need a multiple of 4 from 4 to 256");
        if (c.count > kMaxSceneVertices)
            read.fail("has count " + std::to_string(c.count) + ", more than the " +
                      std::to_string(kMaxSceneVertices) + " vertices a scene may have");
        if (c.count * c.byte_stride / kMaxVertexCodecRatio > c.byte_length)
            read.fail("claims " + std::to_string(c.count) + " elements of " + std::to_string(c.byte_stride) +
                      " bytes, more than its " + std::to_string(c.byte_length) + " bytes can encode");
    } else {
        if (c.byte_stride != 2 && c.byte_stride != 4)
            read.fail("has " + stride + ": " + (c.mode == Mode::kTriangles ? "TRIANGLES" : "INDICES") +
                      " need 2 or 4");
        if (c.count > 3 * kMaxSceneTriangles)
            read.fail("has count " + std::to_string(c.count) + ", more indices than the " +
                      std::to_string(kMaxSceneTriangles) + " triangles a scene may have");
        if (c.mode == Mode::kTriangles && c.count % 3 != 0)
            read.fail("has mode TRIANGLES and count " + std::to_string(c.count) + ", not a multiple of 3");
        // meshoptimizer's own minimum: a header byte, then a code byte per
        // triangle and a 16-byte tail, or at least a byte per index and a 4-byte tail.
        const size_t shortest = c.mode == Mode::kTriangles ? 1 + c.count / 3 + 16 : 1 + c.count + 4;
        if (c.byte_length < shortest)
            read.fail("claims " + std::to_string(c.count) + " indices, more than its " +
                      std::to_string(c.byte_length) + " bytes can encode (at least " + std::to_string(shortest) +
                      " needed)");
    }
    if (c.filter != Filter::kNone && c.mode != Mode::kAttributes) read.fail("has a filter but mode is not ATTRIBUTES");
    if (c.filter == Filter::kOctahedral && c.byte_stride != 4 && c.byte_stride != 8)
        read.fail("has filter OCTAHEDRAL and " + stride + ", expected 4 or 8");
    if (c.filter == Filter::kQuaternion && c.byte_stride != 8)
        read.fail("has filter QUATERNION and " + stride + ", expected 8");
}

std::vector<unsigned char> decode(const Compressed& c, const unsigned char* stream, const ViewReader& read) {
    std::vector<unsigned char> out(c.count * c.byte_stride);
    int result = 0;
    switch (c.mode) {
        case Mode::kAttributes:
            result = meshopt_decodeVertexBuffer(out.data(), c.count, c.byte_stride, stream, c.byte_length);
            break;
        case Mode::kTriangles:
            result = meshopt_decodeIndexBuffer(out.data(), c.count, c.byte_stride, stream, c.byte_length);
            break;
        case Mode::kIndices:
            result = meshopt_decodeIndexSequence(out.data(), c.count, c.byte_stride, stream, c.byte_length);
            break;
    }
    if (result != 0)
        read.fail("cannot be decoded (meshoptimizer error " + std::to_string(result) +
                  (result == -1 ? ": unknown stream version)" : ": truncated or malformed stream)"));
    switch (c.filter) {
        case Filter::kNone: break;
        case Filter::kOctahedral: meshopt_decodeFilterOct(out.data(), c.count, c.byte_stride); break;
        case Filter::kQuaternion: meshopt_decodeFilterQuat(out.data(), c.count, c.byte_stride); break;
        case Filter::kExponential: meshopt_decodeFilterExp(out.data(), c.count, c.byte_stride); break;
    }
    return out;
}

}  // namespace

void DecodeBudget::take(size_t bytes, const std::string& what) {
    if (bytes > left_)
        throw SceneError(what + " would take the decoded geometry past the limit of " +
                         std::to_string(kMaxDecodedGeometryBytes) + " bytes");
    left_ -= bytes;
}

void decode_meshopt(tinygltf::Model& model, const std::string& scene_name, DecodeBudget& budget) {
    for (size_t i = 0; i < model.bufferViews.size(); ++i) {
        tinygltf::BufferView& view = model.bufferViews[i];
        const auto extension = view.extensions.find(kExtension);
        if (extension == view.extensions.end()) continue;
        const std::string what = scene_name + ": bufferViews[" + std::to_string(i) + "]." + kExtension;
        const ViewReader read(extension->second, what);
        const Compressed c = read_extension(extension->second, what);
        check_shape(c, read);
        if (c.buffer >= model.buffers.size())
            read.fail("refers to buffer " + std::to_string(c.buffer) + ", which does not exist");
        const size_t held = model.buffers[c.buffer].data.size();
        if (c.byte_offset > held || c.byte_length > held - c.byte_offset)
            read.fail("(byteOffset " + std::to_string(c.byte_offset) + ", byteLength " +
                      std::to_string(c.byte_length) + ") reaches past the end of buffers[" +
                      std::to_string(c.buffer) + "] (" + std::to_string(held) + " bytes)");
        if (view.byteLength != c.count * c.byte_stride)
            read.fail("decodes to " + std::to_string(c.count * c.byte_stride) + " bytes, but the bufferView's " +
                      "byteLength is " + std::to_string(view.byteLength));
        if (c.mode == Mode::kAttributes && view.byteStride != 0 && view.byteStride != c.byte_stride)
            read.fail("has byteStride " + std::to_string(c.byte_stride) + ", but the bufferView's is " +
                      std::to_string(view.byteStride));
        budget.take(c.count * c.byte_stride, what);

        tinygltf::Buffer decoded;
        decoded.data = decode(c, model.buffers[c.buffer].data.data() + c.byte_offset, read);
        model.buffers.push_back(std::move(decoded));
        view.buffer = int(model.buffers.size() - 1);
        view.byteOffset = 0;
        view.extensions.erase(extension);
    }
}

}  // namespace rt
