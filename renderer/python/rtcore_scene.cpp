#include "rtcore_scene.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <stdexcept>
#include <string>

#include <nanobind/stl/pair.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include "integrator/default_camera.h"
#include "export/glb_export.h"
#include "load/loader.h"
#include "integrator/render.h"
#include "rt/job.pb.h"
#include "rtcore_convert.h"
#include "util/thread_pool.h"

namespace rtcore {
namespace {

using Distances = nb::ndarray<const float, nb::shape<-1>, nb::c_contig, nb::device::cpu>;

// Runs body(begin, end) over [0, n) on `threads` threads (rt::parallel_for),
// in one chunk per thread and no more threads than chunks of 4096 rays.
template <class Body>
void parallel_for(size_t n, unsigned threads, Body body) {
    const size_t chunks = std::min<size_t>(rt::resolve_thread_count(threads), std::max<size_t>(1, n / 4096));
    const size_t chunk = (n + chunks - 1) / chunks;
    rt::parallel_for(threads, chunks, [&](size_t c) { body(std::min(n, c * chunk), std::min(n, (c + 1) * chunk)); });
}

std::vector<rt::Ray> read_rays(const Points& origins, const Points& directions, const nb::handle& t_max) {
    const size_t n = origins.shape(0);
    if (directions.shape(0) != n)
        throw std::invalid_argument("directions: " + std::to_string(directions.shape(0)) +
                                    " rows, but origins has " + std::to_string(n));
    const float* t = nullptr;
    Distances distances;
    if (!t_max.is_none()) {
        distances = nb::cast<Distances>(t_max);
        if (distances.shape(0) != n)
            throw std::invalid_argument("t_max: " + std::to_string(distances.shape(0)) + " values, but " +
                                        std::to_string(n) + " rays");
        t = distances.data();
    }
    std::vector<rt::Ray> rays(n);
    const float* o = origins.data();
    const float* d = directions.data();
    for (size_t i = 0; i < n; ++i) {
        rt::Ray& ray = rays[i];
        ray.origin = {o[3 * i], o[3 * i + 1], o[3 * i + 2]};
        ray.direction = {d[3 * i], d[3 * i + 1], d[3 * i + 2]};
        ray.t_max = t ? t[i] : rt::kInfinity;
        if (!rt::is_finite(ray.origin) || !rt::is_finite(ray.direction) || ray.direction == rt::vec3(0.0f) ||
            std::isnan(ray.t_max))
            throw std::invalid_argument("ray " + std::to_string(i) +
                                        ": origin and direction must be finite and the direction non-zero");
    }
    return rays;
}

}  // namespace

PyScene* PyScene::load(const std::string& path, unsigned threads) {
    nb::gil_scoped_release release;
    return new PyScene(rt::load_scene(path), threads);
}

PyScene* PyScene::from_bytes(const nb::bytes& data, const std::string& name, unsigned threads) {
    const auto* begin = reinterpret_cast<const std::byte*>(data.c_str());
    std::vector<std::byte> copy(begin, begin + data.size());
    nb::gil_scoped_release release;
    return new PyScene(rt::load_scene_from_memory(copy, name), threads);
}

nb::bytes PyScene::info() const {
    const auto add_vec3 = [](google::protobuf::RepeatedField<float>* field, rt::vec3 v) {
        for (float f : {v.x, v.y, v.z}) field->Add(f);
    };
    rt::SceneInfo info;
    info.set_triangle_count(uint32_t(std::min<size_t>(scene_->placed_triangles(), UINT32_MAX)));
    info.set_sphere_count(uint32_t(scene_->spheres.size()));
    info.set_degenerate_triangles(uint32_t(scene_->degenerate_triangles));
    const rt::Bounds3 bounds = scene_->bounds();
    add_vec3(info.mutable_bounds_min(), bounds.min);
    add_vec3(info.mutable_bounds_max(), bounds.max);
    for (const rt::Light& light : scene_->lights) {
        rt::LightSpec* spec = info.add_lights();
        add_vec3(spec->mutable_position(), light.position);
        // The scene holds colour times intensity: the record keeps it as the colour.
        add_vec3(spec->mutable_color(), light.intensity);
        spec->set_intensity(1.0f);
        spec->set_radius(light.radius);
        spec->set_kind(light.kind);
        if (light.kind != rt::POINT) add_vec3(spec->mutable_direction(), light.direction);
        if (light.kind == rt::SPOT) {
            spec->set_inner_cone_angle(std::acos(light.cos_inner) * 180.0f / rt::kPi);
            spec->set_outer_cone_angle(std::acos(light.cos_outer) * 180.0f / rt::kPi);
        }
        spec->set_range(light.range);
        spec->set_angular_diameter(light.angular_diameter * 180.0f / rt::kPi);
    }
    info.set_light_rig(scene_->rig_lights > 0);
    for (const rt::SceneCamera& camera : scene_->cameras) {
        rt::NamedCamera* named = info.add_cameras();
        named->set_name(camera.name);
        *named->mutable_camera() = camera.camera;
    }
    *info.mutable_default_camera() = rt::default_camera(*scene_);
    for (const std::string& warning : scene_->warnings) info.add_warnings(warning);
    return to_bytes(info);
}

size_t PyScene::texture_bytes() const {
    size_t bytes = 0;
    for (const rt::Texture& texture : scene_->textures) bytes += texture.bytes();
    return bytes;
}

size_t PyScene::memory_bytes() const {
    const rt::AccelStats& s = accel_->stats();
    return scene_->stored_bytes() + s.node_bytes + s.leaf_bytes;
}

nb::bytes PyScene::default_camera() const { return to_bytes(rt::default_camera(*scene_)); }

nb::dict PyScene::bvh_stats() const {
    const rt::AccelStats& s = accel_->stats();
    nb::dict d;
    d["triangles"] = s.triangles;  // stored: a shared mesh once
    d["instances"] = s.instances;
    d["nodes"] = s.nodes;
    d["leaves"] = s.leaves;
    d["depth"] = s.depth;
    d["build_ms"] = s.build_ms;
    d["sah_cost"] = s.sah_cost;
    return d;
}

nb::bytes PyScene::to_glb() const {
    std::string glb;
    {
        nb::gil_scoped_release release;
        glb = rt::export_glb(*scene_);
    }
    return nb::bytes(glb.data(), glb.size());
}

nb::tuple PyScene::intersect(const Points& origins, const Points& directions, nb::handle t_max,
                             unsigned threads) const {
    const std::vector<rt::Ray> rays = read_rays(origins, directions, t_max);
    const size_t n = rays.size();
    std::vector<float> t(n), u(n), v(n);
    std::vector<int64_t> primitive(n);
    {
        nb::gil_scoped_release release;
        parallel_for(n, threads, [&](size_t begin, size_t end) {
            for (size_t i = begin; i < end; ++i) {
                rt::Hit hit;
                accel_->intersect(rays[i], hit);
                t[i] = hit.t;
                u[i] = hit.u;
                v[i] = hit.v;
                primitive[i] = hit.found() ? int64_t(hit.primitive) : -1;
            }
        });
    }
    return nb::make_tuple(to_numpy(std::move(t), {n}), to_numpy(std::move(primitive), {n}),
                          to_numpy(std::move(u), {n}), to_numpy(std::move(v), {n}));
}

nb::ndarray<nb::numpy, bool> PyScene::occluded(const Points& origins, const Points& directions, nb::handle t_max,
                                               unsigned threads) const {
    const std::vector<rt::Ray> rays = read_rays(origins, directions, t_max);
    const size_t n = rays.size();
    std::vector<uint8_t> blocked(n);
    {
        nb::gil_scoped_release release;
        parallel_for(n, threads, [&](size_t begin, size_t end) {
            for (size_t i = begin; i < end; ++i) blocked[i] = accel_->occluded(rays[i]);
        });
    }
    auto* owned = new std::vector<uint8_t>(std::move(blocked));
    nb::capsule owner(owned, [](void* p) noexcept { delete static_cast<std::vector<uint8_t>*>(p); });
    return nb::ndarray<nb::numpy, bool>(owned->data(), {n}, owner);
}

nb::bytes PyScene::bvh_boxes(int level, const std::string& tree) const {
    // "top", "world" or an instance number, as GET /api/scenes/<id>/bvh?tree= takes it.
    uint32_t walked = rt::Accelerator::kTopTree;
    rt::BvhTreeKind kind = rt::BVH_TREE_TOP;
    if (tree == "world") {
        walked = rt::AccelScene::kWorldEntry;
        kind = rt::BVH_TREE_WORLD;
    } else if (tree != "top") {
        size_t used = 0;
        unsigned long instance = 0;
        try {
            instance = std::stoul(tree, &used);
        } catch (const std::exception&) {
            used = 0;
        }
        if (used == 0 || used != tree.size() || !std::isdigit(static_cast<unsigned char>(tree[0])) ||
            instance >= accel_->instance_count())
            throw std::invalid_argument("tree: '" + tree + "' is not top, world or an instance number below " +
                                        std::to_string(accel_->instance_count()));
        walked = uint32_t(instance);
        kind = rt::BVH_TREE_INSTANCE;
    }
    const rt::Accelerator::LevelBoxes boxes = accel_->boxes(level, walked);
    rt::BvhBoxes message;
    message.set_level(level < 0 ? -1 : level);
    message.set_total_levels(boxes.depth + 1);
    message.mutable_nodes()->Add(boxes.nodes.begin(), boxes.nodes.end());
    message.mutable_leaf_triangles()->Add(boxes.triangles.begin(), boxes.triangles.end());
    for (uint8_t leaf : boxes.leaf) message.add_leaf(leaf != 0);
    message.set_node_width(rt::bvh::kWideWidth);
    auto* bounds = message.mutable_bounds();
    bounds->Reserve(int(boxes.bounds.size() * 6));
    for (const rt::Bounds3& b : boxes.bounds)
        for (float f : {b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z}) bounds->Add(f);
    message.set_tree(kind);
    if (kind == rt::BVH_TREE_INSTANCE) {
        message.set_instance(walked);
        const std::vector<std::string>& names = scene_->instance_names;
        if (walked < names.size()) message.set_instance_name(names[walked]);
    }
    for (int column = 0; column < 3; ++column)
        for (int row = 0; row < 4; ++row) message.add_to_world(row < 3 ? boxes.to_world.linear[column][row] : 0.0f);
    for (int row = 0; row < 3; ++row) message.add_to_world(boxes.to_world.translation[row]);
    message.add_to_world(1.0f);
    message.set_instance_count(uint32_t(accel_->instance_count()));
    message.set_has_world_tree(accel_->has_world_entry());
    return to_bytes(message);
}

}  // namespace rtcore
