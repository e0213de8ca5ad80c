// rtcore: the renderer as a Python module. Heavy calls release the GIL, so a
// Dask worker's threads render tiles in parallel. Camera and settings arrive as
// rt.Camera / rt.RenderSettings, serialized (bytes) or in their JSON form (str);
// debug paths and BVH boxes leave as serialized rt.DebugPath / rt.BvhBoxes.
#include <algorithm>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/pair.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/tuple.h>
#include <nanobind/stl/vector.h>

#include "accel.h"
#include "default_camera.h"
#include "loader.h"
#include "proto_limits.h"
#include "render.h"
#include "rt/job.pb.h"

namespace nb = nanobind;
using namespace nb::literals;

namespace {

using Points = nb::ndarray<const float, nb::shape<-1, 3>, nb::c_contig, nb::device::cpu>;
using Distances = nb::ndarray<const float, nb::shape<-1>, nb::c_contig, nb::device::cpu>;

template <class T>
nb::ndarray<nb::numpy, T> to_numpy(std::vector<T>&& values, std::initializer_list<size_t> shape) {
    auto* owned = new std::vector<T>(std::move(values));
    nb::capsule owner(owned, [](void* p) noexcept { delete static_cast<std::vector<T>*>(p); });
    return nb::ndarray<nb::numpy, T>(owned->data(), shape, owner);
}

// bytes: the serialized message; str: its JSON form; None: all defaults.
template <class Message>
Message read_message(const nb::handle& value, const char* path) {
    Message message;
    if (value.is_none()) {
    } else if (nb::isinstance<nb::bytes>(value)) {
        const auto data = nb::borrow<nb::bytes>(value);
        if (!message.ParseFromArray(data.c_str(), int(data.size())))
            throw std::invalid_argument(std::string(path) + ": not a serialized " + Message::descriptor()->full_name());
    } else if (nb::isinstance<nb::str>(value)) {
        rt::parse_json_message(nb::borrow<nb::str>(value).c_str(), message, path);
        return message;
    } else {
        throw std::invalid_argument(std::string(path) + ": expected bytes (serialized " +
                                    Message::descriptor()->full_name() + ") or str (its JSON form)");
    }
    rt::apply_limits(message, path);
    return message;
}

template <class Message>
nb::bytes to_bytes(const Message& message) {
    const std::string data = message.SerializeAsString();
    return nb::bytes(data.data(), data.size());
}

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

struct RayBatch {
    std::vector<rt::Ray> rays;
};

RayBatch read_rays(const Points& origins, const Points& directions, const nb::handle& t_max) {
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
    RayBatch batch;
    batch.rays.resize(n);
    const float* o = origins.data();
    const float* d = directions.data();
    for (size_t i = 0; i < n; ++i) {
        rt::Ray& ray = batch.rays[i];
        ray.origin = {o[3 * i], o[3 * i + 1], o[3 * i + 2]};
        ray.direction = {d[3 * i], d[3 * i + 1], d[3 * i + 2]};
        ray.t_max = t ? t[i] : rt::kInfinity;
        if (!rt::is_finite(ray.origin) || !rt::is_finite(ray.direction) || ray.direction == rt::vec3(0.0f) ||
            std::isnan(ray.t_max))
            throw std::invalid_argument("ray " + std::to_string(i) +
                                        ": origin and direction must be finite and the direction non-zero");
    }
    return batch;
}

class PyScene {
  public:
    static PyScene* load(const std::string& path, unsigned threads) {
        nb::gil_scoped_release release;
        return new PyScene(rt::load_scene(path), threads);
    }

    static PyScene* from_bytes(const nb::bytes& data, const std::string& name, unsigned threads) {
        const auto* begin = reinterpret_cast<const std::byte*>(data.c_str());
        std::vector<std::byte> copy(begin, begin + data.size());
        nb::gil_scoped_release release;
        return new PyScene(rt::load_scene_from_memory(copy, name), threads);
    }

    size_t triangle_count() const { return scene_->triangles.size(); }
    size_t sphere_count() const { return scene_->spheres.size(); }
    size_t degenerate_triangles() const { return scene_->degenerate_triangles; }
    const std::vector<std::string>& warnings() const { return scene_->warnings; }

