// Rendering an image, or any tile of it, on all cores. A pixel's value depends
// only on its coordinates, never on the tiling or the thread that computed it:
// it is the mean of its own camera samples (film_sampler.h), as many as
// samples_per_pixel or, with adaptive sampling, as it needs.
//
// When the camera or the scene moves, the pixel averages over the shutter
// interval (rt.MotionBlur): each camera sample at its own time, stratified like
// its film position (a lone sample at the middle), or, as the 2020 report did, the
// mean of motion_frames whole frames at the centres of equal parts of the
// interval, each taking the full samples_per_pixel.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <stdexcept>
#include <stop_token>

#include "geometry/accel.h"
#include "image/aov.h"
#include "integrator/camera.h"
#include "integrator/film_sampler.h"
#include "image/image.h"
#include "integrator/pixel_estimate.h"
#include "rt/debug.pb.h"
#include "rt/render.pb.h"
#include "util/thread_pool.h"
#include "integrator/whitted.h"

namespace rt {

struct TileRect {
    uint32_t x = 0;
    uint32_t y = 0;
    uint32_t width = 0;
    uint32_t height = 0;
};

// What a render did: the rays it traced and the camera samples it took.
struct RenderStats {
    RayCounts rays;
    uint64_t samples = 0;

    RenderStats& operator+=(const RenderStats& o) {
        rays += o.rays;
        samples += o.samples;
        return *this;
    }
};

// Thrown by render_tile when its stop token asks it to stop: the tile's
// buffers then hold some pixels and not others, and must not be used.
struct RenderStopped : std::runtime_error {
    RenderStopped() : std::runtime_error("the render was asked to stop") {}
};

// Called as tiles finish, with (tiles done, tiles total); never concurrently.
using ProgressCallback = std::function<void(size_t, size_t)>;

class Renderer {
  public:
    // Applies the schema's defaults and limits to copies of `settings` and
    // `camera`; throws std::invalid_argument naming a bad field.
    Renderer(const Accelerator& accel, RenderSettings settings, Camera camera);

    // The settings and camera as checked, every default filled in.
    const RenderSettings& settings() const { return settings_; }
    const Camera& camera() const { return camera_; }

    // Throws std::invalid_argument when `tile` is not inside the image or
    // `scale` is 0: render_tile's checks, for callers sizing buffers first.
    void check_tile(const TileRect& tile, uint32_t scale = 1) const;

    // Renders `tile` into `rgb` (3 floats per pixel, rows top to bottom) and
    // into the auxiliary layers `aux` points to. With `scale` s > 1 it is a
    // preview: one pixel per s x s block, the block's top-left pixel computed
    // exactly as the full-resolution render computes it, ceil(width / s) by
    // ceil(height / s) pixels in all (preview_extent). Throws as check_tile does.
    RenderStats render_tile(const TileRect& tile, float* rgb, const AuxLayers& aux = {}, uint32_t scale = 1) const;

    // The same on every thread of `pool`, in bands of kCacheBlock rows taken
    // first come, first served with whatever else the pool is rendering.
    // With `known_stride` s > 0 (scale 1 only), pixels whose image x and y are
    // both multiples of s already hold their final values in `rgb` and `aux`
    // (a preview at scale s computed them exactly as this render would) and
    // are not traced again; the counts are those of the pixels traced.
    // Once `stop` is requested, no pixel starts and RenderStopped is thrown:
    // a cancelled job frees the cores within a pixel's time.
    RenderStats render_tile(ThreadPool& pool, const TileRect& tile, float* rgb, const AuxLayers& aux = {},
                            uint32_t scale = 1, uint32_t known_stride = 0, std::stop_token stop = {}) const;

    // The whole image on `threads` threads (0: all cores; rt::parallel_for, so
    // the render pool's when it has that many) in square tiles, and
    // the layers `aux` holds, when given (it must have the image's size).
    Image render(unsigned threads, uint32_t tile_size, const ProgressCallback& progress, RenderStats& stats,
                 AuxImage* aux = nullptr) const;

