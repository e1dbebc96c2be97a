#include "image/image.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <map>

#include "input_error.h"

namespace vkpath::image {
namespace {

std::filesystem::path temporaryBeside(const std::filesystem::path& path) {
    // Keep the extension: OpenImageIO picks the format from it.
    auto temp = path;
    temp.replace_filename(
        fmt::format(".{}.partial{}", path.stem().string(), path.extension().string()));
    return temp;
}

void writeWithOiio(const std::filesystem::path& path, const OIIO::ImageSpec& spec,
                   OIIO::TypeDesc type, const void* data) {
    const auto temp = temporaryBeside(path);
    auto out = OIIO::ImageOutput::create(temp.string());
    if (!out)
        throw std::runtime_error(fmt::format("{}: cannot create an image writer", path.string()));
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

// OpenEXR 3.1 sizes some attribute buffers from what the header claims
// before reading them (a string's declared size, each string of a
// stringvector, a preview's width x height), and reads fixed-size types by
// their type whatever size is declared, so a damaged 1 KiB file can ask for
// gigabytes (found by fuzz/environment_fuzz). Walks the header(s) first:
// every attribute's declared size must fit in what is left of the file, be
// its type's size where that is fixed, and hold what its value claims. The
// layout (magic, version with flags, then per part "name\0 type\0 int32
// size, value" up to an empty name, and an empty header after the last part
// of a multi-part file), the types' sizes and the channel list's entries:
// OpenEXR's "The OpenEXR File Layout" and "Standard Attributes".
void checkExrHeader(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    unsigned char start[8] = {};
    if (!in.read(reinterpret_cast<char*>(start), 8))
        return;  // too short to be an EXR: OIIO says what it is
    if (start[0] != 0x76 || start[1] != 0x2f || start[2] != 0x31 || start[3] != 0x01) return;
    const bool multiPart = start[5] & 0x10;  // version flags, bit 12
    std::error_code ec;
    const uint64_t size = std::filesystem::file_size(path, ec);
    auto damaged = [&](const std::string& what) {
        return InputError(fmt::format("{}: damaged EXR header: {}", path.string(), what));
    };
    auto readName = [&]() {
        std::string name;
        for (char c; in.get(c) && c != '\0';) {
            if (name.size() == 255) throw damaged("a name longer than 255 bytes");
            name.push_back(c);
        }
        if (!in) throw damaged("it ends inside a name");
        return name;
    };
    auto read32 = [&](const std::string& attribute) {
        unsigned char b[4];
        if (!in.read(reinterpret_cast<char*>(b), 4))
            throw damaged(fmt::format("it ends in attribute '{}'", attribute));
        return uint32_t(b[0]) | uint32_t(b[1]) << 8 | uint32_t(b[2]) << 16 | uint32_t(b[3]) << 24;
    };
    static const std::map<std::string, int32_t> fixedSizes = {{"box2i", 16},
                                                              {"box2f", 16},
                                                              {"compression", 1},
                                                              {"double", 8},
                                                              {"envmap", 1},
                                                              {"float", 4},
                                                              {"int", 4},
                                                              {"keycode", 28},
                                                              {"lineOrder", 1},
                                                              {"m33f", 36},
                                                              {"m44f", 64},
                                                              {"m33d", 72},
                                                              {"m44d", 128},
                                                              {"rational", 8},
                                                              {"tiledesc", 9},
                                                              {"timecode", 8},
                                                              {"v2i", 8},
                                                              {"v2f", 8},
                                                              {"v3i", 12},
                                                              {"v3f", 12},
                                                              {"v2d", 16},
                                                              {"v3d", 24},
                                                              {"deepImageState", 1},
                                                              {"chromaticities", 32}};
    for (bool partStart = true;;) {
        const std::string name = readName();
        if (name.empty()) {
            // The end of a part's header; a multi-part file ends its list with an empty header.
            if (!multiPart || partStart) return;
            partStart = true;
            continue;
        }
        partStart = false;
        const std::string type = readName();
        const int32_t length = int32_t(read32(name));
        const uint64_t at = uint64_t(in.tellg());
        const uint64_t left = size - std::min(size, at);
        if (length < 0 || uint64_t(length) > left)
            throw damaged(fmt::format("attribute '{}' claims {} bytes, the file has {} left", name,
                                      length, left));
        const auto fixed = fixedSizes.find(type);
        if (fixed != fixedSizes.end() && length != fixed->second)
            throw damaged(fmt::format("attribute '{}' of type {} is {} bytes, not {}", name, type,
                                      length, fixed->second));
        if (type == "stringvector") {
            for (int64_t used = 0; used < length;) {
                const uint32_t stringLength = read32(name);
                used += 4 + int64_t(stringLength);
                if (stringLength > uint32_t(INT32_MAX) || used > length)
                    throw damaged(
                        fmt::format("a string of attribute '{}' runs past its end", name));
                in.seekg(stringLength, std::ios::cur);
            }
            continue;
        }
        if (type == "chlist") {
            // Per channel: name\0, int32 pixel type, pLinear, 3 reserved bytes,
            // int32 x and y sampling; an empty name ends the list. OpenImageIO
            // 2.4 aborts (an assertion) on a pixel type other than UINT, HALF
            // and FLOAT (found by fuzz/environment_fuzz).
            const uint64_t end = at + uint64_t(length);
            for (std::string channel = readName(); !channel.empty(); channel = readName()) {
                const uint32_t pixelType = read32(name);
                in.seekg(4, std::ios::cur);
                const int32_t xSampling = int32_t(read32(name)), ySampling = int32_t(read32(name));
                if (uint64_t(in.tellg()) > end)
                    throw damaged(fmt::format("channel list '{}' runs past its end", name));
                if (pixelType > 2)
                    throw damaged(fmt::format(
                        "channel '{}' has pixel type {}, not 0 (uint), 1 (half) or 2 (float)",
                        channel, pixelType));
                if (xSampling < 1 || ySampling < 1)
                    throw damaged(fmt::format("channel '{}' has sampling {}x{}", channel, xSampling,
                                              ySampling));
            }
            // OpenEXR reads the next attribute where the list's empty name
            // ends, not at its declared size (found by fuzz/environment_fuzz:
            // a list 20 bytes short of its size hid a string of 914 MB).
            if (uint64_t(in.tellg()) != end)
                throw damaged(fmt::format("channel list '{}' ends {} bytes before its size says",
                                          name, end - uint64_t(in.tellg())));
            continue;
        }
        if (type == "preview") {
            const uint64_t width = length >= 8 ? read32(name) : 0,
                           height = length >= 8 ? read32(name) : 0;
            if (length < 8 || 8 + 4 * width * height != uint64_t(length))
                throw damaged(fmt::format("preview '{}' claims {}x{} pixels in {} bytes", name,
                                          width, height, length));
            in.seekg(length - 8, std::ios::cur);
            continue;
        }
        in.seekg(length, std::ios::cur);
    }
}

// OpenImageIO's reader of `path`, after the checks above; InputError naming the file otherwise.
std::unique_ptr<OIIO::ImageInput> openImage(const std::filesystem::path& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
        throw InputError(fmt::format("{}: no such file", path.string()));
    checkExrHeader(path);
    auto in = OIIO::ImageInput::open(path.string());
    if (!in)
        throw InputError(fmt::format("{}: cannot read image: {}", path.string(), OIIO::geterror()));
    return in;
}

}  // namespace

float linearToSrgb(float linear) {
    const float v = std::clamp(linear, 0.0f, 1.0f);
    return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

void writeExr(const std::filesystem::path& path, const Image& image, const Metadata& metadata) {
    OIIO::ImageSpec spec(static_cast<int>(image.width), static_cast<int>(image.height), 3,
                         OIIO::TypeDesc::FLOAT);
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
    OIIO::ImageSpec spec(static_cast<int>(image.width), static_cast<int>(image.height), 3,
                         OIIO::TypeDesc::UINT8);
    writeWithOiio(path, spec, OIIO::TypeDesc::UINT8, bytes.data());
}

std::map<std::string, std::string> readVkpathMetadata(const std::filesystem::path& path) {
    const auto in = openImage(path);
    std::map<std::string, std::string> attributes;
    for (const OIIO::ParamValue& p : in->spec().extra_attribs) {
        const std::string name = p.name().string();
        if (name.rfind("vkpath:", 0) == 0) attributes[name] = p.get_string();
    }
    return attributes;
}

Image readImage(const std::filesystem::path& path, uint64_t maxPixels) {
    const auto in = openImage(path);
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0 || spec.depth != 1)
        throw InputError(fmt::format("{}: not a 2-D image", path.string()));
    if (uint64_t(spec.width) * uint64_t(spec.height) > maxPixels)
        throw InputError(fmt::format("{}: {}x{} pixels exceed the limit of {}", path.string(),
                                     spec.width, spec.height, maxPixels));
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

Rgba16Image decodeImage(std::span<const uint8_t> bytes, const std::string& format,
                        uint64_t maxPixels) {
    OIIO::Filesystem::IOMemReader memory(bytes.data(), bytes.size());
    // Texture images keep straight (unassociated) alpha, as glTF's are: without
    // this OpenImageIO premultiplies on reading, and rounds the colour of every
    // translucent texel (40 at alpha 205 came back 39).
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    // With a configuration OpenImageIO 2.4 takes the proxy from it (a pointer
    // to the pointer), not from open()'s argument.
    OIIO::Filesystem::IOProxy* proxy = &memory;
    config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
    // The name only picks the reader; the bytes come from `memory`.
    auto in = OIIO::ImageInput::open("texture." + format, &config, proxy);
    if (!in)
        throw InputError(fmt::format("cannot decode the {} image: {}", format, OIIO::geterror()));
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0 || spec.depth != 1)
        throw InputError(fmt::format("the {} image is not a 2-D image", format));
    if (uint64_t(spec.width) * uint64_t(spec.height) > maxPixels)
        throw InputError(fmt::format("the {} image's {}x{} pixels exceed the limit of {}", format,
                                     spec.width, spec.height, maxPixels));
    const int channels = std::min(spec.nchannels, 4);
    std::vector<uint16_t> data(size_t(spec.width) * spec.height * channels);
    if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::UINT16, data.data()))
        throw InputError(fmt::format("cannot decode the {} image: {}", format, in->geterror()));
    Rgba16Image image;
    image.width = uint32_t(spec.width);
    image.height = uint32_t(spec.height);
    image.texels.resize(size_t(spec.width) * spec.height);
    for (size_t i = 0; i < image.texels.size(); ++i) {
        const uint16_t* p = &data[i * channels];
        const uint16_t opaque = 65535;
        switch (channels) {
            case 1:
                image.texels[i] = glm::u16vec4(p[0], p[0], p[0], opaque);
                break;
            case 2:
                image.texels[i] = glm::u16vec4(p[0], p[0], p[0], p[1]);
                break;
            case 3:
                image.texels[i] = glm::u16vec4(p[0], p[1], p[2], opaque);
                break;
            default:
                image.texels[i] = glm::u16vec4(p[0], p[1], p[2], p[3]);
                break;
        }
    }
    return image;
}

}  // namespace vkpath::image
