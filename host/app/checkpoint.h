// `vkpath render --checkpoint FILE` and `--resume FILE`: a render's running
// state (wavefront::RenderState) in a file, with the render's identity (the
// scene hash and the settings string of app/render_options.h) and the sample
// range it was asked for, so that resuming can refuse a state from another
// scene or other settings and say what differs.
//
// The file: the line "vkpath checkpoint 2" (the format), then one line of
// JSON (the identity, with the settings as an object, the sample range, the
// film's size and format and the counters), the film's bytes, and an FNV-1a
// 64 hash of everything before it (8 bytes, little-endian) that catches a
// truncated or damaged file; a file of another format (builds before JSON
// wrote "key value" lines) is refused with one line. It is
// written beside its final path, flushed to the disk (fsync) and renamed over
// it, so a crash or a full disk leaves the previous checkpoint whole.
#pragma once

#include <filesystem>

#include "app/render_options.h"
#include "vk/check.h"
#include "wavefront/render_types.h"

namespace vkpath::app {

struct Checkpoint {
    RenderIdentity identity;
    wavefront::SampleRange samples;  // the range the render was asked for
    wavefront::RenderState state;
    // render --auto: the choice (app/auto_choice.h, as JSON) that a resumed
    // render goes on with; empty without --auto.
    std::string autoChoice;
};

// Throws std::runtime_error (naming the file and the system's reason) when
// it cannot be written; an earlier file at `path` is then left as it was.
void writeCheckpoint(const std::filesystem::path& path, const Checkpoint& checkpoint);

// Throws InputError (one line, naming the file) for a file that is missing,
// not a checkpoint, of another format, or damaged.
Checkpoint readCheckpoint(const std::filesystem::path& path);

// Throws InputError unless `checkpoint` (read from `path`) continues a render
// of `identity` and `samples`: the same scene bytes, every pixel-changing
// setting equal (the first that differs is named), the same first sample.
void checkCheckpointMatches(const std::filesystem::path& path, const Checkpoint& checkpoint,
                            const RenderIdentity& identity, const wavefront::SampleRange& samples);

// A Vulkan error that ended a render (the device lost, out of memory) after
// `path` got its last checkpoint, of `samplesDone` whole samples: the same
// error (and VkResult), its one line ending with where that checkpoint is and
// how to go on. Checkpoints are only ever renamed over whole, so it is intact.
vk::VulkanError withLastCheckpoint(const vk::VulkanError& error, const std::filesystem::path& path,
                                   uint32_t samplesDone);

}  // namespace vkpath::app
