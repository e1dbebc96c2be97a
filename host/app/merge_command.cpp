// `vkpath merge PART.exr... -o OUT.exr [--aov variance] [--allow-gaps]`: the
// parts of one render (`vkpath render --samples FIRST:COUNT`, on any devices
// and machines) made into one image, each part's mean weighted by its sample
// count. Random numbers are keyed by (pixel, sample index, seed), so parts
// of disjoint ranges are exactly the samples one render of their union
// draws; the merged mean differs from that render's only by the rounding of
// the parts' float means (tests/cli/merge_test.cpp bounds it). An adaptive
// part (render --adaptive) gave each pixel its own count, a prefix of its
// range (vkpath:sampleRange samples from vkpath:firstSample): its pixels are
// weighted by the counts of its spp AOV.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "app/commands.h"
#include "app/render_options.h"
#include "image/image.h"
#include "image/statistics.h"
#include "input_error.h"

namespace vkpath::app {
namespace {

struct MergeOptions {
    std::vector<std::string> parts;
    std::string output;
    std::vector<std::string> aovs;
    bool allowGaps = false;
};

struct Part {
    std::string path;
    std::map<std::string, std::string> metadata;
    uint32_t first = 0;
    uint32_t count = 0;  // every pixel's samples (the least of them when adaptive)
    uint32_t range = 0;  // the sample indices it drew from: count, or an adaptive render's range
    image::Image mean;
    image::Image varianceOfMean;  // with --aov variance
    image::Image samples;         // adaptive: each pixel's count (its spp AOV)

