"""The Python package (python/vkpath), as `make test` installs it
(tools/python-package): renders into numpy arrays equal to the command line's,
a scene loaded once and rendered many times, the stops and the progress
callback, compare and the z-test, the shared routines over arrays (a
chi-square of one BSDF with SciPy) and bad input as Python exceptions.

Run with the validation layers on (VKPATH_VALIDATION=1, as `make test` does):
a validation message raises RuntimeError and fails the test."""

import os
import shutil
import signal
import subprocess
import threading
import time
from pathlib import Path

import numpy as np
import pytest
import scipy.stats

import vkpath

ROOT = Path(__file__).resolve().parents[2]
BINARY = Path(os.environ.get("VKPATH_BINARY", ROOT / "build" / "vkpath"))
BOX = ROOT / "assets" / "cornell_box.gltf"
# Small and quick: 48x32 pixels, 4 bounces.
SMALL = dict(size=(48, 32), max_depth=4)


def cli_render(tmp_path, *flags):
    out = tmp_path / "cli.exr"
    subprocess.run(
        [str(BINARY), "render", str(BOX), "-o", str(out), *flags],
        check=True,
        capture_output=True,
    )
    return vkpath.read_exr(out)


@pytest.mark.parametrize("device", ["cpu", "gpu"])
def test_render_equals_the_command_lines_image_bit_for_bit(tmp_path, device):
    cli = cli_render(tmp_path, "-d", "48x32", "-m", "4", "-s", "8", "--seed", "3",
                     "--device", device)
    image = vkpath.render(BOX, spp=8, seed=3, device=device, **SMALL)
    assert image.dtype == np.float32 and image.shape == (32, 48, 3)
    assert np.array_equal(image, cli)


def test_keywords_keep_the_flags_defaults(tmp_path):
    # No keyword but the size: the command's defaults (16 spp, depth 8, sobol, seed 0).
    cli = cli_render(tmp_path, "-d", "40x30", "--device", "cpu")
    assert np.array_equal(vkpath.render(BOX, size=(40, 30), device="cpu"), cli)


def test_fog_is_a_scene_keyword_with_the_command_lines_bits(tmp_path):
    cli = cli_render(tmp_path, "-d", "24x16", "-m", "3", "-s", "4", "--device", "cpu",
                     "--fog-density", "0.5,0.6,0.7", "--fog-albedo", "0.9", "--fog-anisotropy", "0.25")
    image = vkpath.render(BOX, size=(24, 16), max_depth=3, spp=4, device="cpu",
                          fog_density=(0.5, 0.6, 0.7), fog_albedo=0.9, fog_anisotropy=0.25)
    assert np.array_equal(image, cli)
    assert not np.array_equal(image, vkpath.render(BOX, size=(24, 16), max_depth=3, spp=4, device="cpu"))


def test_a_scene_renders_many_times_without_reloading():
    scene = vkpath.Scene(BOX)
    first = scene.render(spp=4, seed=1, device="cpu", **SMALL)
    other_seed = scene.render(spp=4, seed=2, device="cpu", **SMALL)
    again = scene.render(spp=4, seed=1, device="cpu", **SMALL)
    assert not np.array_equal(first.image, other_seed.image)
    assert np.array_equal(first.image, again.image)
    # The GPU renders the same scene object too.
    gpu = scene.render(spp=4, seed=1, device="gpu", **SMALL)
    assert gpu.image.shape == first.image.shape


def test_a_scene_needs_its_file_only_to_load(tmp_path):
    copy = tmp_path / "box.gltf"
    shutil.copy(BOX, copy)
    scene = vkpath.Scene(copy)
    first = scene.render(spp=2, device="cpu", **SMALL).image
    copy.unlink()  # a reload would fail now
    assert np.array_equal(scene.render(spp=2, device="cpu", **SMALL).image, first)


def test_the_gil_is_released_while_rendering():
    counted = []

    def count():
        while not counted or counted[-1] is not None:
            counted.append(len(counted))
            time.sleep(0.001)

    scene = vkpath.Scene(BOX)
    counter = threading.Thread(target=count)
    counter.start()
    try:
        made = scene.render(spp=32, device="cpu", size=(160, 120), max_depth=8)
    finally:
        during = len(counted)
        counted.append(None)
        counter.join()
    # The other thread ran while the render held no GIL: at least one step per
    # 10 ms of rendering (it sleeps 1 ms per step).
    assert during >= made.seconds * 100, (during, made.seconds)


