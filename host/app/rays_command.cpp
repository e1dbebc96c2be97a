// `vkpath rays`: the camera stage alone. Renders the direction of each pixel's
// camera ray as a colour (0.5 + 0.5 * direction), one jittered sample per
// pixel, through the real generate kernel. A diagnostic of the camera model.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <cstdio>
#include <filesystem>

#include "app/commands.h"
#include "app/film_size.h"
#include "image/image.h"
#include "scene/camera.h"
#include "shared/bindings.h"
#include "vk/buffer.h"
#include "vk/context.h"
#include "vk/kernel.h"

namespace vkpath::app {

void addRaysCommand(CLI::App& app, const GlobalOptions& global, Commands& commands) {
    struct Options {
        std::string output = "out/rays.exr";
        std::string png;
        std::string size = "640x480";
        std::vector<float> eye{0, 0, 3}, target{0, 0, 0}, up{0, 1, 0};
        float fov = 60;
        uint32_t seed = 0;
    };
    auto o = std::make_shared<Options>();
    auto* cmd = app.add_subcommand("rays", "Render camera-ray directions as colours (camera stage only)");
    cmd->add_option("-o,--output", o->output, "Output EXR")->capture_default_str();
    cmd->add_option("--png", o->png, "Also write an sRGB PNG preview");
    cmd->add_option("-d,--size", o->size, "Film size WxH")->capture_default_str();
    cmd->add_option("--eye", o->eye, "Camera position x y z")->expected(3);
    cmd->add_option("--target", o->target, "Look-at point x y z")->expected(3);
    cmd->add_option("--up", o->up, "Up vector x y z")->expected(3);
    cmd->add_option("--fov", o->fov, "Horizontal field of view, degrees")->capture_default_str();
    cmd->add_option("--seed", o->seed, "Random seed")->capture_default_str();
    cmd->callback([&global, &commands, o] {
        commands.run = [&global, o] {
            const FilmSize film = parseFilmSize(o->size);
            scene::Camera camera;
            camera.position = {o->eye[0], o->eye[1], o->eye[2]};
            camera.target = {o->target[0], o->target[1], o->target[2]};
            camera.up = {o->up[0], o->up[1], o->up[2]};
            camera.xfovDegrees = o->fov;
            const shared::Camera gpuCamera = scene::makeGpuCamera(camera, film.width, film.height);
            return withContext(global, [&](vk::Context& context) {
                const uint32_t count = film.width * film.height;
                vk::Buffer cameraBuffer = vk::Buffer::fromSpan(context, std::span(&gpuCamera, 1), "camera");
                vk::Buffer rays(context, sizeof(shared::Ray) * count, vk::MemoryKind::DeviceLocal, "rays");
                vk::Kernel generate(context, "generate");
                shared::GeneratePush push{0, count, 0, o->seed};
                const double ms = generate.dispatch(
                    count, {{VKP_GENERATE_BINDING_CAMERA, &cameraBuffer}, {VKP_GENERATE_BINDING_RAYS, &rays}}, push);
                const auto result = rays.download<shared::Ray>();
                image::Image img(film.width, film.height);
                for (uint32_t i = 0; i < count; ++i) img.pixels[i] = 0.5f + 0.5f * result[i].direction;
                std::filesystem::path out(o->output);
                if (out.has_parent_path()) std::filesystem::create_directories(out.parent_path());
                image::writeExr(out, img, {{"vkpath:device", context.info().name}, {"vkpath:version", VKPATH_VERSION}});
                std::printf("%s\n", out.string().c_str());
                if (!o->png.empty()) {
                    std::filesystem::path png(o->png);
                    if (png.has_parent_path()) std::filesystem::create_directories(png.parent_path());
                    image::writePng(png, img);
                    std::printf("%s\n", png.string().c_str());
                }
                std::fprintf(stderr, "generate: %u rays in %.3f ms of device time on %s\n", count, ms,
                             context.info().name.c_str());
                return 0;
            });
        };
    });
}

}  // namespace vkpath::app
