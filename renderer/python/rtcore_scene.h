// rtcore.Scene: a loaded scene with its BVH. Loading, properties, ray queries
// and exports are in rtcore_scene.cpp; rendering in rtcore_render.cpp; the
// Python names and docstrings in rtcore.cpp. Heavy calls release the GIL.
#pragma once

#include <cstdint>
#include <memory>
#include <stop_token>
#include <string>
#include <utility>
#include <vector>

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include "geometry/accel.h"
#include "geometry/scene.h"
#include "integrator/render.h"

namespace rtcore {

namespace nb = nanobind;

using Points = nb::ndarray<const float, nb::shape<-1, 3>, nb::c_contig, nb::device::cpu>;

class PyScene {
  public:
    static PyScene* load(const std::string& path, unsigned threads);
    static PyScene* from_bytes(const nb::bytes& data, const std::string& name, unsigned threads);

    // Serialized rt.SceneInfo with what the scene itself tells: counts, bounds,
    // lights, cameras, warnings.
    nb::bytes info() const;
    // That rays meet: each instance of a shared mesh counts (bvh_stats() has those stored).
    size_t triangle_count() const { return scene_->placed_triangles(); }
    size_t texture_bytes() const;
    // The scene and its BVHs as stored: each shared mesh once, whatever its instances.
    size_t memory_bytes() const;
    nb::bytes default_camera() const;
    nb::dict bvh_stats() const;

    // The scene as GLB bytes (glb_export.h).
    nb::bytes to_glb() const;

    // A render request of type `type_name` (a message with `camera` and
    // `settings` fields) filled in for this scene and checked once: the one way
    // a job or debugger request enters. Throws std::invalid_argument naming the
    // field.
    nb::bytes complete(const std::string& type_name, nb::handle data) const;

    // The colour array, or with `aux` (a list of names or rt.AuxOutput values)
    // a dict of the colour, the layers asked for and the rays traced.
    // `known` (with `known_stride`): the layers a preview computed for this
    // tile's pixels on its grid, which are then not traced again.
    // Once `stop` (if any) is requested, throws rt::RenderStopped.
    nb::object render_tile(nb::handle camera, nb::handle settings, uint32_t x, uint32_t y, uint32_t width,
                           uint32_t height, nb::handle aux, uint32_t scale, nb::handle known,
                           uint32_t known_stride, const std::stop_source* stop) const;
    nb::ndarray<nb::numpy, float> render(nb::handle camera, nb::handle settings, unsigned threads,
                                         uint32_t tile_size) const;
    nb::bytes debug_path(nb::handle camera, nb::handle settings, uint32_t x, uint32_t y) const;

    nb::tuple intersect(const Points& origins, const Points& directions, nb::handle t_max, unsigned threads) const;
    nb::ndarray<nb::numpy, bool> occluded(const Points& origins, const Points& directions, nb::handle t_max,
                                          unsigned threads) const;
    nb::bytes bvh_boxes(int level, const std::string& tree) const;

  private:
    // A renderer for a camera and settings given as render_tile takes them.
    rt::Renderer renderer(nb::handle camera, nb::handle settings) const;

    PyScene(rt::Scene scene, unsigned threads)
        : scene_(std::make_unique<rt::Scene>(std::move(scene))),
          accel_(std::make_unique<rt::Accelerator>(*scene_, threads)) {}

    std::unique_ptr<rt::Scene> scene_;
    std::unique_ptr<rt::Accelerator> accel_;
};

}  // namespace rtcore
