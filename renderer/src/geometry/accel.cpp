#include "geometry/accel.h"

#include <chrono>
#include <stdexcept>

#include "bvh/binned_sah_builder.h"
#include "bvh/wide_collapse.h"

namespace rt {
namespace {

// The binary build's SAH in units of one four-triangle block test (its leaves
// priced in blocks, as the wide tree tests them): a binary step costs about
// one. On the dragons' diffuse and shadow rays a few percent faster than
// pricing single triangles with a step of 2 (bench/bvh_bench).
constexpr float kTraversalCost = 1.0f;
// Subtrees of at most this many triangles become one leaf of up to two blocks:
// on the dragons' diffuse and shadow rays a few percent faster than one block
// (kBlockWidth), and no faster with three or four (bench/bvh_bench).
constexpr uint32_t kLeafMergeLimit = 2 * bvh::kBlockWidth;
// For the wide tree's SAH (AccelStats): one eight-box test, one four-triangle block test.
constexpr double kWideNodeCost = 1.0;
constexpr double kBlockCost = 1.0;

const AccelKernels& kernels_for(SimdPath path) {
    if (!cpu_supports(path)) throw std::runtime_error(std::string("SIMD path ") + to_string(path) + " is not supported by this CPU");
    return path == SimdPath::avx2 ? avx2::kKernels : generic::kKernels;
}

}  // namespace

Accelerator::Accelerator(const Scene& scene, unsigned threads) : Accelerator(scene, threads, simd_path()) {}

Accelerator::Accelerator(const Scene& scene, unsigned threads, SimdPath path)
    : path_(path), kernels_(&kernels_for(path)) {
    const auto start = std::chrono::steady_clock::now();
    data_.scene = &scene;
    const size_t count = scene.triangles.size();
    // Triangle numbers leave the top bit for the block's alpha flag.
    if (count >= TriangleBlock::kAlphaBit) throw std::length_error("scene: too many triangles for the BVH");
    // A moving scene's tree is built over the boxes that hold each triangle
    // all the shutter long, then given its boxes at open and close.
    std::vector<Bounds3> triangle_bounds(count), open_bounds, close_bounds;
    std::vector<vec3> centroids(count);
    if (scene.moving()) open_bounds.resize(count), close_bounds.resize(count);
    for (size_t i = 0; i < count; ++i) {
        Bounds3 b;
        for (int k = 0; k < 3; ++k) b.extend(scene.positions[scene.triangles[i][k]]);
        if (scene.moving()) {
            open_bounds[i] = b;
            for (int k = 0; k < 3; ++k) close_bounds[i].extend(scene.positions_close[scene.triangles[i][k]]);
            b.extend(close_bounds[i]);
        }
        triangle_bounds[i] = b;
        centroids[i] = b.center();
    }
    bvh::BuildOptions options;
    options.traversal_cost = kTraversalCost;
    options.threads = threads;
    options.leaf_block_size = bvh::kBlockWidth;
    data_.bvh = bvh::collapse_to_wide(bvh::build_binned_sah(triangle_bounds, centroids, options), triangle_bounds, kLeafMergeLimit);

    if (scene.moving()) bvh::refit_motion(data_.bvh, open_bounds, close_bounds);

    std::vector<uint8_t> alpha;
    for (const Material& m : scene.materials) data_.filtered = data_.filtered || m.alpha_mode != AlphaMode::Opaque;
    if (data_.filtered) {
        alpha.resize(count);
        for (size_t i = 0; i < count; ++i)
            alpha[i] = scene.materials[scene.triangle_materials[i]].alpha_mode != AlphaMode::Opaque;
    }
    data_.moving = scene.moving();
    data_.blocks = make_triangle_blocks(data_.bvh.prim_ids, scene.positions, scene.triangles, alpha);
    if (data_.moving)
        data_.blocks_motion = make_motion_blocks(data_.blocks, data_.bvh.prim_ids, scene.positions_close, scene.triangles);
    // The blocks hold the triangle numbers now.
    data_.bvh.prim_ids = {};

    stats_.triangles = count;
    stats_.nodes = data_.bvh.nodes.size();
    stats_.leaves = data_.bvh.leaf_count();
    stats_.leaf_blocks = data_.blocks.size();
    stats_.depth = data_.bvh.depth;
    stats_.node_bytes = data_.bvh.node_bytes();
    stats_.leaf_bytes = (data_.blocks.size() + data_.blocks_motion.size()) * sizeof(TriangleBlock);
    stats_.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    stats_.sah_cost = data_.bvh.sah_cost(kWideNodeCost, kBlockCost);
}

Accelerator::LevelBoxes Accelerator::boxes(int level) const {
    const auto leaf_triangles = [&](bvh::ChildRef leaf) {
        uint32_t triangles = 0;
        for (uint32_t b = leaf.first_block(); b < leaf.first_block() + leaf.block_count(); ++b)
            for (uint32_t lane = 0; lane < bvh::kBlockWidth; ++lane) triangles += data_.blocks[b].lane_used(lane);
        return triangles;
    };
    LevelBoxes boxes;
    for (const bvh::WideBvh::Box& box : data_.bvh.boxes(leaf_triangles)) {
        const bool wanted = level < 0 ? box.leaf : box.level == uint32_t(level);
        if (!wanted) continue;
        boxes.nodes.push_back(box.id);
        boxes.bounds.push_back(box.bounds);
        boxes.triangles.push_back(box.prims);
        boxes.leaf.push_back(box.leaf);
    }
    return boxes;
}

}  // namespace rt
