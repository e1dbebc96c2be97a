#include "image/image.h"

#include <OpenImageIO/imageio.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "input_error.h"

namespace vkpath::image {
namespace {

std::filesystem::path temporaryBeside(const std::filesystem::path& path) {
    // Keep the extension: OpenImageIO picks the format from it.
    auto temp = path;
    temp.replace_filename(fmt::format(".{}.partial{}", path.stem().string(), path.extension().string()));
    return temp;
}

void writeWithOiio(const std::filesystem::path& path, const OIIO::ImageSpec& spec, OIIO::TypeDesc type,
                   const void* data) {
    const auto temp = temporaryBeside(path);
    auto out = OIIO::ImageOutput::create(temp.string());
    if (!out) throw std::runtime_error(fmt::format("{}: cannot create an image writer", path.string()));
    bool ok = out->open(temp.string(), spec) && out->write_image(type, data) && out->close();
    if (!ok) {
        const std::string error = out->geterror();
        out.reset();
        std::filesystem::remove(temp);
        throw std::runtime_error(fmt::format("{}: cannot write: {}", path.string(), error));
    }
    out.reset();
    std::error_code ec;
    std::filesystem::rename(temp, path, ec);
    if (ec) {
        std::filesystem::remove(temp);
        throw std::runtime_error(fmt::format("{}: cannot write: {}", path.string(), ec.message()));
    }
}

}  // namespace

float linearToSrgb(float linear) {
    const float v = std::clamp(linear, 0.0f, 1.0f);
    return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

void writeExr(const std::filesystem::path& path, const Image& image, const Metadata& metadata) {
    OIIO::ImageSpec spec(static_cast<int>(image.width), static_cast<int>(image.height), 3, OIIO::TypeDesc::FLOAT);
    spec.channelnames = {"R", "G", "B"};
    spec.attribute("compression", "zip");
    for (const auto& [key, value] : metadata) spec.attribute(key, value);
    writeWithOiio(path, spec, OIIO::TypeDesc::FLOAT, image.pixels.data());
}

void writePng(const std::filesystem::path& path, const Image& image, float exposureStops) {
    const float scale = std::exp2(exposureStops);
    std::vector<uint8_t> bytes(image.pixels.size() * 3);
    for (size_t i = 0; i < image.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            const float v = image.pixels[i][c] * scale;
            // NaN maps to 0 (std::clamp inside linearToSrgb would keep it).
            const float encoded = std::isnan(v) ? 0.0f : linearToSrgb(v);
            bytes[3 * i + c] = static_cast<uint8_t>(std::lround(encoded * 255.0f));
        }
    OIIO::ImageSpec spec(static_cast<int>(image.width), static_cast<int>(image.height), 3, OIIO::TypeDesc::UINT8);
    writeWithOiio(path, spec, OIIO::TypeDesc::UINT8, bytes.data());
}

std::map<std::string, std::string> readVkpathMetadata(const std::filesystem::path& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
        throw InputError(fmt::format("{}: no such file", path.string()));
    auto in = OIIO::ImageInput::open(path.string());
    if (!in) throw InputError(fmt::format("{}: cannot read image: {}", path.string(), OIIO::geterror()));
    std::map<std::string, std::string> attributes;
    for (const OIIO::ParamValue& p : in->spec().extra_attribs) {
        const std::string name = p.name().string();
        if (name.rfind("vkpath:", 0) == 0) attributes[name] = p.get_string();
    }
    return attributes;
}

Image readImage(const std::filesystem::path& path, uint64_t maxPixels) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
        throw InputError(fmt::format("{}: no such file", path.string()));
    auto in = OIIO::ImageInput::open(path.string());
    if (!in) throw InputError(fmt::format("{}: cannot read image: {}", path.string(), OIIO::geterror()));
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0 || spec.depth != 1)
        throw InputError(fmt::format("{}: not a 2-D image", path.string()));
    if (uint64_t(spec.width) * uint64_t(spec.height) > maxPixels)
        throw InputError(fmt::format("{}: {}x{} pixels exceed the limit of {}", path.string(), spec.width,
                                     spec.height, maxPixels));
    // Only the channels used: the file may declare thousands, and maxPixels
    // bounds what is allocated only if a pixel's size is bounded too.
    const int channels = std::min(spec.nchannels, 3);
    std::vector<float> data(size_t(spec.width) * spec.height * channels);
    if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, data.data()))
        throw InputError(fmt::format("{}: cannot read image: {}", path.string(), in->geterror()));
    Image image(static_cast<uint32_t>(spec.width), static_cast<uint32_t>(spec.height));
    for (size_t i = 0; i < image.pixels.size(); ++i) {
        const float* p = &data[i * channels];
        image.pixels[i] = channels >= 3 ? glm::vec3(p[0], p[1], p[2]) : glm::vec3(p[0]);
    }
    return image;
}

}  // namespace vkpath::image