    // Every ray traced for one pixel: each camera sample's primary ray is a
    // root (parent -1), and `color` is the pixel's value. Throws
    // std::invalid_argument outside the image.
    DebugPath debug_pixel(uint32_t x, uint32_t y) const;

  private:
    // render_tile without the checks, writing output row j at pixel j * row_pixels.
    RenderStats render_pixels(const TileRect& tile, uint32_t scale, float* rgb, const AuxLayers& aux,
                              size_t row_pixels, uint32_t known_stride = 0, const std::stop_token& stop = {}) const;
    // Pixel (x, y), its outputs stored at `index` of `aux`.
    vec3 render_pixel(uint32_t x, uint32_t y, size_t index, const AuxLayers& aux, RenderStats& stats) const;
    // Up to 16 pixels near one another, and where each one's colour goes.
    struct PacketPixels {
        uint32_t count = 0;
        uint32_t x[Accelerator::kPacketSize], y[Accelerator::kPacketSize];
        uint32_t key[Accelerator::kPacketSize];  // pixel_key(x, y)
        size_t index[Accelerator::kPacketSize];
        void add(uint32_t px, uint32_t py, size_t at) {
            x[count] = px, y[count] = py, key[count] = pixel_key(px, py), index[count++] = at;
        }
    };
    // The colours of `block`'s pixels, each sample's camera rays traced as one
    // packet (Accelerator::intersect over a span), each pixel's samples taken
    // in their own order and stopped by their own rule: each pixel gets the
    // value render_pixel gives it, and the same auxiliary outputs. For a scene
    // the packet path serves, unless motion is rendered as frames (packets_),
    // and for every output but the BVH cost, which counts every ray's own
    // traversal.
    void render_packet(const PacketPixels& block, float* rgb, const AuxLayers& aux, RenderStats& stats,
                       const std::stop_token& stop) const;
    // The radiance of a camera sample whose hit a packet found; its auxiliary
    // outputs added to `aux` when given.
    vec3 shade(const Ray& ray, const Hit& hit, const PixelSampler& sampler, RenderStats& stats, AuxPixel* aux) const;
    // Pixels per side of the blocks a tile is walked in.
    static constexpr uint32_t kCacheBlock = 16;
    // The mean of pixel (x, y)'s samples, `trace(ray, sampler)` giving each
    // one's radiance; adds the number taken to `samples`.
    template <class Trace>
    vec3 estimate_pixel(uint32_t x, uint32_t y, uint64_t& samples, Trace&& trace) const;
    // The same for one frame: every sample at `time`, or each at its own.
    template <class Trace>
    vec3 estimate_frame(uint32_t x, uint32_t y, std::optional<float> time, uint64_t& samples, Trace&& trace) const;
    static uint32_t pixel_key(uint32_t x, uint32_t y);

    RenderSettings settings_;
    Camera camera_;
    ViewCamera view_;
    RayCone cone_;  // every camera ray's footprint, for texture filtering (ray_cone.h)
    FilmSampler film_;
    StoppingRule stopping_;
    WhittedIntegrator integrator_;
    // Something moves and settings say how: each sample takes its own time
    // (TIME_SAMPLED), or motion_frames_ > 0 frames are averaged (FRAMES).
    bool sample_times_ = false;
    uint32_t motion_frames_ = 0;
    // Set when the scene takes packet queries (a moving one too, each ray at
    // its sample's time) and motion is not rendered as frames: the colour
    // pixels' camera rays then go in packets.
    const Accelerator* packets_ = nullptr;
};

// Pixels a preview at `scale` has along an edge of `extent` >= 1 pixels: ceil(extent / scale).
inline uint32_t preview_extent(uint32_t extent, uint32_t scale) { return 1 + (extent - 1) / scale; }

}  // namespace rt
