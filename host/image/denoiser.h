// Intel Open Image Denoise 2.x (its "RT" filter: path-traced HDR images),
// loaded at run time from the library PyPI's `pyoidn` wheel ships
// (libOpenImageDenoise.so.2 with its CPU device, and GPU devices where
// present; the wheel has no headers, so the documented C API is declared
// in denoiser.cpp). Where the library is looked for, in order:
// VKPATH_OIDN_LIBRARY (its path), the dynamic linker's search path, and the
// pyoidn package of the `python3` on PATH.
#pragma once

#include <optional>
#include <string>

#include "image/image.h"

namespace vkpath::image {

struct DenoiseInputs {
    const Image* color = nullptr;   // linear HDR radiance
    const Image* albedo = nullptr;  // optional guide: the first non-delta hit's albedo, [0, 1]
    const Image* normal = nullptr;  // optional guide (with albedo): its shading normal, [-1, 1]
    // The guides denoised first and then declared noise-free (OIDN's cleanAux).
    bool prefilterGuides = false;
};

struct Denoised {
    Image image;
    std::string library;  // the file the library was loaded from
    double seconds = 0;   // the filters' execution (the guides' prefilters included)
};

// Loads the library (once): the file it came from. Throws InputError, one
// line saying how to install it, when it cannot be loaded.
const std::string& loadDenoiser();

// Throws what loadDenoiser throws, InputError for guides of another size,
// and std::runtime_error with OIDN's message when it fails.
Denoised denoise(const DenoiseInputs& inputs);

// What the EXR of a denoised image says it is (its vkpath:denoised).
std::string denoisedMetadata(const DenoiseInputs& inputs);

}  // namespace vkpath::image
