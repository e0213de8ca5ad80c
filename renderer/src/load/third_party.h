// The third-party parsers the loaders use, configured once. tinygltf's class
// layout depends on its macros, so every file that includes it must see the same
// ones: include this header, never <tiny_gltf.h> directly.
//
// All of them are compiled from source in third_party.cpp (not linked from the
// system's shared libraries) so that the sanitizer build instruments them too.
#pragma once

// tinygltf reads files only through our FsCallbacks (scene_files.h) and images
// only through our decoder (texture_decode.h); it never writes anything.
#define TINYGLTF_NO_FS
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE

// tinyobjloader parses numbers as double; with float it would narrow them
// unchecked, and a value beyond float's range makes that conversion undefined.
// As double they reach obj_loader.cpp, which checks each before converting.
#define TINYOBJLOADER_USE_DOUBLE

#include <tiny_gltf.h>
#include <tiny_obj_loader.h>