def test_a_camera_set_from_python_moves_the_view_and_back():
    scene = vkpath.Scene(BOX)
    original = scene.camera
    before = scene.render(spp=2, device="cpu", **SMALL).image
    position = np.array(original["position"])
    target = np.array(original["target"])
    scene.set_camera(position + 0.5 * (target - position), target, original["up"], original["fov"],
                     original["aspect"])
    closer = scene.render(spp=2, device="cpu", **SMALL).image
    assert not np.array_equal(before, closer)
    scene.set_camera(**original)
    assert np.array_equal(scene.render(spp=2, device="cpu", **SMALL).image, before)


def test_a_checkpoint_names_the_camera_it_was_rendered_from(tmp_path):
    scene = vkpath.Scene(BOX)
    checkpoint = tmp_path / "box.ckpt"
    scene.render(spp=2, device="cpu", checkpoint=checkpoint, **SMALL)
    camera = scene.camera
    camera["fov"] = camera["fov"] * 0.5
    scene.set_camera(**camera)
    with pytest.raises(ValueError, match="camera"):
        scene.render(spp=4, device="cpu", resume=checkpoint, **SMALL)


def test_a_checkpoint_resumed_from_python_equals_the_whole_render(tmp_path):
    scene = vkpath.Scene(BOX)
    checkpoint = tmp_path / "box.ckpt"
    scene.render(spp=4, device="cpu", checkpoint=checkpoint, **SMALL)
    resumed = scene.render(spp=8, device="cpu", resume=checkpoint, **SMALL)
    whole = scene.render(spp=8, device="cpu", **SMALL)
    assert np.array_equal(resumed.image, whole.image)


@pytest.mark.parametrize("device", ["cpu", "gpu"])
def test_aovs_shapes_types_and_the_command_lines_bits(tmp_path, device):
    image, aovs = vkpath.render(BOX, spp=4, device=device,
                                aov=["variance", "spp", "albedo", "normal"], **SMALL)
    assert image.shape == (32, 48, 3)
    for name in ("variance", "albedo", "normal"):
        assert aovs[name].shape == (32, 48, 3) and aovs[name].dtype == np.float32, name
    assert aovs["spp"].shape == (32, 48) and np.all(aovs["spp"] == 4)
    assert np.all(aovs["variance"] >= 0)
    assert np.all((aovs["albedo"] >= 0) & (aovs["albedo"] <= 1))
    assert np.all(np.linalg.norm(aovs["normal"], axis=-1) <= 1 + 1e-5)
    cli_render(tmp_path, "-d", "48x32", "-m", "4", "-s", "4", "--device", device,
               "--aov", "albedo,normal")
    for name in ("albedo", "normal"):
        assert np.array_equal(aovs[name], vkpath.read_exr(tmp_path / f"cli.{name}.exr")), name


def oidn_library():
    """The library tools/oidn-venv installs beside the vkpath under test, or
    VKPATH_OIDN_LIBRARY's; None when neither is there."""
    if os.environ.get("VKPATH_OIDN_LIBRARY"):
        return os.environ["VKPATH_OIDN_LIBRARY"]
    found = sorted(BINARY.parent.glob("oidn-venv/lib/python*/site-packages/pyoidn/oidn/lib/"
                                      "libOpenImageDenoise.so.2"))
    return str(found[0]) if found else None


def test_denoise_returns_the_guided_denoised_image(monkeypatch):
    library = oidn_library()
    if library is None:
        pytest.skip("no Open Image Denoise (tools/oidn-venv could not install PyPI's pyoidn)")
    monkeypatch.setenv("VKPATH_OIDN_LIBRARY", library)
    scene = vkpath.Scene(BOX)
    made = scene.render(spp=16, device="cpu", denoise=True, **SMALL)
    assert made.denoised.shape == made.image.shape and np.all(np.isfinite(made.denoised))
    assert made.aovs == {}  # the guides were rendered for the denoiser, not asked for
    reference = scene.render(spp=1024, seed=7, device="cpu", **SMALL).image
    assert (vkpath.compare(made.denoised, reference)["rel_mse"]
            < vkpath.compare(made.image, reference)["rel_mse"])


