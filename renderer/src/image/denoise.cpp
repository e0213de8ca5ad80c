#include "image/denoise.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <type_traits>
#include <vector>

#include "image/oidn_library.h"

namespace rt {
namespace {

// OIDN's devices are costly to make (its thread arena, its kernels' set-up),
// so one per thread cap is kept for the process. Filters run one at a time:
// each takes every thread its device has.
class Devices {
  public:
    // Runs f(api, device) under the lock.
    template <class F>
    void with(unsigned threads, F&& f) {
        std::lock_guard lock(mutex_);
        const oidn::Api& api = oidn::api();
        auto& device = devices_[threads];
        if (!device) {
            oidn::Device d = api.new_device(oidn::kDeviceCpu);
            if (!d) throw std::runtime_error("Open Image Denoise made no CPU device (is this CPU supported?)");
            device.reset(d);
            // Our render pool's threads are not pinned either; OIDN's pinning
            // would fight them when both run in one process.
            api.set_device_bool(d, "setAffinity", false);
            if (threads > 0) api.set_device_int(d, "numThreads", int(threads));
            api.commit_device(d);
            check(api, d, "making its device");
        }
        f(api, device.get());
    }

    static void check(const oidn::Api& api, oidn::Device device, const char* doing) {
        const char* message = nullptr;
        if (api.get_device_error(device, &message) != oidn::kErrorNone)
            throw std::runtime_error(std::string("Open Image Denoise failed ") + doing + ": " +
                                     (message ? message : "no message"));
    }

  private:
    struct Release {
        void operator()(oidn::Device d) const { oidn::api().release_device(d); }
    };
    std::mutex mutex_;
    std::map<unsigned, std::unique_ptr<std::remove_pointer_t<oidn::Device>, Release>> devices_;
};

Devices& devices() {
    static Devices* shared = new Devices;  // never destroyed: OIDN's threads may outlive static destructors
    return *shared;
}

}  // namespace

std::vector<AuxOutput> denoise_guides(const RenderSettings& settings) {
    if (settings.denoise() == OIDN) return {NORMAL, ALBEDO};
    return {};
}

void denoise_oidn(uint32_t width, uint32_t height, const float* color, const float* albedo, const float* normal,
                  float* out, unsigned threads) {
    const size_t values = size_t(width) * height * 3;
    // What the network reads: black for pixels that are not finite, albedo in
    // [0, 1] as it was trained on, normals as given (zero where nothing was hit).
    std::vector<float> input(color, color + values), albedo_in(albedo, albedo + values);
    std::vector<bool> kept(values / 3, false);
    for (size_t p = 0; p < values / 3; ++p) {
        float* c = &input[p * 3];
        if (!std::isfinite(c[0]) || !std::isfinite(c[1]) || !std::isfinite(c[2])) {
            kept[p] = true;
            c[0] = c[1] = c[2] = 0.0f;
        }
    }
    for (float& a : albedo_in) a = std::isfinite(a) ? std::clamp(a, 0.0f, 1.0f) : 0.0f;
    std::vector<float> normal_in(normal, normal + values);
    for (float& n : normal_in) n = std::isfinite(n) ? std::clamp(n, -1.0f, 1.0f) : 0.0f;
    std::vector<float> result(values);

    devices().with(threads, [&](const oidn::Api& api, oidn::Device device) {
        oidn::Filter filter = api.new_filter(device, "RT");
        Devices::check(api, device, "making its RT filter");
        const auto image = [&](const char* name, float* data) {
            api.set_shared_filter_image(filter, name, data, oidn::kFormatFloat3, width, height, 0, 0, 0);
        };
        image("color", input.data());
        image("albedo", albedo_in.data());
        image("normal", normal_in.data());
        image("output", result.data());
        api.set_filter_bool(filter, "hdr", true);
        api.commit_filter(filter);
        api.execute_filter(filter);
        api.release_filter(filter);
        Devices::check(api, device, "denoising");
    });
    for (size_t p = 0; p < values / 3; ++p)
        for (int k = 0; k < 3; ++k) out[p * 3 + k] = kept[p] ? color[p * 3 + k] : result[p * 3 + k];
}

void apply_denoise(Image& image, const AuxImage& guides, const RenderSettings& settings, unsigned threads) {
    if (settings.denoise() != OIDN) return;
    if (!guides.has(ALBEDO) || !guides.has(NORMAL) || guides.width != image.width || guides.height != image.height)
        throw std::invalid_argument("denoising needs the albedo and normal layers of the image's size");
    denoise_oidn(image.width, image.height, image.rgb.data(), guides.albedo.data(), guides.normal.data(),
                 image.rgb.data(), threads);
}

}  // namespace rt