    std::pair<std::vector<float>, std::vector<float>> bounds() const {
        const rt::Bounds3 b = scene_->bounds();
        return {{b.min.x, b.min.y, b.min.z}, {b.max.x, b.max.y, b.max.z}};
    }

    std::vector<std::pair<std::string, nb::bytes>> cameras() const {
        std::vector<std::pair<std::string, nb::bytes>> out;
        for (const auto& c : scene_->cameras) out.emplace_back(c.name, to_bytes(c.camera));
        return out;
    }

    nb::bytes default_camera() const { return to_bytes(rt::default_camera(*scene_)); }

    nb::list lights() const {
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

    nb::dict bvh_stats() const {
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

    nb::ndarray<nb::numpy, float> render_tile(nb::handle camera, nb::handle settings, uint32_t x, uint32_t y,
                                              uint32_t width, uint32_t height) const {
        const rt::Renderer renderer(*accel_, read_message<rt::RenderSettings>(settings, "settings"),
                                    read_message<rt::Camera>(camera, "camera"));
        std::vector<float> rgb(size_t(width) * height * 3);
        {
            nb::gil_scoped_release release;
            renderer.render_tile({x, y, width, height}, rgb.data());
        }
        return to_numpy(std::move(rgb), {height, width, 3});
    }

    nb::ndarray<nb::numpy, float> render(nb::handle camera, nb::handle settings, unsigned threads,
                                         uint32_t tile_size) const {
        const rt::Renderer renderer(*accel_, read_message<rt::RenderSettings>(settings, "settings"),
                                    read_message<rt::Camera>(camera, "camera"));
        rt::Image image;
        {
            nb::gil_scoped_release release;
            rt::RayCounts counts;
            image = renderer.render(threads, tile_size, nullptr, counts);
        }
        const size_t w = image.width, h = image.height;
        return to_numpy(std::move(image.rgb), {h, w, 3});
    }

    nb::tuple intersect(const Points& origins, const Points& directions, nb::handle t_max, unsigned threads) const {
        const RayBatch batch = read_rays(origins, directions, t_max);
        const size_t n = batch.rays.size();
        std::vector<float> t(n), u(n), v(n);
        std::vector<int64_t> primitive(n);
        {
            nb::gil_scoped_release release;
            parallel_for(n, threads, [&](size_t begin, size_t end) {
                for (size_t i = begin; i < end; ++i) {
                    rt::Hit hit;
                    accel_->intersect(batch.rays[i], hit);
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

    nb::ndarray<nb::numpy, bool> occluded(const Points& origins, const Points& directions, nb::handle t_max,
                                          unsigned threads) const {
        const RayBatch batch = read_rays(origins, directions, t_max);
        const size_t n = batch.rays.size();
        std::vector<uint8_t> blocked(n);
        {
            nb::gil_scoped_release release;
            parallel_for(n, threads, [&](size_t begin, size_t end) {
                for (size_t i = begin; i < end; ++i) blocked[i] = accel_->occluded(batch.rays[i]);
            });
        }
        auto* owned = new std::vector<uint8_t>(std::move(blocked));
        nb::capsule owner(owned, [](void* p) noexcept { delete static_cast<std::vector<uint8_t>*>(p); });
        return nb::ndarray<nb::numpy, bool>(owned->data(), {n}, owner);
    }

    nb::bytes debug_path(nb::handle camera, nb::handle settings, uint32_t x, uint32_t y) const {
        const rt::Renderer renderer(*accel_, read_message<rt::RenderSettings>(settings, "settings"),
                                    read_message<rt::Camera>(camera, "camera"));
        rt::DebugPath path;
        {
            nb::gil_scoped_release release;
            path = renderer.debug_pixel(x, y);
        }
        return to_bytes(path);
    }

    nb::bytes bvh_boxes(int level) const {
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

  private:
    PyScene(rt::Scene scene, unsigned threads)
        : scene_(std::make_unique<rt::Scene>(std::move(scene))),
          accel_(std::make_unique<rt::Accelerator>(*scene_, threads)) {}

    std::unique_ptr<rt::Scene> scene_;
    std::unique_ptr<rt::Accelerator> accel_;
};

// The JSON form of any rt message, checked against the schema's limits with its
// defaults filled in, returned serialized. The server validates request bodies
// here so that C++ and Python refuse exactly the same values.
nb::bytes parse_message(const std::string& type_name, const std::string& json, const std::string& path) {
    // Naming the messages links their generated code, which registers them.
    static const google::protobuf::Descriptor* const linked[] = {
        rt::JobRequest::descriptor(), rt::DebugRayRequest::descriptor(), rt::SceneExtras::descriptor()};
    (void)linked;
    const auto* descriptor = google::protobuf::DescriptorPool::generated_pool()->FindMessageTypeByName(type_name);
    if (!descriptor) throw std::invalid_argument("unknown message type " + type_name);
    std::unique_ptr<google::protobuf::Message> message(
        google::protobuf::MessageFactory::generated_factory()->GetPrototype(descriptor)->New());
    rt::parse_json_message(json, *message, path);
    const std::string data = message->SerializeAsString();
    return nb::bytes(data.data(), data.size());
}

}  // namespace

NB_MODULE(rtcore, m) {
    m.doc() = "The rt ray tracer: scene loading, tile rendering, ray queries and debugger exports.";
    nb::register_exception_translator([](const std::exception_ptr& p, void*) {
        try {
            std::rethrow_exception(p);
        } catch (const rt::SceneError& e) {
            PyErr_SetString(PyExc_ValueError, e.what());
        }
    });

    m.def("parse_message", &parse_message, "type_name"_a, "json"_a, "path"_a = "body",
          "Parses the JSON form of an rt message (e.g. 'rt.JobRequest'), fills the schema's defaults and "
          "checks its limits: the serialized message, or ValueError naming the field.");

    nb::class_<PyScene>(m, "Scene")
        .def_static("load", &PyScene::load, "path"_a, "threads"_a = 0,
                    "Loads a .gltf, .glb or .obj file (and its .rt.json sidecar) and builds its BVH.")
        .def_static("from_bytes", &PyScene::from_bytes, "data"_a, "name"_a, "threads"_a = 0,
                    "Loads a scene held in memory; `name`'s extension gives the format.")
        .def_prop_ro("triangle_count", &PyScene::triangle_count)
        .def_prop_ro("sphere_count", &PyScene::sphere_count)
        .def_prop_ro("degenerate_triangles", &PyScene::degenerate_triangles)
        .def_prop_ro("warnings", &PyScene::warnings)
        .def_prop_ro("bounds", &PyScene::bounds, "(min, max) corners of the scene's bounding box.")
        .def_prop_ro("cameras", &PyScene::cameras, "[(name, serialized rt.Camera)]")
        .def_prop_ro("default_camera", &PyScene::default_camera, "Serialized rt.Camera used when none is given.")
        .def_prop_ro("lights", &PyScene::lights)
        .def_prop_ro("bvh_stats", &PyScene::bvh_stats)
        .def("render_tile", &PyScene::render_tile, "camera"_a, "settings"_a, "x"_a, "y"_a, "width"_a, "height"_a,
             "Renders one tile on the calling thread (GIL released): float32 array (height, width, 3), linear RGB.")
        .def("render", &PyScene::render, "camera"_a, "settings"_a, "threads"_a = 0, "tile_size"_a = 32,
             "Renders the whole image on `threads` threads: float32 array (height, width, 3), linear RGB.")
        .def("intersect", &PyScene::intersect, "origins"_a, "directions"_a, "t_max"_a = nb::none(),
             "threads"_a = 0, "Closest hits of a batch of rays: (t, primitive, u, v); primitive -1 on a miss.")
        .def("occluded", &PyScene::occluded, "origins"_a, "directions"_a, "t_max"_a = nb::none(), "threads"_a = 0,
             "Whether anything lies on each ray before t_max.")
        .def("debug_path", &PyScene::debug_path, "camera"_a, "settings"_a, "x"_a, "y"_a,
             "Every ray traced for pixel (x, y): serialized rt.DebugPath.")
        .def("bvh_boxes", &PyScene::bvh_boxes, "level"_a,
             "Boxes of one BVH level (0 = root), or of all leaves for level < 0: serialized rt.BvhBoxes.");
}
