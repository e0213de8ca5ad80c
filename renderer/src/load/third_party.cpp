// The implementations of the header-only parsers, in our own translation unit so
// that the sanitizer build covers them (see third_party.h for their configuration).

// stb_image decodes only the formats glTF and OBJ scenes use. Its own dimension
// limit is a first line; texture_decode.cpp caps the texel count far lower.
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#define STBI_ONLY_JPEG
#define STBI_ONLY_BMP
#define STBI_ONLY_TGA
#define STBI_MAX_DIMENSIONS 65536
#include <stb_image.h>

// tinygltf's writer (which we never call) uses std::ofstream even when
// TINYGLTF_NO_FS leaves out the header that declares it.
#include <fstream>

#define TINYGLTF_IMPLEMENTATION
#define TINYOBJLOADER_IMPLEMENTATION
#include "load/third_party.h"
