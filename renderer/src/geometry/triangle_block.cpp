#include "geometry/triangle_block.h"

#include "util/parallel_runs.h"

namespace rt {
namespace {

// Below this many blocks (some 650 KB) a thread of its own costs more than it saves.
constexpr size_t kMinBlocksPerThread = 4096;

void fill_block(TriangleBlock& block, const uint32_t* ids, std::span<const vec3> positions,
                std::span<const uvec3> triangles, std::span<const uint8_t> alpha) {
    for (uint32_t lane = 0; lane < bvh::kBlockWidth; ++lane) {
        const uint32_t id = ids[lane];
        block.prim[lane] = id;
        // An empty lane's triangle has no area; the test masks it out anyway.
        for (int k = 0; k < 3; ++k) {
            const vec3 p = id == TriangleBlock::kEmpty ? vec3(0.0f) : positions[triangles[id][k]];
            for (int axis = 0; axis < 3; ++axis) block.v[k][axis][lane] = p[axis];
        }
        if (id != TriangleBlock::kEmpty && !alpha.empty() && alpha[id]) block.prim[lane] |= TriangleBlock::kAlphaBit;
    }
}

}  // namespace

HugePageVector<TriangleBlock> make_triangle_blocks(std::span<const uint32_t> prim_ids, std::span<const vec3> positions,
                                                std::span<const uvec3> triangles, std::span<const uint8_t> alpha,
                                                unsigned threads) {
    HugePageVector<TriangleBlock> blocks(prim_ids.size() / bvh::kBlockWidth);
    parallel_runs(threads, blocks.size(), kMinBlocksPerThread, [&](size_t begin, size_t end) {
        for (size_t b = begin; b < end; ++b)
            fill_block(blocks[b], &prim_ids[b * bvh::kBlockWidth], positions, triangles, alpha);
    });
    return blocks;
}

HugePageVector<TriangleBlock> make_motion_blocks(std::span<const TriangleBlock> open, std::span<const uint32_t> prim_ids,
                                              std::span<const vec3> positions_close, std::span<const uvec3> triangles,
                                              unsigned threads) {
    HugePageVector<TriangleBlock> motion = make_triangle_blocks(prim_ids, positions_close, triangles, {}, threads);
    for (size_t b = 0; b < motion.size(); ++b)
        for (int k = 0; k < 3; ++k)
            for (int axis = 0; axis < 3; ++axis)
                for (uint32_t lane = 0; lane < bvh::kBlockWidth; ++lane)
                    motion[b].v[k][axis][lane] -= open[b].v[k][axis][lane];
    return motion;
}

}  // namespace rt