def test_files_are_written_only_where_output_is_given(tmp_path):
    os.chdir(tmp_path)
    vkpath.render(BOX, spp=1, device="cpu", png="preview.png", **SMALL)
    assert not any(tmp_path.iterdir())
    vkpath.render(BOX, spp=1, device="cpu", output=tmp_path / "a.exr", **SMALL)
    assert (tmp_path / "a.exr").is_file()


def test_a_target_error_and_a_time_budget_stop_the_render():
    made = vkpath.Scene(BOX).render(target_error=0.05, device="cpu", **SMALL)
    assert made.reached_target and made.estimated_rel_mse <= 0.05
    budget = vkpath.Scene(BOX).render(time_budget=0.5, spp=100000, device="cpu", **SMALL)
    assert 1 <= budget.spp_reached < 100000


def test_progress_is_called_and_its_exception_stops_the_render():
    seen = []
    vkpath.render(BOX, spp=8, device="gpu", paths_in_flight=48 * 32, progress=seen.append, **SMALL)
    assert seen and seen[-1]["spp"] == 8
    assert [p["spp"] for p in seen] == sorted(p["spp"] for p in seen)

    def refuse(progress):
        raise ArithmeticError("enough")

    with pytest.raises(ArithmeticError, match="enough"):
        vkpath.render(BOX, spp=64, device="gpu", paths_in_flight=48 * 32, progress=refuse, **SMALL)


def test_ctrl_c_stops_at_the_next_whole_sample_with_the_image_so_far():
    def interrupt(progress):
        os.kill(os.getpid(), signal.SIGINT)

    made = vkpath.Scene(BOX).render(spp=64, device="gpu", paths_in_flight=48 * 32,
                                     progress=interrupt, **SMALL)
    assert made.interrupted and made.stopped
    assert 1 <= made.spp_reached < 64
    assert np.all(np.isfinite(made.image))


def test_compare_and_z_test_on_arrays_and_files(tmp_path):
    a = vkpath.Scene(BOX).render(spp=16, seed=1, device="cpu", **SMALL)
    b = vkpath.Scene(BOX).render(spp=16, seed=2, device="cpu", **SMALL)
    assert vkpath.compare(a.image, a.image)["rel_mse"] == 0
    measured = vkpath.compare(a.image, b.image)
    assert measured["rel_mse"] > 0 and len(measured["channels"]) == 3
    # Two seeds of one image: the same image at 1% (deterministic renders, so
    # this outcome is fixed; it is what `vkpath compare --ztest` says of them).
    assert vkpath.z_test(a.image, b.image, a.variance, b.variance)["same"]
    vkpath.render(BOX, spp=16, seed=1, device="cpu", output=tmp_path / "a.exr",
                  aov="variance", **SMALL)
    vkpath.render(BOX, spp=16, seed=2, device="cpu", output=tmp_path / "b.exr",
                  aov="variance", **SMALL)
    from_files = vkpath.z_test(tmp_path / "a.exr", tmp_path / "b.exr")
    assert from_files["same"] and from_files["blocks"] == 6 * 4
    assert vkpath.compare(tmp_path / "a.exr", b.image)["rel_mse"] == measured["rel_mse"]


def test_scene_info_is_scene_infos_json():
    info = vkpath.Scene(BOX).info()
    printed = subprocess.run([str(BINARY), "scene-info", str(BOX), "--json"], check=True,
                             capture_output=True, text=True).stdout
    import json

    assert info == json.loads(printed)


def test_instancing_is_a_scene_keyword_and_keeps_the_image():
    path = ROOT / "assets" / "instances.gltf"
    instanced, copied = vkpath.Scene(path, instancing="on"), vkpath.Scene(path)
    assert instanced.info()["instances"] == 30 and copied.info()["instances"] == 0
    assert instanced.info()["drawnTriangles"] == copied.info()["drawnTriangles"]
    a = instanced.render(size=(32, 24), spp=4).image
    b = copied.render(size=(32, 24), spp=4).image
    # The same image up to rounding (tests/render/instancing_render_test.cpp bounds it).
    assert vkpath.compare(a, b)["rel_mse"] < 1e-3
    with pytest.raises(ValueError, match="instancing"):
        vkpath.Scene(path, instancing="sometimes")