    double samplesAt(size_t pixel) const {
        return samples.pixels.empty() ? double(count) : double(samples.pixels[pixel][0]);
    }
};

uint32_t metadataCount(const std::string& path, const std::map<std::string, std::string>& m,
                       const char* key) {
    const auto it = m.find(key);
    if (it == m.end() || it->second.empty() ||
        it->second.find_first_not_of("0123456789") != std::string::npos || it->second.size() > 10 ||
        std::stoull(it->second) > UINT32_MAX)
        throw InputError(
            fmt::format("{}: no {} in its header: not a part written by vkpath render", path, key));
    return uint32_t(std::stoull(it->second));
}

// The header fields that must agree for parts to be samples of one image.
constexpr const char* IDENTITY_KEYS[] = {"vkpath:sceneHash", "vkpath:settings"};

int runMerge(const MergeOptions& o) {
    std::vector<Part> parts;
    for (const std::string& path : o.parts) {
        Part p;
        p.path = path;
        p.metadata = image::readVkpathMetadata(path);
        p.first = metadataCount(path, p.metadata, "vkpath:firstSample");
        p.count = metadataCount(path, p.metadata, "vkpath:spp");
        p.range = p.count;
        const auto adaptive = p.metadata.find("vkpath:adaptive");
        if (adaptive != p.metadata.end() && adaptive->second != "off") {
            p.range = metadataCount(path, p.metadata, "vkpath:sampleRange");
            const auto counts = image::aovPath(path, "spp");
            if (!std::filesystem::exists(counts))
                throw InputError(fmt::format(
                    "{}: an adaptive render, whose pixels merge weighs by their counts: its spp "
                    "AOV {} is missing (render it with --aov spp)",
                    path, counts.string()));
            p.samples = image::readImage(counts);
        } else if (p.count == 0) {
            throw InputError(fmt::format("{}: a part of 0 samples", path));
        }
        for (const char* key : IDENTITY_KEYS)
            if (!p.metadata.count(key))
                throw InputError(fmt::format(
                    "{}: no {} in its header: not a part written by vkpath render", path, key));
        if (!isSettingsRecord(p.metadata.at("vkpath:settings")))
            throw InputError(fmt::format(
                "{}: written by an older vkpath build (its vkpath:settings are not JSON): "
                "render the part again",
                path));
        p.mean = image::readImage(path);
        if (std::count(o.aovs.begin(), o.aovs.end(), "variance"))
            p.varianceOfMean = image::readImage(image::aovPath(path, "variance"));
        parts.push_back(std::move(p));
    }
    const Part& a = parts.front();
    for (const Part& p : parts) {
        if (p.metadata.at("vkpath:sceneHash") != a.metadata.at("vkpath:sceneHash"))
            throw InputError(
                fmt::format("{}: rendered from another scene or environment file than {} (hash {} "
                            "against {})",
                            p.path, a.path, p.metadata.at("vkpath:sceneHash"),
                            a.metadata.at("vkpath:sceneHash")));
        const auto [theirs, ours] = firstSettingDifference(p.metadata.at("vkpath:settings"),
                                                           a.metadata.at("vkpath:settings"));
        if (!theirs.empty())
            throw InputError(fmt::format("{}: rendered with other settings than {}: {} against {}",
                                         p.path, a.path, theirs, ours));
        auto sized = [&](const image::Image& i) {
            return i.pixels.empty() || (i.width == a.mean.width && i.height == a.mean.height);
        };
        if (p.mean.width != a.mean.width || p.mean.height != a.mean.height ||
            !sized(p.varianceOfMean) || !sized(p.samples))
            throw InputError(fmt::format("{}: {}x{} pixels where {} has {}x{}", p.path,
                                         p.mean.width, p.mean.height, a.path, a.mean.width,
                                         a.mean.height));
    }
    std::sort(parts.begin(), parts.end(),
              [](const Part& x, const Part& y) { return x.first < y.first; });
    for (size_t i = 1; i < parts.size(); ++i) {
        const uint64_t end = uint64_t(parts[i - 1].first) + parts[i - 1].range;
        if (parts[i].first < end)
            throw InputError(fmt::format("{}: samples {}..{} overlap {}'s {}..{}", parts[i].path,
                                         parts[i].first,
                                         uint64_t(parts[i].first) + parts[i].range - 1,
                                         parts[i - 1].path, parts[i - 1].first, end - 1));
        if (parts[i].first > end && !o.allowGaps)
            throw InputError(fmt::format(
                "{}: samples {}..{} are missing between {} and {} (--allow-gaps to merge "
                "anyway)",
                parts[i].path, end, parts[i].first - 1, parts[i - 1].path, parts[i].path));
    }

    // ---- the merged mean and variance of the mean, in double ------------------------
    // Per part and channel: n samples of mean m and variance of the mean v;
    // their sum is n m and the sum of their squares n (v (n - 1) + m^2)
    // (wavefront::estimatePixel's definitions, undone).
    const bool withVariance = std::count(o.aovs.begin(), o.aovs.end(), "variance") > 0;
    image::Image mean(a.mean.width, a.mean.height), varianceOfMean(a.mean.width, a.mean.height),
        samples(a.mean.width, a.mean.height);
    double least = INFINITY;  // samples of the pixel with the fewest
    for (size_t i = 0; i < mean.pixels.size(); ++i) {
        double total = 0;
        for (const Part& p : parts) total += p.samplesAt(i);
        least = std::min(least, total);
        samples.pixels[i] = glm::vec3(float(total));
        for (int c = 0; c < 3; ++c) {
            double sum = 0, sumSquares = 0;
            for (const Part& p : parts) {
                const double n = p.samplesAt(i), m = p.mean.pixels[i][c];
                sum += n * m;
                if (withVariance)
                    sumSquares += n * (double(p.varianceOfMean.pixels[i][c]) * (n - 1) + m * m);
            }
            const double n = total, m = n > 0 ? sum / n : 0.0;
            mean.pixels[i][c] = float(m);
            if (withVariance && n > 1)
                varianceOfMean.pixels[i][c] =
                    float(std::max(0.0, (sumSquares - n * m * m) / (n - 1)) / n);
        }
    }
    uint64_t range = 0;  // the sample indices the parts drew from
    for (const Part& p : parts) range += p.range;
    const uint64_t total = uint64_t(least);

    image::Metadata metadata;
    double sampleSum = 0, most = 0;
    for (const glm::vec3& n : samples.pixels) sampleSum += n.x, most = std::max(most, double(n.x));
    // A part's error estimate and target say nothing of the merged image.
    const std::string partOnly[] = {"vkpath:estimatedRelMse", "vkpath:targetError",
                                    "vkpath:targetReached"};
    for (const auto& [key, value] : a.metadata) {
        if (std::find(std::begin(partOnly), std::end(partOnly), key) != std::end(partOnly))
            continue;
        if (key == "vkpath:sppMean")
            metadata.emplace_back(key, fmt::format("{:.6g}", sampleSum / samples.pixels.size()));
        else if (key == "vkpath:sppMax")
            metadata.emplace_back(key, std::to_string(uint64_t(most)));
        else if (key == "vkpath:spp")
            metadata.emplace_back(key, std::to_string(total));
        else if (key == "vkpath:sampleRange")
            metadata.emplace_back(key, std::to_string(range));
        else if (key == "vkpath:firstSample")
            metadata.emplace_back(key, std::to_string(parts.front().first));
        else
            metadata.emplace_back(key, value);
    }
    metadata.emplace_back("vkpath:mergedParts", std::to_string(parts.size()));
    const std::filesystem::path output(o.output);
    if (output.has_parent_path()) std::filesystem::create_directories(output.parent_path());
    image::writeExr(output, mean, metadata);
    std::printf("%s\n", output.string().c_str());
    for (const std::string& aov : o.aovs) {
        const auto path = image::aovPath(output, aov);
        image::writeExr(path, aov == "spp" ? samples : varianceOfMean, metadata);
        std::printf("%s\n", path.string().c_str());
    }
    std::fprintf(stderr, "merged %zu parts: samples %u..%llu, %llu spp\n", parts.size(),
                 parts.front().first,
                 (unsigned long long)(uint64_t(parts.back().first) + parts.back().range - 1),
                 (unsigned long long)total);
    return 0;
}

}  // namespace

void addMergeCommand(CLI::App& app, const GlobalOptions&, Commands& commands) {
    auto o = std::make_shared<MergeOptions>();
    auto* cmd = app.add_subcommand("merge",
                                   "Merge the parts of one render (vkpath render --samples "
                                   "FIRST:COUNT), weighted by their sample counts");
    cmd->add_option("parts", o->parts, "The parts' EXRs")->required()->check(CLI::ExistingFile);
    cmd->add_option("-o,--output", o->output, "The merged EXR")->required();
    cmd->add_option("--aov", o->aovs,
                    "Also write these AOVs beside the merged EXR: variance (merged from the "
                    "parts'), spp (each pixel's samples)")
        ->check(CLI::IsMember({"variance", "spp"}));
    cmd->add_flag("--allow-gaps", o->allowGaps,
                  "Merge parts whose sample ranges leave gaps between them");
    cmd->callback([&commands, o] { commands.run = [o] { return runMerge(*o); }; });
}

}  // namespace vkpath::app
