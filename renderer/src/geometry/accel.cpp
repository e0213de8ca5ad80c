#include "geometry/accel.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <string>

#include "bvh/binned_sah_builder.h"
#include "bvh/wide_collapse.h"
#include "util/cpu_features.h"
#include "util/parallel_runs.h"
#include "util/thread_pool.h"

namespace rt {
namespace {

// The binary build's SAH in units of one four-triangle block test (its leaves
// priced in blocks, as the wide tree tests them): a binary step costs about
// one. On the dragons' diffuse and shadow rays a few percent faster than
// pricing single triangles with a step of 2 (bench/bvh_bench).
constexpr float kTraversalCost = 1.0f;
// Binary leaves of at most one block: the collapse (collapse_plan.h) then
// chooses which subtrees to merge into leaves, by the wide tree's SAH.
constexpr uint32_t kBinaryLeafSize = bvh::kBlockWidth;
// Wide leaves of up to two blocks: on the dragons' diffuse and shadow rays a
// few percent faster than one block, and no faster with more (bench/bvh_bench).
constexpr uint32_t kWideLeafSize = 2 * bvh::kBlockWidth;
// The collapse prices a wide node at two block tests: the dragons' rays run a
// few percent faster than at one (which Embree's SAH statistics assume, and
// by which the tree then costs some 1% more, still under Embree's).
constexpr float kCollapseNodeCost = 2.0f;
// Below this many triangles their boxes are not worth a thread of their own.
constexpr size_t kMinTrianglesPerThread = 16384;
// For the wide tree's SAH (AccelStats): one eight-box test, one four-triangle block test.
constexpr double kWideNodeCost = 1.0;
constexpr double kBlockCost = 1.0;

const AccelKernels& kernels_for(SimdPath path) {
    if (!cpu_supports(path)) throw std::runtime_error(std::string("SIMD path ") + to_string(path) + " is not supported by this CPU");
    switch (path) {
        case SimdPath::avx512: return avx512::kKernels;
        case SimdPath::avx2: return avx2::kKernels;
        case SimdPath::generic: break;
    }
    return generic::kKernels;
}

// One tree over scene.triangles[first, first + count), in whatever space
// they are in; adds its sizes to `stats`.
// Some vertex of those triangles moves while the shutter is open.
bool triangles_move(const Scene& scene, size_t first, size_t count) {
    if (!scene.moving()) return false;
    for (size_t i = first; i < first + count; ++i)
        for (int k = 0; k < 3; ++k) {
            const uint32_t v = scene.triangles[i][k];
            if (scene.positions[v] != scene.positions_close[v]) return true;
        }
    return false;
}

// A tree's root box at shutter open, or close (for a still tree the same).
Bounds3 root_bounds(const bvh::WideBvh& tree, bool at_close) {
    Bounds3 b;
    if (tree.empty()) return b;
    for (uint32_t i = 0; i < bvh::kWideWidth; ++i) {
        if (tree.nodes[0].child[i].empty()) continue;
        b.extend(at_close && !tree.motion.empty() ? tree.child_bounds_at_close(0, i) : tree.nodes[0].child_bounds(i));
    }
    return b;
}

// One tree over scene.triangles[first, first + count), in whatever space
// they are in; adds its sizes to `stats`.
AccelData build_tree(const Scene& scene, size_t first, size_t count, unsigned threads, AccelStats& stats) {
    AccelData data;
    data.scene = &scene;
    // A tree over moving triangles is built over each triangle's box halfway
    // through the shutter (the mean of its boxes at open and close), then
    // given its boxes at open and close (refit_motion), between which the
    // traversal interpolates: as Embree's linear-bounds SAH prices a box by its
    // area over time, not by the box that holds the whole sweep. Over the
    // sweeps, dragon_2 moving by 5% of its length built a tree of fewer,
    // fuller nodes (6450 against 7250) that rendered 2% slower. Triangles
    // that stand still in a moving scene (a shared mesh, which its instances
    // move) get a still tree.
    const bool moving = triangles_move(scene, first, count);
    std::vector<Bounds3> triangle_bounds(count), open_bounds, close_bounds;
    std::vector<vec3> centroids(count);
    std::vector<uint8_t> triangle_moves;
    if (moving) open_bounds.resize(count), close_bounds.resize(count), triangle_moves.resize(count);
    parallel_runs(threads, count, kMinTrianglesPerThread, [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) {
            const uvec3 tri = scene.triangles[first + i];
            Bounds3 b;
            for (int k = 0; k < 3; ++k) b.extend(scene.positions[tri[k]]);
            if (moving) {
                open_bounds[i] = b;
                for (int k = 0; k < 3; ++k) {
                    close_bounds[i].extend(scene.positions_close[tri[k]]);
                    triangle_moves[i] |= scene.positions[tri[k]] != scene.positions_close[tri[k]];
                }
                b = {0.5f * (b.min + close_bounds[i].min), 0.5f * (b.max + close_bounds[i].max)};
            }
            triangle_bounds[i] = b;
            centroids[i] = b.center();
        }
    });
    bvh::BuildOptions options;
    options.traversal_cost = kTraversalCost;
    options.threads = threads;
    options.leaf_block_size = bvh::kBlockWidth;
    options.max_leaf_size = kBinaryLeafSize;
    bvh::CollapseOptions collapse;
    collapse.max_leaf_prims = kWideLeafSize;
    collapse.node_cost = kCollapseNodeCost;
    collapse.threads = threads;
    data.bvh = bvh::collapse_to_wide(bvh::build_binned_sah(triangle_bounds, centroids, options), triangle_bounds, collapse);
    if (moving) bvh::refit_motion(data.bvh, open_bounds, close_bounds, triangle_moves);
    // The blocks hold scene triangle numbers.
    for (uint32_t& id : data.bvh.prim_ids)
        if (id != bvh::kNoPrim) id += uint32_t(first);