def test_a_material_variant_is_a_scene_keyword(tmp_path):
    """The dark triangle made red, with a variant "green" (KHR_materials_variants)."""
    import json

    path = dark_triangle(tmp_path)
    gltf = json.loads(path.read_text())
    diffuse = {"KHR_materials_specular": {"specularFactor": 0}}  # Lambertian (docs/SCENES.md)
    gltf["materials"] = [
        {"pbrMetallicRoughness": {"baseColorFactor": [1, 0, 0, 1], "metallicFactor": 0}, "extensions": diffuse},
        {"pbrMetallicRoughness": {"baseColorFactor": [0, 1, 0, 1], "metallicFactor": 0}, "extensions": diffuse},
    ]
    primitive = gltf["meshes"][0]["primitives"][0]
    primitive["material"] = 0
    primitive["extensions"] = {"KHR_materials_variants": {"mappings": [{"material": 1, "variants": [0]}]}}
    gltf["extensions"] = {"KHR_materials_variants": {"variants": [{"name": "green"}]}}
    path.write_text(json.dumps(gltf))
    sky = (1, 1, 1)
    own, green = vkpath.Scene(path, env_color=sky), vkpath.Scene(path, env_color=sky, variant="green")
    assert own.info()["materialVariants"] == ["green"]
    a = own.render(size=(8, 8), spp=2).image[..., :3].reshape(-1, 3).sum(axis=0)
    b = green.render(size=(8, 8), spp=2).image[..., :3].reshape(-1, 3).sum(axis=0)
    # The white sky behind adds to every channel; the triangle to its colour's.
    assert a[0] - a[1] > 5 and b[1] - b[0] > 5
    with pytest.raises(ValueError, match="no material variant named 'blue'"):
        vkpath.Scene(path, variant="blue")


# ---- the shared routines over arrays -----------------------------------------------------


def sphere_directions(count, rng):
    v = rng.normal(size=(count, 3)).astype(np.float32)
    return v / np.linalg.norm(v, axis=1, keepdims=True)


@pytest.mark.parametrize("device", ["gpu", "cpu"])
def test_a_rough_conductor_chi_square_from_python(device):
    """Mitsuba's ChiSquareTest in a few lines of SciPy: sampleBsdf's directions
    binned in (cos theta, phi) against bsdfPdf integrated over each bin."""
    material = dict(kind="conductor", reflectance=(0.9, 0.6, 0.3), roughness=0.6)
    wo = np.array([0.48, 0.0, 0.877], np.float32)
    wo /= np.linalg.norm(wo)
    rng = np.random.default_rng(7)
    count = 200_000
    s = vkpath.bsdf_sample(material, wo, rng.random((count, 3), np.float32), device=device)
    valid = s["valid"] == 1
    d = s["direction"][valid]
    cos_bins, phi_bins = 16, 32
    observed, _, _ = np.histogram2d(d[:, 2], np.arctan2(d[:, 1], d[:, 0]),
                                    bins=(cos_bins, phi_bins), range=((-1, 1), (-np.pi, np.pi)))
    # The density integrated over each bin: 8 x 8 midpoints per bin (solid angle
    # d(cos) d(phi) per point).
    sub = 8
    c = -1 + (np.arange(cos_bins * sub) + 0.5) * 2 / (cos_bins * sub)
    p = -np.pi + (np.arange(phi_bins * sub) + 0.5) * 2 * np.pi / (phi_bins * sub)
    cc, pp = np.meshgrid(c, p, indexing="ij")
    sin = np.sqrt(1 - cc**2)
    wi = np.stack([sin * np.cos(pp), sin * np.sin(pp), cc], axis=-1).reshape(-1, 3)
    density = vkpath.bsdf_pdf(material, wo, wi, device="cpu").astype(np.float64)
    density = density.reshape(cos_bins * sub, phi_bins * sub)
    cell = (2 / (cos_bins * sub)) * (2 * np.pi / (phi_bins * sub))
    expected = density.reshape(cos_bins, sub, phi_bins, sub).sum(axis=(1, 3)) * cell * count
    # Bins expected below 5 are pooled (the chi-square approximation's rule).
    small = expected < 5
    assert observed[expected == 0].sum() == 0  # no sample where the density is 0
    obs, exp = observed[~small], expected[~small]
    if expected[small].sum() > 0:
        obs = np.append(obs, observed[small].sum())
        exp = np.append(exp, expected[small].sum())
    exp *= obs.sum() / exp.sum()  # the pdf's mass outside valid samples is the test's, not SciPy's
    assert abs(expected.sum() / count - valid.mean()) < 0.01  # the density integrates to the valid share
    p_value = scipy.stats.chisquare(obs, exp).pvalue
    assert p_value > 0.01, p_value


