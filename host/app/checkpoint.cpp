#include "app/checkpoint.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <string>

#include "app/fnv1a.h"
#include "input_error.h"

namespace vkpath::app {
namespace {

// The first line; the number is the format's version, raised whenever the
// header's meaning changes (1: "key value" lines; 2: JSON).
constexpr const char* MAGIC_PREFIX = "vkpath checkpoint ";
constexpr int FORMAT = 3;

uint64_t hashText(const std::string& text, uint64_t hash = FNV1A_OFFSET) {
    return fnv1a(std::as_bytes(std::span(text.data(), text.size())), hash);
}

// The file's text before the film: the first line and every field but the
// film's bytes as one line of JSON.
std::string header(const Checkpoint& c) {
    const wavefront::RenderState& s = c.state;
    nlohmann::ordered_json fields;
    fields["scene-hash"] = c.identity.sceneHash;
    fields["settings"] = nlohmann::ordered_json::parse(c.identity.settings, nullptr, false);
    if (fields["settings"].is_discarded()) fields["settings"] = c.identity.settings;
    fields["first-sample"] = c.samples.first;
    fields["sample-count"] = c.samples.count;
    fields["samples-done"] = s.samplesDone;
    fields["film-format"] = s.filmFormat;
    fields["width"] = s.width;
    fields["height"] = s.height;
    fields["film-bytes"] = uint64_t(s.film.size());
    // Adaptive sampling: per-pixel counts and the pass in progress (its
    // pixels), as 32-bit words after the film.
    fields["pixel-samples"] = uint64_t(s.pixelSamples.size());
    fields["pass-pixels"] = s.pass ? uint64_t(s.pass->pixels.size()) : 0;
    fields["pass-rounds"] = s.pass ? s.pass->rounds : 0;
    fields["non-finite-samples"] = s.nonFiniteSamples;
    fields["firefly-samples"] = s.fireflySamples;
    fields["rejected-light-samples"] = s.rejectedLightSamples;
    fields["closest-rays"] = s.rays.closest;
    fields["shadow-rays"] = s.rays.shadow;
    fields["waves"] = s.waves;
    fields["seconds"] = s.seconds;  // JSON numbers keep a double exactly
    if (!c.autoChoice.empty())
        fields["auto"] = nlohmann::ordered_json::parse(c.autoChoice, nullptr, false);
    return fmt::format("{}{}\n{}\n", MAGIC_PREFIX, FORMAT,
                       fields.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
}

void writeAll(int fd, const char* data, size_t size, const std::filesystem::path& path) {
    while (size > 0) {
        const ssize_t n = ::write(fd, data, size);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0)
            throw std::runtime_error(fmt::format("{}: cannot write the checkpoint: {}",
                                                 path.string(), std::strerror(errno)));
        data += n;
        size -= size_t(n);
    }
}

// The whole number at `key` of the header; InputError if absent, not a whole
// number or beyond T.
template <typename T>
T number(const nlohmann::ordered_json& fields, const char* key, const std::string& file) {
    const auto it = fields.find(key);
    if (it == fields.end())
        throw InputError(fmt::format("{}: damaged checkpoint: no {}", file, key));
    if (!it->is_number_unsigned() || it->get<uint64_t>() > std::numeric_limits<T>::max())
        throw InputError(fmt::format("{}: damaged checkpoint: {} {}", file, key, it->dump()));
    return T(it->get<uint64_t>());
}

// The string, or for "settings" the JSON text, at `key`; InputError if absent.
std::string text(const nlohmann::ordered_json& fields, const char* key, const std::string& file) {
    const auto it = fields.find(key);
    if (it == fields.end())
        throw InputError(fmt::format("{}: damaged checkpoint: no {}", file, key));
    if (it->is_string()) return it->get<std::string>();
    if (it->is_object()) return it->dump();
    throw InputError(fmt::format("{}: damaged checkpoint: {} {}", file, key, it->dump()));
}

}  // namespace

void writeCheckpoint(const std::filesystem::path& path, const Checkpoint& checkpoint) {
    const std::string text = header(checkpoint);
    const wavefront::RenderState& state = checkpoint.state;
    const std::span<const std::byte> counts = std::as_bytes(std::span(state.pixelSamples));
    const std::span<const std::byte> passPixels =
        state.pass ? std::as_bytes(std::span(state.pass->pixels)) : std::span<const std::byte>();
    const auto* film = reinterpret_cast<const char*>(state.film.data());
    const uint64_t hash = fnv1a(passPixels, fnv1a(counts, fnv1a(state.film, hashText(text))));
    unsigned char hashBytes[8];
    for (int i = 0; i < 8; ++i) hashBytes[i] = uint8_t(hash >> (8 * i));

    auto temp = path;
    temp.replace_filename(fmt::format(".{}.partial", path.filename().string()));
    const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0)
        throw std::runtime_error(fmt::format("{}: cannot write the checkpoint: {}", path.string(),
                                             std::strerror(errno)));
    try {
        writeAll(fd, text.data(), text.size(), path);
        writeAll(fd, film, state.film.size(), path);
        writeAll(fd, reinterpret_cast<const char*>(counts.data()), counts.size(), path);
        writeAll(fd, reinterpret_cast<const char*>(passPixels.data()), passPixels.size(), path);
        writeAll(fd, reinterpret_cast<const char*>(hashBytes), 8, path);
        if (::fsync(fd) != 0)
            throw std::runtime_error(fmt::format("{}: cannot write the checkpoint: {}",
                                                 path.string(), std::strerror(errno)));
    } catch (...) {
        ::close(fd);
        ::unlink(temp.c_str());
        throw;
    }
    ::close(fd);
    if (::rename(temp.c_str(), path.c_str()) != 0) {
        const int error = errno;
        ::unlink(temp.c_str());
        throw std::runtime_error(fmt::format("{}: cannot write the checkpoint: {}", path.string(),
                                             std::strerror(error)));
    }
    // The rename itself reaches the disk with the folder's entry.
    const auto folder = path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
    const int dir = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dir >= 0) {
        ::fsync(dir);
        ::close(dir);
    }
}

