#include "image/image.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include <OpenImageIO/imageio.h>

namespace rt {

void write_image(const std::filesystem::path& file, const Image& image, const AuxImage* aux,
                 const DisplayTransform& display, const Image* noisy) {
    std::string extension = file.extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(), ::tolower);
    const bool png = extension == ".png";
    if (!png && extension != ".exr")
        throw std::runtime_error(file.string() + ": unsupported image format '" + extension +
                                 "' (use .png or .exr)");
    const std::vector<AuxOutput> layers = aux ? aux->outputs() : std::vector<AuxOutput>{};
    if (png && (!layers.empty() || noisy))
        throw std::invalid_argument(file.string() + ": a PNG holds colour only; write auxiliary outputs to an .exr");
    if (noisy && (noisy->width != image.width || noisy->height != image.height))
        throw std::invalid_argument(file.string() + ": the noisy image is not the image's size");
    if (aux && (aux->width != image.width || aux->height != image.height))
        throw std::invalid_argument(file.string() + ": the auxiliary outputs are not the image's size");

    auto out = OIIO::ImageOutput::create(file.string());
    if (!out) throw std::runtime_error(file.string() + ": " + OIIO::geterror());
    std::vector<std::string> channels = {"R", "G", "B"};
    for (AuxOutput layer : layers)
        for (const std::string& name : aux_channel_names(layer)) channels.push_back(name);
    if (noisy) channels.insert(channels.end(), {"noisy.R", "noisy.G", "noisy.B"});
    OIIO::ImageSpec spec(int(image.width), int(image.height), int(channels.size()),
                         png ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT);
    spec.channelnames = channels;
    spec.attribute("oiio:ColorSpace", png ? "sRGB" : "linear");
    if (!out->open(file.string(), spec)) throw std::runtime_error(file.string() + ": " + out->geterror());

    bool written;
    if (png) {
        std::vector<uint8_t> bytes(image.rgb.size());
        encode_srgb8(image.rgb, display, bytes);
        written = out->write_image(OIIO::TypeDesc::UINT8, bytes.data());
    } else if (layers.empty() && !noisy) {
        written = out->write_image(OIIO::TypeDesc::FLOAT, image.rgb.data());
    } else {
        // Interleaved as the file stores them: each pixel's colour, then its layers.
        const size_t pixels = size_t(image.width) * image.height;
        std::vector<float> values;
        values.reserve(pixels * channels.size());
        std::vector<uint32_t> counts;
        for (AuxOutput layer : layers) counts.push_back(aux_channel_count(layer));
        for (size_t p = 0; p < pixels; ++p) {
            values.insert(values.end(), &image.rgb[3 * p], &image.rgb[3 * p] + 3);
            for (size_t k = 0; k < layers.size(); ++k)
                for (uint32_t c = 0; c < counts[k]; ++c) values.push_back(aux->channel(layers[k], p, c));
            if (noisy) values.insert(values.end(), &noisy->rgb[3 * p], &noisy->rgb[3 * p] + 3);
        }
        written = out->write_image(OIIO::TypeDesc::FLOAT, values.data());
    }
    if (!written || !out->close()) throw std::runtime_error(file.string() + ": " + out->geterror());
}

}  // namespace rt