@pytest.mark.parametrize("kind", vkpath.MATERIAL_KINDS)
def test_every_kinds_routines_agree_between_gpu_and_cpu(kind):
    rng = np.random.default_rng(3)
    wo = sphere_directions(1000, rng)
    wo[:, 2] = np.abs(wo[:, 2])
    wi = sphere_directions(1000, rng)
    u = rng.random((1000, 3), np.float32)
    material = dict(kind=kind, roughness=0.4, metallic=0.5, ior=1.5)
    gpu = vkpath.bsdf_sample(material, wo, u, device="gpu")
    cpu = vkpath.bsdf_sample(material, wo, u, device="cpu")
    assert np.array_equal(gpu["valid"], cpu["valid"]) and np.array_equal(gpu["delta"], cpu["delta"])
    for key in ("direction", "weight", "pdf", "eval", "eval_pdf"):
        np.testing.assert_allclose(gpu[key], cpu[key], rtol=2e-4, atol=1e-5, err_msg=key)
    np.testing.assert_allclose(vkpath.bsdf_eval(material, wo, wi, device="gpu"),
                               vkpath.bsdf_eval(material, wo, wi, device="cpu"), rtol=2e-4, atol=1e-6)


def test_the_samplers_agree_between_gpu_and_cpu():
    gpu = vkpath.sampler_values("sobol", samples=64, dimensions=4, pixels=3, seed=5, device="gpu")
    cpu = vkpath.sampler_values("sobol", samples=64, dimensions=4, pixels=3, seed=5, device="cpu")
    assert gpu.shape == (64, 4, 3) and np.array_equal(gpu, cpu)


def test_a_lambertian_evaluates_to_albedo_cos_over_pi():
    wo = np.array([0, 0, 1], np.float32)
    wi = np.array([[0.6, 0, 0.8]], np.float32)
    f = vkpath.bsdf_eval(dict(kind="diffuse", reflectance=(0.5, 0.25, 1.0)), wo, wi, device="cpu")
    np.testing.assert_allclose(f[0], np.array([0.5, 0.25, 1.0]) * 0.8 / np.pi, rtol=1e-6)


def chi_square_of_directions(directions, density, count, cos_bins=16, phi_bins=32, sub=8):
    """The p-value of `directions` (M, 3) drawn from `density` (a function of
    (K, 3) unit directions, the density per steradian, integrating to M /
    count over the sphere), binned in (cos theta, phi)."""
    observed, _, _ = np.histogram2d(directions[:, 2], np.arctan2(directions[:, 1], directions[:, 0]),
                                    bins=(cos_bins, phi_bins), range=((-1, 1), (-np.pi, np.pi)))
    c = -1 + (np.arange(cos_bins * sub) + 0.5) * 2 / (cos_bins * sub)
    p = -np.pi + (np.arange(phi_bins * sub) + 0.5) * 2 * np.pi / (phi_bins * sub)
    cc, pp = np.meshgrid(c, p, indexing="ij")
    sin = np.sqrt(1 - cc**2)
    wi = np.stack([sin * np.cos(pp), sin * np.sin(pp), cc], axis=-1).reshape(-1, 3)
    values = np.asarray(density(wi), np.float64).reshape(cos_bins * sub, phi_bins * sub)
    cell = (2 / (cos_bins * sub)) * (2 * np.pi / (phi_bins * sub))
    expected = values.reshape(cos_bins, sub, phi_bins, sub).sum(axis=(1, 3)) * cell * count
    assert observed[expected == 0].sum() == 0  # no sample where the density is 0
    small = expected < 5  # pooled: the chi-square approximation's rule
    obs, exp = observed[~small], expected[~small]
    if expected[small].sum() > 0:
        obs = np.append(obs, observed[small].sum())
        exp = np.append(exp, expected[small].sum())
    exp *= obs.sum() / exp.sum()
    return expected.sum() / count, scipy.stats.chisquare(obs, exp).pvalue