Checkpoint readCheckpoint(const std::filesystem::path& path) {
    const std::string file = path.string();
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
        throw InputError(fmt::format("{}: no such file", file));
    std::ifstream in(path, std::ios::binary);
    std::ostringstream buffer;
    buffer << in.rdbuf();
    const std::string bytes = buffer.str();
    if (!in && !in.eof()) throw InputError(fmt::format("{}: cannot read", file));
    const size_t magicEnd = bytes.find('\n');
    if (bytes.compare(0, std::strlen(MAGIC_PREFIX), MAGIC_PREFIX) != 0 ||
        magicEnd == std::string::npos)
        throw InputError(fmt::format("{}: not a vkpath checkpoint", file));
    const std::string format =
        bytes.substr(std::strlen(MAGIC_PREFIX), magicEnd - std::strlen(MAGIC_PREFIX));
    if (format != std::to_string(FORMAT)) {
        const bool older = format.size() == 1 && format[0] >= '1' && format[0] < '0' + FORMAT;
        throw InputError(fmt::format(
            "{}: a checkpoint of format {}, written by {} vkpath build; this build reads "
            "format {} only: render again without --resume",
            file, format.substr(0, 20), older ? "an older" : "another", FORMAT));
    }
    const size_t headerEnd = bytes.find('\n', magicEnd + 1);
    if (headerEnd == std::string::npos)
        throw InputError(fmt::format("{}: damaged checkpoint: no end of header", file));
    const auto fields = nlohmann::ordered_json::parse(bytes.begin() + magicEnd + 1,
                                                      bytes.begin() + headerEnd, nullptr, false);
    if (!fields.is_object())
        throw InputError(
            fmt::format("{}: damaged checkpoint: its header is not a JSON object", file));
    Checkpoint c;
    c.identity = {text(fields, "scene-hash", file), text(fields, "settings", file)};
    c.samples = {number<uint32_t>(fields, "first-sample", file),
                 number<uint32_t>(fields, "sample-count", file)};
    wavefront::RenderState& s = c.state;
    s.filmFormat = text(fields, "film-format", file);
    s.width = number<uint32_t>(fields, "width", file);
    s.height = number<uint32_t>(fields, "height", file);
    s.samplesDone = number<uint32_t>(fields, "samples-done", file);
    s.nonFiniteSamples = number<uint64_t>(fields, "non-finite-samples", file);
    s.fireflySamples = number<uint64_t>(fields, "firefly-samples", file);
    s.rejectedLightSamples = number<uint64_t>(fields, "rejected-light-samples", file);
    s.rays = {number<uint64_t>(fields, "closest-rays", file),
              number<uint64_t>(fields, "shadow-rays", file)};
    s.waves = number<uint32_t>(fields, "waves", file);
    const auto seconds = fields.find("seconds");
    if (seconds == fields.end() || !seconds->is_number())
        throw InputError(fmt::format("{}: damaged checkpoint: no seconds", file));
    s.seconds = seconds->get<double>();
    if (const auto choice = fields.find("auto"); choice != fields.end()) {
        if (!choice->is_object())
            throw InputError(fmt::format("{}: damaged checkpoint: its auto choice", file));
        c.autoChoice = choice->dump();
    }
    const uint64_t filmBytes = number<uint64_t>(fields, "film-bytes", file);
    const uint64_t countBytes = 4 * uint64_t(number<uint32_t>(fields, "pixel-samples", file));
    const uint64_t passBytes = 4 * uint64_t(number<uint32_t>(fields, "pass-pixels", file));
    const uint32_t passRounds = number<uint32_t>(fields, "pass-rounds", file);
    const size_t filmStart = headerEnd + 1;
    const uint64_t bodyBytes = filmBytes + countBytes + passBytes;
    if (bytes.size() < filmStart || bytes.size() - filmStart != bodyBytes + 8)
        throw InputError(fmt::format("{}: damaged checkpoint: {} bytes, expected {}", file,
                                     bytes.size(), filmStart + bodyBytes + 8));
    uint64_t stored = 0;
    for (int i = 0; i < 8; ++i)
        stored |= uint64_t(uint8_t(bytes[filmStart + bodyBytes + i])) << (8 * i);
    if (fnv1a(std::as_bytes(std::span(bytes.data(), filmStart + bodyBytes))) != stored)
        throw InputError(
            fmt::format("{}: damaged checkpoint: its hash does not match its contents", file));
    s.film.resize(filmBytes);
    std::memcpy(s.film.data(), bytes.data() + filmStart, filmBytes);
    s.pixelSamples.resize(countBytes / 4);
    std::memcpy(s.pixelSamples.data(), bytes.data() + filmStart + filmBytes, countBytes);
    if (passRounds > 0) {
        s.pass = wavefront::SamplePass{std::vector<uint32_t>(passBytes / 4), passRounds};
        std::memcpy(s.pass->pixels.data(), bytes.data() + filmStart + filmBytes + countBytes,
                    passBytes);
    }
    return c;
}