    std::vector<uint8_t> alpha;
    for (size_t i = first; i < first + count && !data.filtered; ++i)
        data.filtered = scene.materials[scene.triangle_materials[i]].alpha_mode != AlphaMode::Opaque;
    if (data.filtered) {
        alpha.resize(scene.triangles.size());
        for (size_t i = first; i < first + count; ++i)
            alpha[i] = scene.materials[scene.triangle_materials[i]].alpha_mode != AlphaMode::Opaque;
    }
    data.moving = moving;
    data.blocks = make_triangle_blocks(data.bvh.prim_ids, scene.positions, scene.triangles, alpha, threads);
    if (data.moving)
        data.blocks_motion = make_motion_blocks(data.blocks, data.bvh.prim_ids, scene.positions_close, scene.triangles, threads);
    data.bvh.prim_ids = {};
    // Fetching ahead pays where the tree and its leaves outgrow twice the L2
    // cache. 1T against rtcIntersect1 on the Xeon (2 MiB L2), diffuse rays
    // without the fetches: bunny 0.94 -> 0.98, teapot 0.99 -> 1.05, dragon_4
    // (0.6 MB) 0.88 -> 0.92, dragon_3 (2.4 MB) 0.90 -> 0.92, dragon_2 (10 MB)
    // alike, dragon_1 (45 MB) 0.95 -> 0.90.
    const size_t leaf_bytes = (data.blocks.size() + data.blocks_motion.size()) * sizeof(TriangleBlock);
    data.bvh.fetch_ahead = data.bvh.node_bytes() + leaf_bytes > 2 * l2_cache_bytes();