@pytest.mark.parametrize("device", ["gpu", "cpu"])
def test_environment_sampling_chi_square_from_python(tmp_path, device):
    """An environment map's importance sampling (an alias table over its
    texels): its directions against the density environment() reports. The
    map (64 x 32, a smooth sky brighter toward one side and up) is coarse
    enough that 8 x 8 midpoints per bin integrate its piecewise-constant
    density to a fraction of the test's resolution."""
    v, u = np.meshgrid((np.arange(32) + 0.5) / 32, (np.arange(64) + 0.5) / 64, indexing="ij")
    sky = 0.2 + 4 * np.cos(np.pi * v / 2) ** 4 + 2 * (1 + np.cos(2 * np.pi * u)) * np.sin(np.pi * v)
    sky_path = tmp_path / "sky.exr"
    vkpath.write_exr(sky_path, np.stack([sky, 0.8 * sky, 0.6 * sky], axis=-1))
    scene = vkpath.Scene(dark_triangle(tmp_path), env=sky_path)
    count = 100_000
    s = scene.sample_lights(np.zeros((count, 3)), seed=4, device=device)
    assert np.all(s["distance"] > 1e30) and np.all(s["choice"] == 1)  # the sky is the only light
    _, pdf = scene.environment(s["direction"], device=device)
    np.testing.assert_allclose(pdf, s["pdf"], rtol=1e-4)  # the sample's own density, looked up
    mass, p_value = chi_square_of_directions(
        s["direction"], lambda w: scene.environment(w, device="cpu")[1], count)
    assert abs(mass - 1) < 0.005  # the density integrates to 1 over the sphere
    assert p_value > 0.01, p_value


def test_light_samples_agree_between_gpu_and_cpu():
    scene = vkpath.Scene(BOX)
    rng = np.random.default_rng(2)
    points = rng.uniform(-0.5, 0.5, size=(2000, 3)).astype(np.float32)
    gpu = scene.sample_lights(points, seed=9, device="gpu")
    cpu = scene.sample_lights(points, seed=9, device="cpu")
    assert np.array_equal(gpu["light"], cpu["light"])
    for key in ("direction", "radiance", "pdf", "distance", "choice"):
        np.testing.assert_allclose(gpu[key], cpu[key], rtol=1e-4, atol=1e-6, err_msg=key)
    assert np.all(cpu["pdf"] > 0) and np.all(cpu["choice"] > 0)


# ---- bad input ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    "keywords, message",
    [
        (dict(spp=0), "--spp"),
        (dict(size="wide"), "--size"),
        (dict(sampler="halton"), "--sampler"),
        (dict(no_such_flag=1), "--no-such-flag"),
        (dict(kernel="megakernel", device="cpu"), "--kernel"),
    ],
)
def test_bad_keywords_raise_the_command_lines_message(keywords, message):
    with pytest.raises(ValueError, match=message):
        vkpath.render(BOX, **keywords)


def dark_triangle(folder):
    """A glTF of one triangle and nothing that emits."""
    import base64
    import json

    positions = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32)
    data = base64.b64encode(positions.tobytes()).decode()
    gltf = {
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 0]}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64," + data}],
    }
    path = folder / "dark.gltf"
    path.write_text(json.dumps(gltf))
    return path


def test_bad_input_is_a_python_exception(tmp_path):
    with pytest.raises(ValueError, match="missing.gltf"):
        vkpath.Scene(tmp_path / "missing.gltf")
    broken = tmp_path / "broken.gltf"
    broken.write_text("{ not json")
    with pytest.raises(ValueError, match="broken.gltf"):
        vkpath.Scene(broken)
    with pytest.raises(ValueError, match="the scene's own"):
        vkpath.Scene(BOX).render(env_color=(1, 1, 1))
    with pytest.raises(ValueError, match="kind 'velvet'"):
        vkpath.bsdf_eval(dict(kind="velvet"), [0, 0, 1], [0, 0, 1])
    with pytest.raises(ValueError, match="unknown field"):
        vkpath.bsdf_eval(dict(kind="diffuse", colour=1), [0, 0, 1], [0, 0, 1])
    with pytest.raises(ValueError, match=r"\(N, 3\)"):
        vkpath.bsdf_eval(dict(kind="diffuse"), np.zeros((4, 2)), [0, 0, 1])
    with pytest.raises(ValueError, match="sizes"):
        vkpath.compare(np.zeros((4, 4, 3)), np.zeros((4, 5, 3)))
    with pytest.raises(ValueError, match="no light"):
        vkpath.Scene(dark_triangle(tmp_path)).sample_lights([[0, 0, 0]])
    with pytest.raises(ValueError, match=r"\(H, W, 3\)"):
        vkpath.compare(np.zeros((4, 4)), np.zeros((4, 4)))
