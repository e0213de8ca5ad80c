// rtcore: the renderer as a Python module. Heavy calls release the GIL, so a
// Dask worker's threads render tiles in parallel. Camera and settings arrive as
// rt.Camera / rt.RenderSettings, serialized (bytes) or in their JSON form (str);
// debug paths and BVH boxes leave as serialized rt.DebugPath / rt.BvhBoxes.
//
// This file names things for Python; rtcore_scene.h is the Scene class behind them.
#include <memory>
#include <stdexcept>
#include <stop_token>
#include <string>

#include <nanobind/nanobind.h>
#include <nanobind/stl/pair.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/tuple.h>
#include <nanobind/stl/vector.h>

#include "image/aov.h"
#include "load/loader.h"
#include "util/proto_limits.h"
#include "integrator/render.h"
#include "rt/job.pb.h"
#include "rtcore_convert.h"
#include "rtcore_image.h"
#include "rtcore_scene.h"
#include "util/thread_pool.h"

namespace nb = nanobind;
using namespace nb::literals;
using rtcore::PyScene;

namespace {

// The JSON form of any rt message, returned serialized: with `limits`, checked
// against the schema's limits with its defaults filled in, so that C++ and
// Python refuse exactly the same values; without, only read (field names and
// types), for a render request that its scene then completes (Scene.complete).
nb::bytes parse_message(const std::string& type_name, const std::string& json, const std::string& path,
                        bool limits) {
    const auto message = rtcore::new_message(type_name);
    if (limits)
        rt::parse_json_message(json, *message, path);
    else
        rt::read_json_message(json, *message, path);
    return rtcore::to_bytes(*message);
}

}  // namespace

std::unique_ptr<google::protobuf::Message> rtcore::new_message(const std::string& type_name) {
    // Naming the messages links their generated code, which registers them.
    static const google::protobuf::Descriptor* const linked[] = {
        rt::JobRequest::descriptor(), rt::DebugRayRequest::descriptor(), rt::SceneExtras::descriptor()};
    (void)linked;
    const auto* descriptor = google::protobuf::DescriptorPool::generated_pool()->FindMessageTypeByName(type_name);
    if (!descriptor) throw std::invalid_argument("unknown message type " + type_name);
    return std::unique_ptr<google::protobuf::Message>(
        google::protobuf::MessageFactory::generated_factory()->GetPrototype(descriptor)->New());
}

