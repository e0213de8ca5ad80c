#include "rtcore_scene.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <thread>

#include <nanobind/stl/pair.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include "integrator/default_camera.h"
#include "export/glb_export.h"
#include "load/loader.h"
#include "integrator/render.h"
#include "rtcore_convert.h"

namespace rtcore {
namespace {

using Distances = nb::ndarray<const float, nb::shape<-1>, nb::c_contig, nb::device::cpu>;

// Runs body(begin, end) over [0, n) on `threads` threads.
template <class Body>
void parallel_for(size_t n, unsigned threads, Body body) {
    const size_t workers = std::min<size_t>(rt::resolve_thread_count(threads), std::max<size_t>(1, n / 4096));
    std::vector<std::thread> pool;
    const size_t chunk = (n + workers - 1) / std::max<size_t>(workers, 1);
    for (size_t w = 1; w < workers; ++w)
        pool.emplace_back(body, std::min(n, w * chunk), std::min(n, (w + 1) * chunk));
    body(0, std::min(n, chunk));
    for (auto& t : pool) t.join();
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

std::pair<std::vector<float>, std::vector<float>> PyScene::bounds() const {
    const rt::Bounds3 b = scene_->bounds();
    return {{b.min.x, b.min.y, b.min.z}, {b.max.x, b.max.y, b.max.z}};
}

std::vector<std::pair<std::string, nb::bytes>> PyScene::cameras() const {
    std::vector<std::pair<std::string, nb::bytes>> out;
    for (const auto& c : scene_->cameras) out.emplace_back(c.name, to_bytes(c.camera));
    return out;
}

nb::bytes PyScene::default_camera() const { return to_bytes(rt::default_camera(*scene_)); }

nb::list PyScene::lights() const {
    nb::list out;
    for (const auto& l : scene_->lights) {
        nb::dict d;
        d["name"] = l.name;
        d["position"] = std::vector<float>{l.position.x, l.position.y, l.position.z};
        d["intensity"] = std::vector<float>{l.intensity.x, l.intensity.y, l.intensity.z};
        d["radius"] = l.radius;
        out.append(d);
    }
    return out;
}

nb::dict PyScene::bvh_stats() const {
    const rt::AccelStats& s = accel_->stats();
    nb::dict d;
    d["triangles"] = s.triangles;
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

nb::bytes PyScene::bvh_boxes(int level) const {
    const rt::Accelerator::LevelBoxes boxes = accel_->boxes(level);
    rt::BvhBoxes message;
    message.set_level(level < 0 ? -1 : level);
    message.set_total_levels(accel_->stats().depth + 1);
    message.mutable_nodes()->Add(boxes.nodes.begin(), boxes.nodes.end());
    message.mutable_leaf_triangles()->Add(boxes.triangles.begin(), boxes.triangles.end());
    auto* bounds = message.mutable_bounds();
    bounds->Reserve(int(boxes.bounds.size() * 6));
    for (const rt::Bounds3& b : boxes.bounds)
        for (float f : {b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z}) bounds->Add(f);
    return to_bytes(message);
}

}  // namespace rtcore
