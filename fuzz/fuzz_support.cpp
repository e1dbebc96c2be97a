#include "fuzz_support.h"

#include <cxxabi.h>
#include <fcntl.h>
#include <fmt/format.h>
#include <sys/inotify.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <memory>
#include <span>
#include <typeinfo>

#include "input_error.h"
#include "scene/camera.h"
#include "scene/tangents.h"

namespace vkpath::fuzz {
namespace {

namespace fs = std::filesystem;

struct State {
    fs::path root, scene, outside;
    fs::path lastInput;  // removed when the next input has another name
    int watch = -1;      // inotify descriptor watching outside/
    FILE* report = stderr;
    bool verbose = false;  // VKPATH_FUZZ_VERBOSE=1: print every InputError's message
};

State& state() {
    static State s;
    return s;
}

void removeFolder() {
    std::error_code ec;
    if (!state().root.empty()) fs::remove_all(state().root, ec);
}

void writeFile(const fs::path& path, const void* data, size_t size) {
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
    if (fd < 0)
        finding(fmt::format("harness: cannot create {}: {}", path.string(), strerror(errno)));
    const auto* bytes = static_cast<const uint8_t*>(data);
    while (size > 0) {
        const ssize_t n = ::write(fd, bytes, size);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) finding(fmt::format("harness: cannot write {}", path.string()));
        bytes += n;
        size -= size_t(n);
    }
    ::close(fd);
}

// Any open of outside/ or a file in it since the last call.
void checkNothingOutsideWasOpened() {
    alignas(inotify_event) std::array<char, 4096> buffer;
    const ssize_t n = ::read(state().watch, buffer.data(), buffer.size());
    if (n <= 0) return;  // EAGAIN: no events
    const auto* event = reinterpret_cast<const inotify_event*>(buffer.data());
    const std::string name = event->len > 0 ? event->name : "";
    finding(fmt::format("the loader opened {}, outside the scene's folder",
                        (state().outside / name).string()));
}

std::string demangledTypeName(const std::type_info& type) {
    int status = 0;
    std::unique_ptr<char, void (*)(void*)> name(
        abi::__cxa_demangle(type.name(), nullptr, nullptr, &status), std::free);
    return status == 0 && name ? name.get() : type.name();
}

bool finite(const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// The tangents the renderer generates for a normal-mapped mesh without
// TANGENT (host/scene/tangents, as wavefront/surface_tables calls it), on
// whatever positions, normals and texture coordinates the file holds: unit,
// finite, w = +-1, every triangle over the generated vertices, every vertex
// a copy of one of the mesh's.
void checkTangents(const scene::Mesh& mesh, const scene::Material& material) {
    const size_t n = mesh.positions.size();
    const std::vector<glm::vec2>& uvs =
        material.normalTexture.texCoord == 0 ? mesh.texcoords0 : mesh.texcoords1;
    if (!material.normalTexture.present() || n == 0 || uvs.size() != n) return;
    const std::span<const glm::vec3> normals = mesh.normals.size() == n
                                                   ? std::span<const glm::vec3>(mesh.normals)
                                                   : std::span<const glm::vec3>();
    const scene::MeshTangents t =
        scene::generateTangents(mesh.positions, normals, uvs, mesh.triangles);
    if (t.tangents.size() != t.sourceVertex.size() || t.tangents.size() < n ||
        t.triangles.size() != mesh.triangles.size())
        finding(fmt::format("mesh '{}': generated tangents of inconsistent sizes", mesh.name));
    for (size_t v = 0; v < t.tangents.size(); ++v) {
        const glm::vec4& tangent = t.tangents[v];
        const float length = glm::length(glm::vec3(tangent));
        if (!finite(glm::vec3(tangent)) || std::abs(length - 1.0f) > 1e-3f ||
            (tangent.w != 1.0f && tangent.w != -1.0f) || t.sourceVertex[v] >= n)
            finding(
                fmt::format("mesh '{}': generated tangent {} is not a unit vector with w = +-1 "
                            "of a mesh vertex",
                            mesh.name, v));
    }
    for (const glm::uvec3& tri : t.triangles)
        if (glm::any(glm::greaterThanEqual(tri, glm::uvec3(uint32_t(t.tangents.size())))))
            finding(fmt::format("mesh '{}': a triangle past the generated tangents", mesh.name));
}

bool finiteNonNegative(const glm::vec3& v) {
    return finite(v) && v.x >= 0.0f && v.y >= 0.0f && v.z >= 0.0f;
}

}  // namespace

void writeBufferBin(const fs::path& path) {
    std::array<uint8_t, BUFFER_BYTES> bytes{};
    const float positions[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const uint16_t indices[3] = {0, 1, 2};
    std::memcpy(bytes.data() + BUFFER_POSITIONS_OFFSET, positions, sizeof(positions));
    std::memcpy(bytes.data() + BUFFER_INDICES_OFFSET, indices, sizeof(indices));
    writeFile(path, bytes.data(), bytes.size());
}

void initialize() {
    State& s = state();
    // Findings go to the stderr the process started with, which libFuzzer's
    // -close_fd_mask=2 (set later, after LLVMFuzzerInitialize) leaves open.
    if (const int fd = ::dup(STDERR_FILENO); fd >= 0)
        if (FILE* file = ::fdopen(fd, "w")) {
            std::setvbuf(file, nullptr, _IONBF, 0);
            s.report = file;
        }

    const char* verbose = std::getenv("VKPATH_FUZZ_VERBOSE");
    s.verbose = verbose && std::string_view(verbose) == "1";

    std::error_code ec;
    const char* tmp = std::getenv("TMPDIR");
    const fs::path base = tmp && *tmp ? fs::path(tmp) : fs::temp_directory_path(ec);
    std::string pattern = (base / "vkpath-fuzz-XXXXXX").string();
    if (!::mkdtemp(pattern.data()))
        finding(fmt::format("harness: cannot create {}: {}", pattern, strerror(errno)));
    s.root = pattern;
    s.scene = s.root / "scene";
    s.outside = s.root / "outside";
    std::atexit(removeFolder);
    fs::create_directory(s.scene);
    fs::create_directory(s.outside);
    writeBufferBin(s.scene / "buffer.bin");
    // 2 x 2 RGB, 8-bit: red, green, blue, white.
    static const uint8_t png[] = {
        0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44,
        0x52, 0x00, 0x00, 0x00, 0x02, 0x00, 0x00, 0x00, 0x02, 0x08, 0x02, 0x00, 0x00, 0x00, 0xfd,
        0xd4, 0x9a, 0x73, 0x00, 0x00, 0x00, 0x12, 0x49, 0x44, 0x41, 0x54, 0x78, 0xda, 0x63, 0xf8,
        0xcf, 0xc0, 0xc0, 0x00, 0xc2, 0x0c, 0xff, 0x81, 0x00, 0x00, 0x1f, 0xee, 0x05, 0xfb, 0xf1,
        0xab, 0xba, 0x77, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82};
    writeFile(s.scene / TEXTURE_PNG, png, sizeof(png));
    writeBufferBin(s.outside / "buffer.bin");
    const std::string secret = "not the scene's\n";
    writeFile(s.outside / "secret.txt", secret.data(), secret.size());
    fs::create_symlink("../outside/buffer.bin", s.scene / "escape.bin");
    fs::create_directory_symlink("../outside", s.scene / "escape_dir");

    s.watch = ::inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
    if (s.watch < 0 || ::inotify_add_watch(s.watch, s.outside.c_str(), IN_OPEN | IN_ACCESS) < 0)
        finding(fmt::format("harness: cannot watch {}: {}", s.outside.string(), strerror(errno)));
}

fs::path writeInput(std::string_view name, const uint8_t* data, size_t size) {
    State& s = state();
    const fs::path path = s.scene / name;
    // Only this input in the folder, so a crash reproduces from its bytes alone.
    if (!s.lastInput.empty() && s.lastInput != path) {
        std::error_code ec;
        fs::remove(s.lastInput, ec);
    }
    writeFile(path, data, size);
    s.lastInput = path;
    return path;
}

void run(const std::function<void()>& load) {
    try {
        load();
    } catch (const InputError& e) {
        // The expected refusal of a bad input.
        if (state().verbose) std::fprintf(state().report, "InputError: %s\n", e.what());
    } catch (const std::exception& e) {
        finding(fmt::format("{} escaped the loader (only vkpath::InputError may): {}",
                            demangledTypeName(typeid(e)), e.what()));
    } catch (...) {
        finding("an exception that is not a std::exception escaped the loader");
    }
    checkNothingOutsideWasOpened();
}

void finding(const std::string& what) {
    std::fprintf(state().report, "vkpath fuzz finding: %s\n", what.c_str());
    std::abort();
}

void checkScene(const scene::Scene& s) {
    const size_t materials = s.materials.size();
    for (const scene::Material& m : s.materials)
        if (!finiteNonNegative(m.reflectance) || !finiteNonNegative(m.transmittance) ||
            !finiteNonNegative(m.emission) || !std::isfinite(m.ior) || !(m.ior > 0.0f) ||
            !finiteNonNegative(m.specularColor) || !finiteNonNegative(m.conductorEta) ||
            !finiteNonNegative(m.conductorK))
            finding(fmt::format("material '{}' has a negative or non-finite value", m.name));
    // The microfacet kinds' parameters are fractions (shared/bsdf.h reads them unchecked).
    for (const scene::Material& m : s.materials)
        if (!(m.roughness >= 0.0f && m.roughness <= 1.0f) ||
            !(m.metallic >= 0.0f && m.metallic <= 1.0f) ||
            !(m.specular >= 0.0f && m.specular <= 1.0f))
            finding(fmt::format("material '{}': roughness, metallic or specular outside [0, 1]",
                                m.name));
    // Instances place instanced meshes only, with finite transforms; an
    // instanced mesh is placed by some instance and emits no light.
    std::vector<uint8_t> placed(s.meshes.size(), 0);
    for (const scene::Instance& instance : s.instances) {
        if (uint64_t(instance.firstMesh) + instance.meshCount > s.meshes.size() ||
            instance.meshCount == 0) {
            finding(fmt::format("instance '{}': meshes out of range", instance.name));
            continue;
        }
        for (uint32_t m = instance.firstMesh; m < instance.firstMesh + instance.meshCount; ++m) {
            placed[m] = 1;
            if (!s.meshes[m].instanced)
                finding(fmt::format("instance '{}' places mesh '{}', which is not instanced",
                                    instance.name, s.meshes[m].name));
        }
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r)
                if (!std::isfinite(instance.objectToWorld[c][r]))
                    finding(fmt::format("instance '{}': a transform entry is not finite",
                                        instance.name));
    }
    for (size_t m = 0; m < s.meshes.size(); ++m) {
        const scene::Mesh& mesh = s.meshes[m];
        if (mesh.instanced && !placed[m])
            finding(fmt::format("mesh '{}' is instanced and placed by no instance", mesh.name));
        if (mesh.instanced && mesh.material < materials && s.materials[mesh.material].emissive())
            finding(fmt::format("mesh '{}' is instanced and emissive", mesh.name));
    }
    for (const scene::Mesh& mesh : s.meshes) {
        if (mesh.material >= materials)
            finding(
                fmt::format("mesh '{}': material {} of {}", mesh.name, mesh.material, materials));
        if (!mesh.normals.empty() && mesh.normals.size() != mesh.positions.size())
            finding(fmt::format("mesh '{}': {} normals for {} positions", mesh.name,
                                mesh.normals.size(), mesh.positions.size()));
        for (const glm::vec3& p : mesh.positions)
            if (!finite(p)) finding(fmt::format("mesh '{}': a position is not finite", mesh.name));
        for (const glm::vec3& n : mesh.normals)
            if (!finite(n)) finding(fmt::format("mesh '{}': a normal is not finite", mesh.name));
        // The other per-vertex attributes: one per vertex or none, and usable
        // as the scene model defines them.
        auto perVertex = [&](size_t count, const char* what) {
            if (count != 0 && count != mesh.positions.size())
                finding(fmt::format("mesh '{}': {} {} for {} positions", mesh.name, count, what,
                                    mesh.positions.size()));
        };
        perVertex(mesh.texcoords0.size(), "texcoords0");
        perVertex(mesh.texcoords1.size(), "texcoords1");
        perVertex(mesh.colors.size(), "colours");
        perVertex(mesh.tangents.size(), "tangents");
        for (const auto* uvs : {&mesh.texcoords0, &mesh.texcoords1})
            for (const glm::vec2& uv : *uvs)
                if (!std::isfinite(uv.x) || !std::isfinite(uv.y))
                    finding(
                        fmt::format("mesh '{}': a texture coordinate is not finite", mesh.name));
        for (const glm::vec4& c : mesh.colors)
            if (!(glm::all(glm::greaterThanEqual(c, glm::vec4(0.0f))) &&
                  glm::all(glm::lessThanEqual(c, glm::vec4(1.0f)))))
                finding(fmt::format("mesh '{}': a colour is not in [0, 1]", mesh.name));
        for (const glm::vec4& t : mesh.tangents)
            if (!finite(glm::vec3(t)) || std::abs(glm::length(glm::vec3(t)) - 1.0f) > 1e-3f ||
                (t.w != 1.0f && t.w != -1.0f))
                finding(fmt::format("mesh '{}': a tangent is not a unit vector with w = +-1",
                                    mesh.name));
        for (const glm::uvec3& t : mesh.triangles)
            for (int k = 0; k < 3; ++k)
                if (t[k] >= mesh.positions.size())
                    finding(fmt::format("mesh '{}': index {} of {} positions", mesh.name, t[k],
                                        mesh.positions.size()));
        if (mesh.material < materials) checkTangents(mesh, s.materials[mesh.material]);
    }
    for (const scene::Sphere& sphere : s.spheres) {
        if (sphere.material >= materials)
            finding(fmt::format("sphere '{}': material {} of {}", sphere.name, sphere.material,
                                materials));
        if (!finite(sphere.center) || !std::isfinite(sphere.radius) || !(sphere.radius > 0.0f))
            finding(
                fmt::format("sphere '{}': centre or radius not finite and positive", sphere.name));
    }
    for (const scene::PointLight& l : s.pointLights)
        if (!finite(l.position) || !finiteNonNegative(l.intensity))
            finding("a point light is not finite");
    for (const scene::SpotLight& l : s.spotLights)
        if (!finite(l.position) || !finite(l.direction) || !finiteNonNegative(l.intensity) ||
            !std::isfinite(l.innerConeAngle) || !std::isfinite(l.outerConeAngle))
            finding("a spot light is not finite");
    for (const scene::DirectionalLight& l : s.directionalLights)
        if (!finite(l.direction) || !finiteNonNegative(l.irradiance))
            finding("a directional light is not finite");
    (void)s.features();  // Material::at on every used index
    if (!finite(s.camera.position) || !finite(s.camera.target) || !finite(s.camera.up))
        finding(fmt::format("camera '{}' is not finite", s.camera.name));
    // May refuse a degenerate camera with InputError, as `vkpath render` would.
    const shared::Camera gpu = scene::makeGpuCamera(s.camera, 64, 48);
    if (!finite(gpu.origin) || !finite(gpu.forward) || !finite(gpu.right) || !finite(gpu.up))
        finding(fmt::format("camera '{}' makes a non-finite GPU camera", s.camera.name));
}

}  // namespace vkpath::fuzz
