// What the loader harnesses share: a private folder to write each input into,
// a watch on the files a loader must never open, and the rule that InputError
// is the only acceptable way for a loader to refuse an input.
//
// The folder, made once per process under $TMPDIR (the fuzz scripts point it
// into build-fuzz/):
//
//   vkpath-fuzz-XXXXXX/scene/     the input (input.<ext>), buffer.bin (a valid
//                                 external glTF buffer, BUFFER_BYTES below),
//                                 texture.png (a 2 x 2 RGB image),
//                                 escape.bin -> ../outside/buffer.bin and
//                                 escape_dir -> ../outside (links that leave)
//   vkpath-fuzz-XXXXXX/outside/   buffer.bin and secret.txt: a loader that
//                                 opens anything here has read outside the
//                                 scene's folder (inotify reports the open)
//
// A finding (an exception other than InputError, a scene that breaks the
// scene model's invariants, an open outside the folder) is printed on the
// stderr the process started with (libFuzzer's -close_fd_mask=2 silences the
// loaders' warnings, not this) and ends the process with abort(), which
// libFuzzer reports as a crash and saves as an artifact.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>

#include "scene/scene.h"

namespace vkpath::fuzz {

// buffer.bin in both folders: one triangle, positions (3 x VEC3 float, bytes
// 0..35) then indices (3 x u16, bytes 36..41), padded to 44 bytes. fuzz_seeds
// writes glTF seeds that use it.
inline constexpr size_t BUFFER_POSITIONS_OFFSET = 0;
inline constexpr size_t BUFFER_INDICES_OFFSET = 36;
inline constexpr size_t BUFFER_BYTES = 44;
void writeBufferBin(const std::filesystem::path& path);

// texture.png in the scene's folder: a valid 2 x 2 PNG for the COLLADA seeds'
// <image> to decode.
inline constexpr const char* TEXTURE_PNG = "texture.png";

// Sets up the folder and the watch; call from LLVMFuzzerInitialize (before
// libFuzzer closes stderr).
void initialize();

// Writes the input to scene/<name> and returns its path.
std::filesystem::path writeInput(std::string_view name, const uint8_t* data, size_t size);

// Runs `load`: InputError is a normal outcome (its message is printed when
// VKPATH_FUZZ_VERBOSE=1); any other exception, or an open of a file in
// outside/, is a finding.
void run(const std::function<void()>& load);

// Prints "vkpath fuzz finding: <what>" and aborts.
[[noreturn]] void finding(const std::string& what);

// The scene model's invariants, which the BVH builder, the GPU upload and the
// kernels rely on: every index in range, every number finite, a usable
// camera. A violation is a finding.
void checkScene(const scene::Scene& scene);

}  // namespace vkpath::fuzz
