#include "image.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <OpenImageIO/imageio.h>

namespace rt {

float linear_to_srgb(float linear) {
    const float v = std::clamp(std::isnan(linear) ? 0.0f : linear, 0.0f, 1.0f);
    return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

void write_image(const std::filesystem::path& file, const Image& image) {
    std::string extension = file.extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(), ::tolower);
    const bool png = extension == ".png";
    if (!png && extension != ".exr")
        throw std::runtime_error(file.string() + ": unsupported image format '" + extension +
                                 "' (use .png or .exr)");

    auto out = OIIO::ImageOutput::create(file.string());
    if (!out) throw std::runtime_error(file.string() + ": " + OIIO::geterror());
    OIIO::ImageSpec spec(int(image.width), int(image.height), 3, png ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT);
    spec.attribute("oiio:ColorSpace", png ? "sRGB" : "linear");
    if (!out->open(file.string(), spec)) throw std::runtime_error(file.string() + ": " + out->geterror());

    bool written;
    if (png) {
        std::vector<uint8_t> bytes(image.rgb.size());
        std::transform(image.rgb.begin(), image.rgb.end(), bytes.begin(),
                       [](float v) { return uint8_t(std::lround(linear_to_srgb(v) * 255.0f)); });
        written = out->write_image(OIIO::TypeDesc::UINT8, bytes.data());
    } else {
        written = out->write_image(OIIO::TypeDesc::FLOAT, image.rgb.data());
    }
    if (!written || !out->close()) throw std::runtime_error(file.string() + ": " + out->geterror());
}

}  // namespace rt