NB_MODULE(rtcore, m) {
    m.doc() = "The rt ray tracer: scene loading, tile rendering, ray queries and debugger exports.";
    nb::register_exception_translator([](const std::exception_ptr& p, void*) {
        try {
            std::rethrow_exception(p);
        } catch (const rt::SceneError& e) {
            PyErr_SetString(PyExc_ValueError, e.what());
        }
    });

    nb::exception<rt::RenderStopped>(m, "RenderStopped", PyExc_RuntimeError);
    nb::class_<std::stop_source>(m, "StopSource",
                                 "Asks renders to stop: Scene.render_tile(..., stop=source) raises RenderStopped "
                                 "once request_stop() is called, from any thread, starting no further pixel.")
        .def(nb::init<>())
        .def("request_stop", &std::stop_source::request_stop, "True for the call that made the request.")
        .def_prop_ro("stop_requested", &std::stop_source::stop_requested);

    m.def("parse_message", &parse_message, "type_name"_a, "json"_a, "path"_a = "body", nb::kw_only(),
          "limits"_a = true,
          "Parses the JSON form of an rt message (e.g. 'rt.JobRequest'), fills the schema's defaults and "
          "checks its limits: the serialized message, or ValueError naming the field. limits=False only "
          "reads it (field names and types), for Scene.complete to finish.");
    m.def("aux_channel_count", [](const std::string& name) { return rt::aux_channel_count(rt::parse_aux_output(name)); },
          "name"_a, "Values per pixel of an auxiliary layer ('depth': 1, 'normal': 3, ...), as render_tile returns it.");
    m.def("aux_channel_names", [](const std::string& name) { return rt::aux_channel_names(rt::parse_aux_output(name)); },
          "name"_a, "The channels of an auxiliary layer as the EXR names them ('depth': ['depth.Z'], ...).");
    rtcore::bind_images(m);
    m.def("set_render_threads", &rt::set_render_threads, "threads"_a,
          "Sizes the pool of threads Scene.render_tile renders on (0: all cores); renders already running "
          "finish on the old pool.");
    m.def("render_threads", [] { return rt::render_pool()->size(); },
          "The number of threads Scene.render_tile renders on.");

    nb::class_<PyScene>(m, "Scene")
        .def_static("load", &PyScene::load, "path"_a, "threads"_a = 0,
                    "Loads a .gltf, .glb or .obj file (and its .rt.json sidecar) and builds its BVH.")
        .def_static("from_bytes", &PyScene::from_bytes, "data"_a, "name"_a, "threads"_a = 0,
                    "Loads a scene held in memory; `name`'s extension gives the format.")
        .def_prop_ro("info", &PyScene::info,
                     "What the renderer knows of the scene, as a serialized rt.SceneInfo: triangle and sphere "
                     "counts, degenerate triangles dropped, bounds, lights, named cameras, the default camera "
                     "and the loader's warnings (the service fills in the rest).")
        .def_prop_ro("triangle_count", &PyScene::triangle_count,
                     "The triangles rays meet: each instance of a shared mesh counts its own.")
        .def_prop_ro("memory_bytes", &PyScene::memory_bytes,
                     "What the loaded scene and its BVHs take in memory, as stored: a mesh that nodes share counts once.")
        .def_prop_ro("texture_bytes", &PyScene::texture_bytes,
                     "What the scene's textures take in memory: 8-bit texels with their mip levels.")
        .def_prop_ro("default_camera", &PyScene::default_camera, "Serialized rt.Camera used when none is given.")
        .def_prop_ro("bvh_stats", &PyScene::bvh_stats)
        .def("to_glb", &PyScene::to_glb,
             "The scene as the renderer sees it, as binary glTF 2.0 (GLB) bytes, for the viewer (GIL released).")
        .def("complete", &PyScene::complete, "type_name"_a, "data"_a,
             "A render request (an rt message with camera and settings, e.g. 'rt.JobRequest'; serialized or "
             "JSON, as parse_message(..., limits=False) reads it) completed and checked once for this scene: an "
             "absent camera is the scene's default view, absent settings the schema's defaults, every field within "
             "its limits and the camera and settings as the renderer takes them. The serialized message, or "
             "ValueError naming the field.")
        .def("render_tile", &PyScene::render_tile, "camera"_a, "settings"_a, "x"_a, "y"_a, "width"_a, "height"_a,
             nb::kw_only(), "aux"_a = nb::none(), "scale"_a = 1, "known"_a = nb::none(), "known_stride"_a = 0,
             "stop"_a = nb::none(),
             "Renders one tile on the render pool's threads (set_render_threads), the GIL released: float32 array "
             "(height, width, 3), linear RGB. Tiles rendered at once from several threads share the pool, the "
             "oldest first.\n\n"
             "scale=s > 1 renders a preview: each s x s block's top-left pixel, exactly as the full render "
             "computes it, so the arrays are ceil(height/s) x ceil(width/s).\n"
             "aux=[...] (names 'depth', 'normal', 'albedo', 'bvh_cost' or rt.AuxOutput values) returns a dict "
             "instead: 'color', each layer asked for ('depth' (h, w) float32, 0 on a miss; 'normal' and "
             "'albedo' (h, w, 3) float32, zeros on a miss; 'bvh_cost' (h, w, 2) uint32: BVH nodes visited and "
             "triangles tested over all the pixel's rays), 'rays', the rays traced, and 'samples', the camera samples "
             "taken (samples_per_pixel per pixel, fewer where adaptive sampling stopped early).\n"
             "known={'color': ..., <each aux layer>: ...} with known_stride=s: a preview at scale s of this tile "
             "(the tile starting on its grid) already computed the pixels whose x and y are multiples of s; they are "
             "placed, not traced again, and the counts cover the pixels traced.\n"
             "stop=StopSource: once its stop is requested, no further pixel starts and RenderStopped is raised.")
        .def("render", &PyScene::render, "camera"_a, "settings"_a, "threads"_a = 0, "tile_size"_a = 32,
             "Renders the whole image on `threads` threads: float32 array (height, width, 3), linear RGB, "
             "denoised when the settings ask (as rtrender; bloom is apply_bloom's).")
        .def("intersect", &PyScene::intersect, "origins"_a, "directions"_a, "t_max"_a = nb::none(),
             "threads"_a = 0, "Closest hits of a batch of rays: (t, primitive, u, v); primitive -1 on a miss.")
        .def("occluded", &PyScene::occluded, "origins"_a, "directions"_a, "t_max"_a = nb::none(), "threads"_a = 0,
             "Whether anything lies on each ray before t_max.")
        .def("debug_path", &PyScene::debug_path, "camera"_a, "settings"_a, "x"_a, "y"_a,
             "Every ray traced for pixel (x, y): serialized rt.DebugPath.")
        .def("bvh_boxes", &PyScene::bvh_boxes, "level"_a, "tree"_a = "top",
             "Boxes of one BVH level (0 = root), or of all leaves for level < 0, of the tree named by `tree`: "
             "'top' (the top level, or the scene's only tree), 'world' (the triangles placed once beside "
             "instances) or an instance number. Serialized rt.BvhBoxes; ValueError for a tree the scene lacks.");
}
