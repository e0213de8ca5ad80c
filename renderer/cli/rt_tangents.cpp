// rt_tangents: the renderer's MikkTSpace tangents (geometry/mikktspace.h) for
// a mesh on stdin, so that tests/web/mikktspace.test.mjs can hold them
// against the reference built to WebAssembly (npm mikktspace).
//
// stdin, little-endian: uint32 corner count n (a multiple of 3), then n
// corners of 8 float32 each (position xyz, normal xyz, texcoord uv).
// stdout: n tangents of 4 float32 each (xyz, w in MikkTSpace's convention).
#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <vector>

#include "geometry/mikktspace.h"

int main() {
    try {
        uint32_t count = 0;
        if (std::fread(&count, sizeof count, 1, stdin) != 1) throw std::runtime_error("no corner count on stdin");
        std::vector<float> input(size_t(count) * 8);
        if (!input.empty() && std::fread(input.data(), sizeof(float), input.size(), stdin) != input.size())
            throw std::runtime_error("stdin ends before its corners do");
        std::vector<rt::TangentCorner> corners(count);
        for (size_t c = 0; c < count; ++c) {
            const float* f = &input[c * 8];
            corners[c] = {rt::vec3(f[0], f[1], f[2]), rt::vec3(f[3], f[4], f[5]), rt::vec2(f[6], f[7])};
        }
        const std::vector<glm::vec4> tangents = rt::mikktspace_tangents(corners);
        if (!tangents.empty() && std::fwrite(tangents.data(), sizeof(glm::vec4), tangents.size(), stdout) != tangents.size())
            throw std::runtime_error("cannot write the tangents");
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "rt_tangents: %s\n", e.what());
        return 1;
    }
}