    stats.nodes += data.bvh.nodes.size();
    stats.leaves += data.bvh.leaf_count();
    stats.leaf_blocks += data.blocks.size();
    stats.node_bytes += data.bvh.node_bytes();
    stats.leaf_bytes += leaf_bytes;
    return data;
}

// The top-level tree over the instances' world boxes and the world tree's:
// one entry per leaf, since entering one costs a whole traversal. When some
// entry moves, its boxes at open and close are those of its content then (a
// moving instance's mesh box under its transforms at open and close, which
// hold it blended between), and the tree keeps both, as a tree over moving
// triangles does.
bvh::WideBvh build_top(const AccelScene& accel, unsigned threads) {
    const Scene& scene = *accel.scene;
    std::vector<uint32_t> entries;
    std::vector<Bounds3> open, close;
    std::vector<uint8_t> moves;
    std::vector<Bounds3> local(accel.meshes.size());
    for (size_t m = 0; m < accel.meshes.size(); ++m) local[m] = root_bounds(accel.meshes[m].bvh, false);
    bool moving = false;
    if (!accel.world.bvh.empty()) {
        entries.push_back(AccelScene::kWorldEntry);
        open.push_back(root_bounds(accel.world.bvh, false));
        close.push_back(root_bounds(accel.world.bvh, true));
        moves.push_back(accel.world.moving);
        moving = accel.world.moving;
    }
    for (uint32_t i = 0; i < scene.instances.size(); ++i) {
        const Instance& instance = scene.instances[i];
        const Bounds3& b = local[instance.mesh];
        if (b.empty()) continue;
        entries.push_back(i);
        open.push_back(instance.to_world.box(b));
        close.push_back(instance.to_world_close.box(b));
        moves.push_back(instance.moving);
        moving = moving || instance.moving;
    }
    std::vector<Bounds3> boxes(open.size());
    std::vector<vec3> centroids(open.size());
    for (size_t i = 0; i < boxes.size(); ++i) {
        boxes[i] = open[i];
        boxes[i].extend(close[i]);
        centroids[i] = boxes[i].center();
    }
    bvh::BuildOptions options;
    options.max_leaf_size = 1;
    options.threads = threads;
    bvh::CollapseOptions collapse;
    collapse.max_leaf_prims = 1;
    collapse.threads = threads;
    bvh::WideBvh top = bvh::collapse_to_wide(bvh::build_binned_sah(boxes, centroids, options), boxes, collapse);
    if (moving) bvh::refit_motion(top, open, close, moves);
    for (uint32_t& id : top.prim_ids)
        if (id != bvh::kNoPrim) id = entries[id];
    return top;
}

}  // namespace

Accelerator::Accelerator(const Scene& scene, unsigned threads) : Accelerator(scene, threads, simd_path()) {}

Accelerator::Accelerator(const Scene& scene, unsigned threads, SimdPath path)
    : path_(path), kernels_(&kernels_for(path)) {
    const auto start = std::chrono::steady_clock::now();
    data_.scene = &scene;
    // Triangle numbers leave the top bit for the block's alpha flag.
    if (scene.triangles.size() >= TriangleBlock::kAlphaBit) throw std::length_error("scene: too many triangles for the BVH");
    size_t next = scene.world_triangles();
    for (const SharedMesh& mesh : scene.meshes) {
        if (mesh.first_triangle != next || size_t(mesh.first_triangle) + mesh.triangle_count > scene.triangles.size())
            throw std::invalid_argument("scene: shared meshes must cover the tail of the triangles, in order");
        next += mesh.triangle_count;
    }
    if (next != scene.triangles.size()) throw std::invalid_argument("scene: triangles after the last shared mesh");
    for (const Instance& instance : scene.instances) {
        if (instance.mesh >= scene.meshes.size()) throw std::invalid_argument("scene: an instance of a mesh that does not exist");
        // Rays get times only in a moving scene (Scene::moving).
        if (instance.moving && !scene.moving())
            throw std::invalid_argument("scene: a moving instance in a scene without positions at shutter close");
    }

    // Resolved once: each of the build's parts would otherwise ask the system
    // for the core count, tens of microseconds each, as long as a whole build
    // of the Cornell box.
    threads = resolve_thread_count(threads);
    data_.world = build_tree(scene, 0, scene.world_triangles(), threads, stats_);
    for (const SharedMesh& mesh : scene.meshes)
        data_.meshes.push_back(build_tree(scene, mesh.first_triangle, mesh.triangle_count, threads, stats_));
    if (!scene.instances.empty()) {
        data_.top = build_top(data_, threads);
        stats_.nodes += data_.top.nodes.size();
        stats_.node_bytes += data_.top.node_bytes() + data_.top.prim_ids.size() * sizeof(uint32_t);
    }
    const bvh::WideBvh& walked = data_.instanced() ? data_.top : data_.world.bvh;
    stats_.triangles = scene.triangles.size();
    stats_.instances = scene.instances.size();
    stats_.depth = walked.depth;
    stats_.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    stats_.sah_cost = walked.sah_cost(kWideNodeCost, kBlockCost);
}

