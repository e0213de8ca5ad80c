#include "integrator/render.h"

#include <algorithm>
#include <array>
#include <bit>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include "util/proto_limits.h"
#include "integrator/sampling.h"

namespace rt {
namespace {

RenderSettings checked(RenderSettings settings) {
    apply_limits(settings, "settings");
    return settings;
}

Camera checked(Camera camera) {
    apply_limits(camera, "camera");
    return camera;
}

}  // namespace

Renderer::Renderer(const Accelerator& accel, RenderSettings settings, Camera camera)
    : settings_(checked(std::move(settings))),
      camera_(checked(std::move(camera))),
      view_(camera_, settings_.width(), settings_.height()),
      cone_(view_.ray_cone()),
      film_(settings_),
      stopping_(settings_.adaptive_threshold(), settings_.samples_per_pixel()),
      integrator_(accel, settings_) {
    if (view_.moving() || accel.scene().moving()) {
        sample_times_ = settings_.motion_blur() == TIME_SAMPLED;
        if (settings_.motion_blur() == FRAMES) motion_frames_ = settings_.motion_frames();
    }
    // Frames are rendered one after another, each pixel's samples per frame:
    // not the packets' loop.
    if (accel.packets_serve() && motion_frames_ == 0) packets_ = &accel;
}

uint32_t Renderer::pixel_key(uint32_t x, uint32_t y) { return hash_combine(mix_bits(x), y); }

template <class Trace>
vec3 Renderer::estimate_pixel(uint32_t x, uint32_t y, uint64_t& samples, Trace&& trace) const {
    if (motion_frames_ == 0) {
        // Time-sampled, or nothing moves and any one time gives the image.
        return estimate_frame(x, y, sample_times_ ? std::nullopt : std::optional(0.5f), samples, trace);
    }
    dvec3 sum(0.0);
    for (uint32_t f = 0; f < motion_frames_; ++f)
        sum += dvec3(estimate_frame(x, y, (float(f) + 0.5f) / float(motion_frames_), samples, trace));
    return vec3(sum / double(motion_frames_));
}

template <class Trace>
vec3 Renderer::estimate_frame(uint32_t x, uint32_t y, std::optional<float> time, uint64_t& samples,
                              Trace&& trace) const {
    const uint32_t key = pixel_key(x, y);
    const uint32_t count = settings_.samples_per_pixel();
    if (count == 1) {
        // A lone sample goes through the centre, whatever the filter, at the
        // middle of the shutter interval: the image of before samples_per_pixel
        // existed, with nothing to place or average.
        ++samples;
        return trace(view_.generate_ray(float(x) + 0.5f, float(y) + 0.5f, time.value_or(0.5f)),
                     PixelSampler(key, 0));
    }
    PixelEstimate estimate;
    for (uint32_t i = 0; i < count; ++i) {
        const PixelSampler sampler(key, i);
        const vec2 offset = film_.offset(sampler);
        const Ray ray = view_.generate_ray(float(x) + 0.5f + offset.x, float(y) + 0.5f + offset.y,
                                              time ? *time : sampler.time());
        estimate.add(trace(ray, sampler));
        if (stopping_.done(estimate)) break;
    }
    samples += estimate.count();
    return estimate.mean();
}

void Renderer::check_tile(const TileRect& tile, uint32_t scale) const {
    if (tile.width == 0 || tile.height == 0 || tile.x >= settings_.width() || tile.y >= settings_.height() ||
        tile.width > settings_.width() - tile.x || tile.height > settings_.height() - tile.y)
        throw std::invalid_argument("tile (" + std::to_string(tile.x) + ", " + std::to_string(tile.y) + ", " +
                                    std::to_string(tile.width) + "x" + std::to_string(tile.height) +
                                    ") is not inside the " + std::to_string(settings_.width()) + "x" +
                                    std::to_string(settings_.height()) + " image");
    if (scale == 0) throw std::invalid_argument("scale must be at least 1");
}

RenderStats Renderer::render_tile(const TileRect& tile, float* rgb, const AuxLayers& aux, uint32_t scale) const {
    check_tile(tile, scale);
    return render_pixels(tile, scale, rgb, aux, preview_extent(tile.width, scale));
}

RenderStats Renderer::render_tile(ThreadPool& pool, const TileRect& tile, float* rgb, const AuxLayers& aux,
                                  uint32_t scale, uint32_t known_stride, std::stop_token stop) const {
    check_tile(tile, scale);
    if (known_stride != 0 && scale != 1)
        throw std::invalid_argument("known pixels (stride " + std::to_string(known_stride) +
                                    ") are for full-resolution tiles, not a preview at scale " + std::to_string(scale));
    const uint32_t rows = preview_extent(tile.height, scale), columns = preview_extent(tile.width, scale);
    const uint32_t bands = (rows + kCacheBlock - 1) / kCacheBlock;
    std::vector<RenderStats> band_stats(bands);
    pool.parallel_for(bands, [&](size_t band) {
        const uint32_t first_row = uint32_t(band) * kCacheBlock;
        const TileRect rect{tile.x, tile.y + first_row * scale, tile.width,
                            std::min(tile.height - first_row * scale, kCacheBlock * scale)};
        const size_t first = size_t(first_row) * columns;
        band_stats[band] = render_pixels(rect, scale, rgb + first * 3, aux.from(first), columns, known_stride, stop);
    });
    RenderStats stats;
    for (const RenderStats& s : band_stats) stats += s;
    return stats;
}

RenderStats Renderer::render_pixels(const TileRect& tile, uint32_t scale, float* rgb, const AuxLayers& aux,
                                    size_t row_pixels, uint32_t known_stride, const std::stop_token& stop) const {
    RenderStats stats;
    const uint32_t rows = preview_extent(tile.height, scale), columns = preview_extent(tile.width, scale);
    // Neighbouring rays visit mostly the same BVH nodes; walking a large tile
    // in small blocks keeps those nodes in cache (a 256-pixel tile row by row
    // was 8% slower on the dragon than 32-pixel tiles).
    for (uint32_t block_y = 0; block_y < rows; block_y += kCacheBlock) {
        for (uint32_t block_x = 0; block_x < columns; block_x += kCacheBlock) {
            if (packets_ && !aux.bvh_cost) {
                // 4 x 4 pixels at a time, their camera rays one packet per sample.
                for (uint32_t j0 = block_y; j0 < std::min(rows, block_y + kCacheBlock); j0 += 4)
                    for (uint32_t i0 = block_x; i0 < std::min(columns, block_x + kCacheBlock); i0 += 4) {
                        PacketPixels block;
                        for (uint32_t j = j0; j < std::min(rows, j0 + 4); ++j)
                            for (uint32_t i = i0; i < std::min(columns, i0 + 4); ++i) {
                                const uint32_t x = tile.x + i * scale, y = tile.y + j * scale;
                                if (known_stride != 0 && y % known_stride == 0 && x % known_stride == 0) continue;
                                block.add(x, y, j * row_pixels + i);
                            }
                        render_packet(block, rgb, aux, stats, stop);
                    }
                continue;
            }
            for (uint32_t j = block_y; j < std::min(rows, block_y + kCacheBlock); ++j) {
                const uint32_t y = tile.y + j * scale;
                const bool known_row = known_stride != 0 && y % known_stride == 0;
                for (uint32_t i = block_x; i < std::min(columns, block_x + kCacheBlock); ++i) {
                    const uint32_t x = tile.x + i * scale;
                    if (known_row && x % known_stride == 0) continue;
                    // Per pixel: one pixel at many samples can take a second.
                    if (stop.stop_requested()) throw RenderStopped();
                    const size_t index = j * row_pixels + i;
                    const vec3 c = render_pixel(x, y, index, aux, stats);
                    float* out = rgb + index * 3;
                    out[0] = c.r;
                    out[1] = c.g;
                    out[2] = c.b;
                }
            }
        }
    }
    return stats;
}

void Renderer::render_packet(const PacketPixels& block, float* rgb, const AuxLayers& aux, RenderStats& stats,
                             const std::stop_token& stop) const {
    const uint32_t count = settings_.samples_per_pixel();
    // When time is sampled, a pixel's samples are spread over the shutter
    // (its time dimension is stratified) but neighbours' first samples are
    // not: one sample of each pixel would make a packet whose rays span the
    // whole shutter, and whose node tests take boxes swept over all of it.
    // Instead a group of samples is traced at once, its rays sorted by time
    // into packets: with 4 samples, each packet spans about a quarter of the
    // shutter. A group is a batch of StoppingRule's, so no pixel stops within
    // one: each still takes the samples render_pixel takes.
    const uint32_t group_size = sample_times_ ? StoppingRule::kBatch : 1;
    // A lone sample's mean is the sample itself, bit for bit, as
    // estimate_frame returns it.
    std::array<PixelEstimate, Accelerator::kPacketSize> estimates;
    std::array<AuxPixel, Accelerator::kPacketSize> aux_pixels;
    const bool with_aux = !aux.empty();
    uint32_t sampling = (1u << block.count) - 1;  // the pixels still taking samples
    constexpr uint32_t kPacket = Accelerator::kPacketSize, kMaxRays = kPacket * StoppingRule::kBatch;
    // Uninitialised: every ray traced is made first, every hit found first.
    union Rays { Ray at[kMaxRays]; Rays() {} } rays;
    union Hits { Hit at[kMaxRays]; Hits() {} } hits;
    for (uint32_t first = 0; first < count && sampling != 0; first += group_size) {
        if (stop.stop_requested()) throw RenderStopped();
        const uint32_t group = std::min(group_size, count - first);
        // Sample first + s of each pixel k still sampling, at its sample's
        // time when time is sampled (a lone sample at the middle of the
        // shutter interval), put in order of its stratum of the shutter, one
        // of `group` (a counting sort): the group's samples of a pixel take
        // one each. slot[s * kPacket + k] is where its ray goes.
        std::array<float, kMaxRays> time;
        std::array<uint8_t, kMaxRays> stratum;
        std::array<uint16_t, kMaxRays> slot;
        std::array<uint32_t, StoppingRule::kBatch + 1> starts{};
        for (uint32_t s = 0; s < group; ++s)
            for (uint32_t left = sampling; left != 0; left &= left - 1) {
                const uint32_t r = s * kPacket + uint32_t(std::countr_zero(left));
                const PixelSampler sampler(block.key[r % kPacket], count == 1 ? 0 : first + s);
                time[r] = count == 1 || !sample_times_ ? 0.5f : sampler.time();
                stratum[r] = uint8_t(std::min(uint32_t(time[r] * float(group)), group - 1));
                ++starts[stratum[r] + 1];
            }
        for (uint32_t b = 1; b <= group; ++b) starts[b] += starts[b - 1];
        const uint32_t n = starts[group];
        for (uint32_t s = 0; s < group; ++s)
            for (uint32_t left = sampling; left != 0; left &= left - 1) {
                const uint32_t k = uint32_t(std::countr_zero(left)), r = s * kPacket + k;
                const PixelSampler sampler(block.key[k], count == 1 ? 0 : first + s);
                const vec2 offset = count == 1 ? vec2(0.0f) : film_.offset(sampler);
                slot[r] = uint16_t(starts[stratum[r]]++);
                rays.at[slot[r]] = view_.generate_ray(float(block.x[k]) + 0.5f + offset.x,
                                                      float(block.y[k]) + 0.5f + offset.y, time[r]);
            }
        for (uint32_t at = 0; at < n; at += kPacket) {
            const uint32_t size = std::min(n - at, kPacket);
            packets_->intersect(std::span(rays.at + at, size), std::span(hits.at + at, size));
        }
        for (uint32_t s = 0; s < group; ++s)
            for (uint32_t left = sampling; left != 0; left &= left - 1) {
                const uint32_t k = uint32_t(std::countr_zero(left)), r = slot[s * kPacket + k];
                const PixelSampler sampler(block.key[k], count == 1 ? 0 : first + s);
                estimates[k].add(shade(rays.at[r], hits.at[r], sampler, stats, with_aux ? &aux_pixels[k] : nullptr));
                if (stopping_.done(estimates[k])) sampling &= ~(1u << k);
            }
    }
    for (uint32_t k = 0; k < block.count; ++k) {
        const vec3 c = estimates[k].mean();
        stats.samples += estimates[k].count();
        if (with_aux) aux.store(block.index[k], aux_pixels[k].mean());
        float* out = rgb + block.index[k] * 3;
        out[0] = c.r;
        out[1] = c.g;
        out[2] = c.b;
    }
}

vec3 Renderer::shade(const Ray& ray, const Hit& hit, const PixelSampler& sampler, RenderStats& stats,
                     AuxPixel* aux) const {
    if (!aux) return integrator_.radiance(ray, hit, sampler, stats.rays, cone_);
    AuxSample sample;
    const vec3 c = integrator_.radiance(ray, sampler, stats.rays, sample, cone_, false, &hit);
    aux->add(sample);
    return c;
}

vec3 Renderer::render_pixel(uint32_t x, uint32_t y, size_t index, const AuxLayers& aux, RenderStats& stats) const {
    // One test per pixel keeps the colour-only path free of the outputs' work.
    if (aux.empty()) {
        return estimate_pixel(x, y, stats.samples, [&](const Ray& ray, const PixelSampler& sampler) {
            return integrator_.radiance(ray, sampler, stats.rays, cone_);
        });
    }
    AuxPixel pixel;
    const vec3 c = estimate_pixel(x, y, stats.samples, [&](const Ray& ray, const PixelSampler& sampler) {
        AuxSample sample;
        const vec3 radiance = integrator_.radiance(ray, sampler, stats.rays, sample, cone_, aux.bvh_cost != nullptr);
        pixel.add(sample);
        return radiance;
    });
    aux.store(index, pixel.mean());
    return c;
}

Image Renderer::render(unsigned threads, uint32_t tile_size, const ProgressCallback& progress, RenderStats& stats,
                       AuxImage* aux) const {
    if (tile_size == 0) throw std::invalid_argument("tile size must be at least 1");
    const uint32_t width = settings_.width(), height = settings_.height();
    if (aux && (aux->width != width || aux->height != height))
        throw std::invalid_argument("auxiliary outputs of " + std::to_string(aux->width) + "x" +
                                    std::to_string(aux->height) + " pixels for a " + std::to_string(width) + "x" +
                                    std::to_string(height) + " image");
    const AuxLayers layers = aux ? aux->layers() : AuxLayers{};
    Image image(width, height);
    std::vector<TileRect> tiles;
    for (uint32_t y = 0; y < height; y += tile_size)
        for (uint32_t x = 0; x < width; x += tile_size)
            tiles.push_back({x, y, std::min(tile_size, width - x), std::min(tile_size, height - y)});

    std::mutex mutex;  // guards stats, done and the progress callback
    size_t done = 0;
    parallel_for(threads, tiles.size(), [&](size_t index) {
        // Tiles write straight into the image: their pixels never overlap.
        const TileRect& tile = tiles[index];
        const size_t first = size_t(tile.y) * width + tile.x;
        const RenderStats tile_stats = render_pixels(tile, 1, &image.rgb[first * 3], layers.from(first), width);
        std::lock_guard lock(mutex);
        stats += tile_stats;
        ++done;
        if (progress) progress(done, tiles.size());
    });
    return image;
}

DebugPath Renderer::debug_pixel(uint32_t x, uint32_t y) const {
    if (x >= settings_.width() || y >= settings_.height())
        throw std::invalid_argument("pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                                    ") is outside the " + std::to_string(settings_.width()) + "x" +
                                    std::to_string(settings_.height()) + " image");
    DebugPath path;
    path.set_pixel_x(x);
    path.set_pixel_y(y);
    uint64_t samples = 0;
    const vec3 color = estimate_pixel(x, y, samples, [&](const Ray& ray, const PixelSampler& sampler) {
        return integrator_.radiance(ray, sampler, path, cone_);
    });
    path.clear_color();
    path.add_color(color.r);
    path.add_color(color.g);
    path.add_color(color.b);
    return path;
}

}  // namespace rt
