#include "image/denoiser.h"

#include <dlfcn.h>
#include <fmt/format.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <type_traits>
#include <vector>

#include "input_error.h"

namespace vkpath::image {
namespace {

// The part of OIDN 2.x's C API used here (include/OpenImageDenoise/oidn.h;
// the values are the API's).
using OIDNDevice = struct OIDNDeviceImpl*;
using OIDNFilter = struct OIDNFilterImpl*;
using OIDNBuffer = struct OIDNBufferImpl*;
constexpr int OIDN_DEVICE_TYPE_DEFAULT = 0;
constexpr int OIDN_FORMAT_FLOAT3 = 3;
constexpr int OIDN_ERROR_NONE = 0;

struct Api {
    void* library = nullptr;
    std::string path;
    OIDNDevice (*newDevice)(int type);
    void (*commitDevice)(OIDNDevice);
    void (*releaseDevice)(OIDNDevice);
    int (*getDeviceError)(OIDNDevice, const char** message);
    OIDNBuffer (*newBuffer)(OIDNDevice, size_t bytes);
    void (*writeBuffer)(OIDNBuffer, size_t offset, size_t bytes, const void* source);
    void (*readBuffer)(OIDNBuffer, size_t offset, size_t bytes, void* destination);
    void (*releaseBuffer)(OIDNBuffer);
    OIDNFilter (*newFilter)(OIDNDevice, const char* type);
    void (*setFilterImage)(OIDNFilter, const char* name, OIDNBuffer, int format, size_t width,
                           size_t height, size_t byteOffset, size_t pixelStride, size_t rowStride);
    void (*setFilterBool)(OIDNFilter, const char* name, bool value);
    void (*commitFilter)(OIDNFilter);
    void (*executeFilter)(OIDNFilter);
    void (*releaseFilter)(OIDNFilter);
};

// Where pip put pyoidn for the python3 on PATH, if it did.
std::string pyoidnLibrary() {
    std::unique_ptr<FILE, int (*)(FILE*)> pipe(
        popen("python3 -c 'import os, pyoidn; print(os.path.dirname(pyoidn.__file__))' "
              "2>/dev/null",
              "r"),
        &pclose);
    if (!pipe) return {};
    char line[4096] = {};
    if (!std::fgets(line, sizeof(line), pipe.get())) return {};
    std::string folder(line);
    while (!folder.empty() && (folder.back() == '\n' || folder.back() == '\r')) folder.pop_back();
    return folder.empty() ? std::string() : folder + "/oidn/lib/libOpenImageDenoise.so.2";
}

const Api& api() {
    static const Api loaded = [] {
        std::vector<std::string> candidates;
        if (const char* path = std::getenv("VKPATH_OIDN_LIBRARY"); path && *path)
            candidates = {path};
        else
            candidates = {"libOpenImageDenoise.so.2", pyoidnLibrary()};
        Api a;
        for (const std::string& candidate : candidates)
            if (!candidate.empty() &&
                (a.library = dlopen(candidate.c_str(), RTLD_NOW | RTLD_LOCAL))) {
                a.path = candidate;
                break;
            }
        if (!a.library)
            throw InputError(
                "Intel Open Image Denoise 2 is not installed: `pip install pyoidn` (its wheel "
                "carries the library), or set VKPATH_OIDN_LIBRARY to libOpenImageDenoise.so.2");
        auto symbol = [&](auto& function, const char* name) {
            function = reinterpret_cast<std::remove_reference_t<decltype(function)>>(
                dlsym(a.library, name));
            if (!function)
                throw InputError(
                    fmt::format("{}: no {}: not Open Image Denoise 2.x", a.path, name));
        };
        symbol(a.newDevice, "oidnNewDevice");
        symbol(a.commitDevice, "oidnCommitDevice");
        symbol(a.releaseDevice, "oidnReleaseDevice");
        symbol(a.getDeviceError, "oidnGetDeviceError");
        symbol(a.newBuffer, "oidnNewBuffer");
        symbol(a.writeBuffer, "oidnWriteBuffer");
        symbol(a.readBuffer, "oidnReadBuffer");
        symbol(a.releaseBuffer, "oidnReleaseBuffer");
        symbol(a.newFilter, "oidnNewFilter");
        symbol(a.setFilterImage, "oidnSetFilterImage");
        symbol(a.setFilterBool, "oidnSetFilterBool");
        symbol(a.commitFilter, "oidnCommitFilter");
        symbol(a.executeFilter, "oidnExecuteFilter");
        symbol(a.releaseFilter, "oidnReleaseFilter");
        return a;
    }();
    return loaded;
}

}  // namespace

const std::string& loadDenoiser() {
    return api().path;
}

std::string denoisedMetadata(const DenoiseInputs& in) {
    return fmt::format("Intel Open Image Denoise 2, RT filter, hdr, guides: {}{}",
                       in.normal   ? "albedo, normal"
                       : in.albedo ? "albedo"
                                   : "none",
                       in.albedo && in.prefilterGuides ? " (prefiltered, cleanAux)" : "");
}

Denoised denoise(const DenoiseInputs& in) {
    const Api& oidn = api();
    const Image& color = *in.color;
    if (in.normal && !in.albedo)
        throw InputError("a normal guide needs an albedo guide too (OIDN's RT filter)");
    for (const Image* guide : {in.albedo, in.normal})
        if (guide && (guide->width != color.width || guide->height != color.height))
            throw InputError(fmt::format("a guide image is {}x{}, the image {}x{}", guide->width,
                                         guide->height, color.width, color.height));
    const OIDNDevice device = oidn.newDevice(OIDN_DEVICE_TYPE_DEFAULT);
    std::unique_ptr<OIDNDeviceImpl, void (*)(OIDNDevice)> deviceOwner(device, oidn.releaseDevice);
    auto check = [&](const char* what) {
        const char* message = nullptr;
        if (oidn.getDeviceError(device, &message) != OIDN_ERROR_NONE)
            throw std::runtime_error(fmt::format("Open Image Denoise ({}): {}: {}", oidn.path, what,
                                                 message ? message : "failed"));
    };
    if (!device) throw std::runtime_error("Open Image Denoise: no device");
    oidn.commitDevice(device);
    check("the device");
    const size_t bytes = color.pixels.size() * sizeof(glm::vec3);
    std::vector<std::unique_ptr<OIDNBufferImpl, void (*)(OIDNBuffer)>> buffers;
    auto upload = [&](const Image& image) {
        buffers.emplace_back(oidn.newBuffer(device, bytes), oidn.releaseBuffer);
        check("a buffer");
        oidn.writeBuffer(buffers.back().get(), 0, bytes, image.pixels.data());
        return buffers.back().get();
    };
    auto image = [&](OIDNFilter filter, const char* name, OIDNBuffer buffer) {
        oidn.setFilterImage(filter, name, buffer, OIDN_FORMAT_FLOAT3, color.width, color.height, 0,
                            sizeof(glm::vec3), sizeof(glm::vec3) * color.width);
    };
    using FilterOwner = std::unique_ptr<OIDNFilterImpl, void (*)(OIDNFilter)>;
    auto newFilter = [&] {
        FilterOwner filter(oidn.newFilter(device, "RT"), oidn.releaseFilter);
        check("the RT filter");
        return filter;
    };
    const OIDNBuffer albedo = in.albedo ? upload(*in.albedo) : nullptr;
    const OIDNBuffer normal = in.normal ? upload(*in.normal) : nullptr;
    // The guides denoised first, in place, and then declared clean: OIDN's
    // recommendation for final frames with noisy guides (doc/api.md, "RT":
    // "the auxiliary images should be first denoised in a prefiltering step").
    std::vector<FilterOwner> prefilters;
    for (const auto& [name, guide] : {std::pair{"albedo", albedo}, std::pair{"normal", normal}}) {
        if (!guide || !in.prefilterGuides) continue;
        prefilters.push_back(newFilter());
        image(prefilters.back().get(), name, guide);
        image(prefilters.back().get(), "output", guide);
        oidn.commitFilter(prefilters.back().get());
        check("the prefilter's settings");
    }
    const FilterOwner filterOwner = newFilter();
    const OIDNFilter filter = filterOwner.get();
    image(filter, "color", upload(color));
    if (albedo) image(filter, "albedo", albedo);
    if (normal) image(filter, "normal", normal);
    buffers.emplace_back(oidn.newBuffer(device, bytes), oidn.releaseBuffer);
    OIDNBuffer output = buffers.back().get();
    image(filter, "output", output);
    oidn.setFilterBool(filter, "hdr", true);
    if (!prefilters.empty()) oidn.setFilterBool(filter, "cleanAux", true);
    oidn.commitFilter(filter);
    check("the filter's settings");
    const auto start = std::chrono::steady_clock::now();
    for (const FilterOwner& prefilter : prefilters) {
        oidn.executeFilter(prefilter.get());
        check("prefiltering a guide");
    }
    oidn.executeFilter(filter);
    check("denoising");
    Denoised result;
    result.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    result.image = Image(color.width, color.height);
    oidn.readBuffer(output, 0, bytes, result.image.pixels.data());
    result.library = oidn.path;
    return result;
}

}  // namespace vkpath::image
