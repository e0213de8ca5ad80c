// Compressed glTF geometry (EXT_meshopt_compression, KHR_draco_mesh_compression)
// decoded as a pass over the parsed model, before the scene builder reads any
// accessor: afterwards the model holds plain buffer views, which GltfAccessor
// checks like any others. Every count a stream or its extension object claims is
// checked before it sizes an allocation.
#pragma once

#include <cstddef>
#include <string>

#include <nlohmann/json.hpp>

#include "load/format_loaders.h"
#include "load/scene_files.h"
#include "load/third_party.h"

namespace rt {

// What the decoded geometry of one file may take in all: no more than the
// largest uncompressed file we accept could hold, so compression never lets a
// file ask for more memory than it could without it.
inline constexpr size_t kMaxDecodedGeometryBytes = size_t(kMaxSceneFileBytes);

// Bytes of decoded geometry a file may still allocate; take() throws SceneError
// naming `what` once `bytes` more would exceed it.
class DecodeBudget {
  public:
    void take(size_t bytes, const std::string& what);

  private:
    size_t left_ = kMaxDecodedGeometryBytes;
};

// The JSON stage, before tinygltf parses the document (gltf_compressed_json.cpp):
// - checks that the numbers of every EXT_meshopt_compression and
//   KHR_draco_mesh_compression object are integers that fit an int, as tinygltf
//   2.7 truncates larger ones there (2^32 would read as 0), and that the objects
//   are objects (tinygltf drops others silently);
// - gives each meshopt fallback buffer (extensions.EXT_meshopt_compression.
//   fallback true) without a uri a 4-byte data: URI of its own, as tinygltf
//   insists on data for every buffer; only compressed views may refer to it;
// - gives each Draco primitive's indices accessor without a bufferView one to
//   parse with (the extension's, or 0), as tinygltf refuses indices without one.
// decode_meshopt() and decode_draco() replace what the placeholders point at. Throws
// SceneError prefixed with `scene_name`; returns whether `doc` changed.
bool prepare_compressed_json(nlohmann::json& doc, const std::string& scene_name);

// Decodes every bufferView with EXT_meshopt_compression into a new buffer and
// points the view at it. Throws SceneError prefixed with `scene_name`.
void decode_meshopt(tinygltf::Model& model, const std::string& scene_name, DecodeBudget& budget);

// Decodes every primitive with KHR_draco_mesh_compression into a new buffer and
// points the accessors it names (attributes, indices) at views of it.
void decode_draco(tinygltf::Model& model, const std::string& scene_name, DecodeBudget& budget);

}  // namespace rt