void checkCheckpointMatches(const std::filesystem::path& path, const Checkpoint& checkpoint,
                            const RenderIdentity& identity, const wavefront::SampleRange& samples) {
    const std::string file = path.string();
    if (checkpoint.identity.sceneHash != identity.sceneHash)
        throw InputError(fmt::format("{}: from another scene (scene hash {}, this scene's {})",
                                     file, checkpoint.identity.sceneHash, identity.sceneHash));
    if (!isSettingsRecord(checkpoint.identity.settings))
        throw InputError(fmt::format(
            "{}: written by an older vkpath build (its settings are not JSON): render again "
            "without --resume",
            file));
    const auto [theirs, ours] =
        firstSettingDifference(checkpoint.identity.settings, identity.settings);
    if (!theirs.empty())
        throw InputError(
            fmt::format("{}: other settings: {} in the checkpoint, {} here", file, theirs, ours));
    if (checkpoint.samples.first != samples.first)
        throw InputError(fmt::format("{}: samples from {} on; this render starts at sample {}",
                                     file, checkpoint.samples.first, samples.first));
}

vk::VulkanError withLastCheckpoint(const vk::VulkanError& error, const std::filesystem::path& path,
                                   uint32_t samplesDone) {
    return vk::VulkanError(
        error.result(),
        fmt::format("{}; the last checkpoint, {} spp, is in {}: resume with --resume {}",
                    error.what(), samplesDone, path.string(), path.string()));
}

}  // namespace vkpath::app