Accelerator::LevelBoxes Accelerator::boxes(int level, uint32_t tree) const {
    const Scene& scene = *data_.scene;
    const auto entry_triangles = [&](uint32_t entry) -> uint32_t {
        if (entry == AccelScene::kWorldEntry) return uint32_t(scene.world_triangles());
        return scene.meshes[scene.instances[entry].mesh].triangle_count;
    };
    LevelBoxes boxes;
    const AccelData* triangles = nullptr;  // the tree's blocks, unless it is the top level
    if (tree == kTopTree) {
        if (!data_.instanced()) triangles = &data_.world;
    } else if (tree == AccelScene::kWorldEntry) {
        if (!has_world_entry()) throw std::invalid_argument("tree: the scene has no triangles placed once beside its instances");
        triangles = &data_.world;
    } else {
        if (tree >= scene.instances.size())
            throw std::invalid_argument("tree: instance " + std::to_string(tree) + " does not exist; the scene has " +
                                        std::to_string(scene.instances.size()));
        triangles = &data_.tree_of(tree);
        boxes.to_world = scene.instances[tree].to_world;
    }
    // A triangle tree's leaf: the triangles in its blocks; a top-level leaf: those its entries place.
    const auto leaf_triangles = [&](bvh::ChildRef leaf) {
        uint32_t count = 0;
        for (uint32_t b = leaf.first_block(); b < leaf.first_block() + leaf.block_count(); ++b)
            for (uint32_t lane = 0; lane < bvh::kBlockWidth; ++lane) {
                if (triangles) {
                    count += triangles->blocks[b].lane_used(lane);
                } else {
                    const uint32_t entry = data_.top.prim_ids[size_t(b) * bvh::kBlockWidth + lane];
                    if (entry != bvh::kNoPrim) count += entry_triangles(entry);
                }
            }
        return count;
    };
    const bvh::WideBvh& walked = triangles ? triangles->bvh : data_.top;
    boxes.depth = walked.depth;
    for (const bvh::WideBvh::Box& box : walked.boxes(leaf_triangles)) {
        const bool wanted = level < 0 ? box.leaf : box.level == uint32_t(level);
        if (!wanted) continue;
        boxes.nodes.push_back(box.id);
        boxes.bounds.push_back(box.bounds);
        boxes.triangles.push_back(box.prims);
        boxes.leaf.push_back(box.leaf);
    }
    return boxes;
}

bool Accelerator::intersect(std::span<const Ray> rays, std::span<Hit> hits) const {
    if (rays.size() != hits.size() || rays.size() > kPacketSize)
        throw std::invalid_argument("a packet of " + std::to_string(rays.size()) + " rays and " +
                                    std::to_string(hits.size()) + " hits (at most " + std::to_string(kPacketSize) +
                                    " rays, one hit each)");
    return kernels_->intersect_packet(data_, rays.data(), uint32_t(rays.size()), hits.data());
}

bool Accelerator::packets_serve() const { return data_.packets_serve(); }

bool Accelerator::visibility(std::span<const Ray> rays, std::span<float> visibility) const {
    if (rays.size() != visibility.size() || rays.size() > kPacketSize)
        throw std::invalid_argument("a packet of " + std::to_string(rays.size()) + " rays and " +
                                    std::to_string(visibility.size()) + " visibilities (at most " +
                                    std::to_string(kPacketSize) + " rays, one each)");
    return kernels_->visibility_packet(data_, rays.data(), uint32_t(rays.size()), visibility.data());
}

}  // namespace rt
