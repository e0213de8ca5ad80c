// MikkTSpace tangents: the tangent frame a normal map was baked in, which
// glTF asks a renderer to compute where a mesh has no TANGENT attribute.
//
// A C++ port of Morten S. Mikkelsen's reference implementation, mikktspace.c
// (https://github.com/mmikk/MikkTSpace, commit 3e895b4; zlib licence:
// Copyright (C) 2011 by Morten S. Mikkelsen. This is an altered version: it
// reads triangles only, from a vector of corners instead of callbacks, and
// allocates with std::vector). The algorithm is the reference's step by step,
// so the tangents are the same a baker computed: corners with equal position,
// normal and texcoord are welded, welded corners whose triangles agree on the
// uv orientation share one tangent space (averaged by the angle each triangle
// spans at the corner), and degenerate triangles copy a neighbour's.
// The analysis: M. S. Mikkelsen, "Simulation of wrinkled surfaces revisited",
// master's thesis, University of Copenhagen, 2008.
#pragma once

#include <span>
#include <vector>

#include "util/math.h"

namespace rt {

// One triangle corner as MikkTSpace reads it; corners 3t, 3t + 1, 3t + 2 make
// triangle t. The normal should be unit length, as the reference assumes.
struct TangentCorner {
    vec3 position{0.0f};
    vec3 normal{0.0f};
    vec2 texcoord{0.0f};
};

// One tangent per corner: xyz unit length, w = +1 or -1 the sign of the
// bitangent B = w * cross(N, T) in MikkTSpace's convention (v up; glTF's v
// points down the image, so glTF's TANGENT w is the negative of this one).
// A corner no good triangle gives a space keeps the reference's default,
// (1, 0, 0, -1). Throws std::invalid_argument when the corners are not whole
// triangles or number more than the reference's int indices allow.
std::vector<glm::vec4> mikktspace_tangents(std::span<const TangentCorner> corners);

}  // namespace rt
