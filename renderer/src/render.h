// Rendering an image, or any tile of it, on all cores. A pixel's value depends
// only on its coordinates, never on the tiling or the thread that computed it.
#pragma once

#include <cstdint>
#include <functional>

#include "accel.h"
#include "camera.h"
#include "image.h"
#include "rt/debug.pb.h"
#include "rt/render.pb.h"
#include "whitted.h"

namespace rt {

struct TileRect {
    uint32_t x = 0;
    uint32_t y = 0;
    uint32_t width = 0;
    uint32_t height = 0;
};

// Called as tiles finish, with (tiles done, tiles total); never concurrently.
using ProgressCallback = std::function<void(size_t, size_t)>;

class Renderer {
  public:
    // Applies the schema's defaults and limits to copies of `settings` and
    // `camera`; throws std::invalid_argument naming a bad field.
    Renderer(const Accelerator& accel, RenderSettings settings, Camera camera);

    const RenderSettings& settings() const { return settings_; }

    // Renders `tile` into `rgb` (3 floats per pixel, tile rows top to bottom).
    // Throws std::invalid_argument when the tile is not inside the image.
    RayCounts render_tile(const TileRect& tile, float* rgb) const;

    // The whole image on `threads` threads (0: all cores) in square tiles.
    Image render(unsigned threads, uint32_t tile_size, const ProgressCallback& progress,
                 RayCounts& counts) const;

    // Every ray traced for one pixel. Throws std::invalid_argument outside the image.
    DebugPath debug_pixel(uint32_t x, uint32_t y) const;

  private:
    Ray camera_ray(uint32_t x, uint32_t y) const;
    static uint32_t pixel_key(uint32_t x, uint32_t y);

    RenderSettings settings_;
    Camera camera_;
    PinholeCamera pinhole_;
    WhittedIntegrator integrator_;
};

unsigned resolve_thread_count(unsigned requested);

}  // namespace rt
