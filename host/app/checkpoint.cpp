#include "app/checkpoint.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>

#include "app/fnv1a.h"
#include "input_error.h"

namespace vkpath::app {
namespace {

constexpr const char* MAGIC = "vkpath checkpoint 1\n";

uint64_t hashText(const std::string& text, uint64_t hash = FNV1A_OFFSET) {
    return fnv1a(std::as_bytes(std::span(text.data(), text.size())), hash);
}

// Values are one line each: newlines and backslashes escaped.
std::string escape(const std::string& value) {
    std::string out;
    for (char c : value) {
        if (c == '\n' || c == '\\') out.push_back('\\');
        out.push_back(c == '\n' ? 'n' : c);
    }
    return out;
}

std::string unescape(const std::string& value) {
    std::string out;
    for (size_t i = 0; i < value.size(); ++i) {
        if (value[i] == '\\' && i + 1 < value.size()) {
            ++i;
            out.push_back(value[i] == 'n' ? '\n' : value[i]);
        } else {
            out.push_back(value[i]);
        }
    }
    return out;
}

// The file's text before the film: every field but the film's bytes.
std::string header(const Checkpoint& c) {
    const wavefront::RenderState& s = c.state;
    const std::pair<const char*, std::string> fields[] = {
        {"scene-hash", c.identity.sceneHash},
        {"settings", c.identity.settings},
        {"first-sample", std::to_string(c.samples.first)},
        {"sample-count", std::to_string(c.samples.count)},
        {"samples-done", std::to_string(s.samplesDone)},
        {"film-format", s.filmFormat},
        {"width", std::to_string(s.width)},
        {"height", std::to_string(s.height)},
        {"film-bytes", std::to_string(s.film.size())},
        {"non-finite-samples", std::to_string(s.nonFiniteSamples)},
        {"firefly-samples", std::to_string(s.fireflySamples)},
        {"rejected-light-samples", std::to_string(s.rejectedLightSamples)},
        {"closest-rays", std::to_string(s.rays.closest)},
        {"shadow-rays", std::to_string(s.rays.shadow)},
        {"waves", std::to_string(s.waves)},
        // Exact: hexadecimal floating point.
        {"seconds", fmt::format("{:a}", s.seconds)},
    };
    std::string text = MAGIC;
    for (const auto& [key, value] : fields) text.append(fmt::format("{} {}\n", key, escape(value)));
    text.push_back('\n');
    return text;
}

void writeAll(int fd, const char* data, size_t size, const std::filesystem::path& path) {
    while (size > 0) {
        const ssize_t n = ::write(fd, data, size);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) throw std::runtime_error(fmt::format("{}: cannot write the checkpoint: {}", path.string(), std::strerror(errno)));
        data += n;
        size -= size_t(n);
    }
}

// The number at `key` of the header's fields; InputError if absent or not a number.
template <typename T>
T number(const std::map<std::string, std::string>& fields, const char* key, const std::string& file) {
    const auto it = fields.find(key);
    if (it == fields.end()) throw InputError(fmt::format("{}: not a vkpath checkpoint: no {}", file, key));
    try {
        size_t used = 0;
        if constexpr (std::is_same_v<T, double>) {
            const double value = std::stod(it->second, &used);
            if (used == it->second.size()) return value;
        } else {
            const unsigned long long value = std::stoull(it->second, &used);
            if (used == it->second.size() && value <= std::numeric_limits<T>::max()) return T(value);
        }
    } catch (const std::exception&) {
    }
    throw InputError(fmt::format("{}: damaged checkpoint: {} \"{}\"", file, key, it->second));
}

}  // namespace

void writeCheckpoint(const std::filesystem::path& path, const Checkpoint& checkpoint) {
    const std::string text = header(checkpoint);
    const auto* film = reinterpret_cast<const char*>(checkpoint.state.film.data());
    const uint64_t hash = fnv1a(checkpoint.state.film, hashText(text));
    unsigned char hashBytes[8];
    for (int i = 0; i < 8; ++i) hashBytes[i] = uint8_t(hash >> (8 * i));

    auto temp = path;
    temp.replace_filename(fmt::format(".{}.partial", path.filename().string()));
    const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) throw std::runtime_error(fmt::format("{}: cannot write the checkpoint: {}", path.string(), std::strerror(errno)));
    try {
        writeAll(fd, text.data(), text.size(), path);
        writeAll(fd, film, checkpoint.state.film.size(), path);
        writeAll(fd, reinterpret_cast<const char*>(hashBytes), 8, path);
        if (::fsync(fd) != 0)
            throw std::runtime_error(fmt::format("{}: cannot write the checkpoint: {}", path.string(), std::strerror(errno)));
    } catch (...) {
        ::close(fd);
        ::unlink(temp.c_str());
        throw;
    }
    ::close(fd);
    if (::rename(temp.c_str(), path.c_str()) != 0) {
        const int error = errno;
        ::unlink(temp.c_str());
        throw std::runtime_error(fmt::format("{}: cannot write the checkpoint: {}", path.string(), std::strerror(error)));
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
    if (!std::filesystem::is_regular_file(path, ec)) throw InputError(fmt::format("{}: no such file", file));
    std::ifstream in(path, std::ios::binary);
    std::ostringstream buffer;
    buffer << in.rdbuf();
    const std::string bytes = buffer.str();
    if (!in && !in.eof()) throw InputError(fmt::format("{}: cannot read", file));
    if (bytes.compare(0, std::strlen(MAGIC), MAGIC) != 0)
        throw InputError(fmt::format("{}: not a vkpath checkpoint", file));
    const size_t headerEnd = bytes.find("\n\n");
    if (headerEnd == std::string::npos) throw InputError(fmt::format("{}: damaged checkpoint: no end of header", file));
    std::map<std::string, std::string> fields;
    std::istringstream lines(bytes.substr(std::strlen(MAGIC), headerEnd + 1 - std::strlen(MAGIC)));
    for (std::string line; std::getline(lines, line);) {
        const size_t space = line.find(' ');
        fields[line.substr(0, space)] = space == std::string::npos ? "" : unescape(line.substr(space + 1));
    }
    Checkpoint c;
    c.identity = {fields["scene-hash"], fields["settings"]};
    c.samples = {number<uint32_t>(fields, "first-sample", file), number<uint32_t>(fields, "sample-count", file)};
    wavefront::RenderState& s = c.state;
    s.filmFormat = fields["film-format"];
    s.width = number<uint32_t>(fields, "width", file);
    s.height = number<uint32_t>(fields, "height", file);
    s.samplesDone = number<uint32_t>(fields, "samples-done", file);
    s.nonFiniteSamples = number<uint64_t>(fields, "non-finite-samples", file);
    s.fireflySamples = number<uint64_t>(fields, "firefly-samples", file);
    s.rejectedLightSamples = number<uint64_t>(fields, "rejected-light-samples", file);
    s.rays = {number<uint64_t>(fields, "closest-rays", file), number<uint64_t>(fields, "shadow-rays", file)};
    s.waves = number<uint32_t>(fields, "waves", file);
    s.seconds = number<double>(fields, "seconds", file);
    const uint64_t filmBytes = number<uint64_t>(fields, "film-bytes", file);
    const size_t filmStart = headerEnd + 2;
    if (bytes.size() < filmStart || bytes.size() - filmStart != filmBytes + 8)
        throw InputError(fmt::format("{}: damaged checkpoint: {} bytes, expected {}", file, bytes.size(),
                                     filmStart + filmBytes + 8));
    uint64_t stored = 0;
    for (int i = 0; i < 8; ++i) stored |= uint64_t(uint8_t(bytes[filmStart + filmBytes + i])) << (8 * i);
    if (fnv1a(std::as_bytes(std::span(bytes.data(), filmStart + filmBytes))) != stored)
        throw InputError(fmt::format("{}: damaged checkpoint: its hash does not match its contents", file));
    s.film.resize(filmBytes);
    std::memcpy(s.film.data(), bytes.data() + filmStart, filmBytes);
    return c;
}

void checkCheckpointMatches(const std::filesystem::path& path, const Checkpoint& checkpoint,
                            const RenderIdentity& identity, const wavefront::SampleRange& samples) {
    const std::string file = path.string();
    if (checkpoint.identity.sceneHash != identity.sceneHash)
        throw InputError(fmt::format("{}: from another scene (scene hash {}, this scene's {})", file,
                                     checkpoint.identity.sceneHash, identity.sceneHash));
    const auto [theirs, ours] = firstSettingDifference(checkpoint.identity.settings, identity.settings);
    if (!theirs.empty())
        throw InputError(fmt::format("{}: other settings: {} in the checkpoint, {} here", file, theirs, ours));
    if (checkpoint.samples.first != samples.first)
        throw InputError(fmt::format("{}: samples from {} on; this render starts at sample {}", file,
                                     checkpoint.samples.first, samples.first));
}

vk::VulkanError withLastCheckpoint(const vk::VulkanError& error, const std::filesystem::path& path,
                                   uint32_t samplesDone) {
    return vk::VulkanError(error.result(), fmt::format("{}; the last checkpoint, {} spp, is in {}: resume with --resume {}",
                                                       error.what(), samplesDone, path.string(), path.string()));
}

}  // namespace vkpath::app
