"""vkpath from Python: render a scene into numpy arrays, compare images, and
run the path tracer's own sampling routines over arrays.

    import vkpath
    image = vkpath.render("assets/cornell_box.gltf", spp=64, size=(320, 240), device="cpu")

Every keyword of `render` is a flag of `vkpath render` of the same meaning and
default (`max_depth=4` is `--max-depth 4`, `size=(w, h)` is `-d WxH`, a true
boolean is the flag, a list repeats it), parsed by the command line's own
parser, so the same arguments give the command line's image bit for bit.
Bad arguments raise ValueError with the command line's one-line message.
"""

from __future__ import annotations

import os
from typing import Any, Callable, Iterable, Mapping, Optional, Sequence, Union

import numpy as np

from . import _vkpath

__version__ = _vkpath.__version__
# The material kinds' keys, from the registry (shaders/shared/material_kinds.h).
MATERIAL_KINDS: tuple = tuple(_vkpath.MATERIAL_KINDS)

__all__ = [
    "Scene",
    "Render",
    "render",
    "compare",
    "z_test",
    "read_exr",
    "write_exr",
    "bsdf_sample",
    "bsdf_eval",
    "bsdf_pdf",
    "sampler_values",
    "MATERIAL_FIELDS",
    "MATERIAL_KINDS",
]

# The keywords that change the scene itself (its environment, its fog, its
# camera, whether meshes several nodes place are instanced, a glTF material variant):
# given to Scene(), which loads the file with them once.
SCENE_KEYWORDS = (
    "env",
    "env_color",
    "env_strength",
    "env_rotate",
    "fog_density",
    "fog_albedo",
    "fog_anisotropy",
    "volume",
    "volume_grid",
    "volume_density",
    "volume_albedo",
    "volume_anisotropy",
    "camera",
    "instancing",
    "variant",
)
# The device is also the scene's: a CPU render is admitted against the host's
# memory alone (wavefront/scene_footprint.h).
_LOAD_KEYWORDS = SCENE_KEYWORDS + ("device",)

# The fields of a material for the BSDF routines (scene::Material's, in
# host/scene/scene.h, which says what each means); `kind` is a key of the
# material registry, MATERIAL_KINDS.
MATERIAL_FIELDS = (
    "kind",
    "reflectance",
    "transmittance",
    "ior",
    "roughness",
    "metallic",
    "specular",
    "specular_color",
    "conductor_eta",
    "conductor_k",
    "attenuation",
)


def _flag(name: str) -> str:
    return "--" + name.replace("_", "-")


def _flags(keywords: Mapping[str, Any]) -> list[str]:
    """`vkpath render`'s flags for `keywords`."""
    args: list[str] = []
    for name, value in keywords.items():
        if value is None or value is False:
            continue
        flag = _flag(name)
        if name == "size":
            if isinstance(value, str):
                args += [flag, value]
            else:
                width, height = value
                args += [flag, f"{int(width)}x{int(height)}"]
        elif value is True:
            args.append(flag)
        elif name in ("env_color", "fog_density", "fog_albedo", "volume_albedo") and isinstance(
            value, (list, tuple)
        ):
            args += [flag, ",".join(repr(float(v)) for v in value)]
        elif isinstance(value, (list, tuple)):
            for item in value:
                args += [flag, str(item)]
        elif isinstance(value, float):
            args += [flag, repr(value)]
        elif isinstance(value, os.PathLike):
            args += [flag, os.fspath(value)]
        else:
            args += [flag, str(value)]
    return args


class Render:
    """What a render made: `image` (H, W, 3) float32 linear RGB, `variance`
    (each pixel's variance of its mean), `spp` (each pixel's samples), and
    `aovs` (the AOVs asked for with aov=[...]: variance, spp, albedo,
    normal); `denoised` with denoise=True (guided by the albedo and normal
    AOVs, as render --denoise is).
    `spp_reached`, `seconds`, `paths`, `estimated_rel_mse`, `reached_target`,
    `stopped` and `interrupted` (Ctrl-C) say how it went."""

    def __init__(self, result: dict, aovs: Sequence[str]):
        self.image: np.ndarray = result["image"]
        self.variance: np.ndarray = result["variance"]
        self.spp: np.ndarray = result["spp"]
        self.denoised: Optional[np.ndarray] = result.get("denoised")
        self.aovs = {name: result[name] for name in aovs}
        for key in (
            "spp_reached",
            "seconds",
            "paths",
            "estimated_rel_mse",
            "reached_target",
            "stopped",
            "interrupted",
            "non_finite_samples",
        ):
            setattr(self, key, result[key])

    def __repr__(self) -> str:
        height, width, _ = self.image.shape
        return f"<vkpath.Render {width}x{height} at {self.spp_reached} spp in {self.seconds:.3f} s>"


class Scene:
    """A scene loaded once and rendered many times (other settings, seeds,
    cameras) without reloading it or rebuilding its BVH.

    Keywords: the flags that change the scene (env, env_color, env_strength,
    env_rotate, fog_density, fog_albedo: one number or (R, G, B), fog_anisotropy,
    volume: an OpenVDB file, volume_grid, volume_density, volume_albedo,
    volume_anisotropy, camera: a glTF camera's name, instancing: "auto", "on" or
    "off", variant: a glTF KHR_materials_variants name) and device ("gpu" or "cpu", the
    memory the scene is admitted against; a render may name either)."""

    def __init__(self, path: Union[str, os.PathLike], **keywords: Any):
        unknown = sorted(set(keywords) - set(_LOAD_KEYWORDS))
        if unknown:
            raise ValueError(
                f"Scene(): {', '.join(unknown)} not a scene keyword ({', '.join(_LOAD_KEYWORDS)}); "
                "give render settings to render()"
            )
        self._device = keywords.pop("device", None)
        self._scene = _vkpath.Scene([os.fspath(path)] + _flags(keywords), self._device or "gpu")

    @property
    def path(self) -> str:
        return self._scene.path

    def info(self) -> dict:
        """What `vkpath scene-info PATH --json` prints, as a dict."""
        import json

        return json.loads(self._scene.info())

    @property
    def camera(self) -> dict:
        """The camera renders use: position, target, up (world space), fov
        (degrees across the width of the camera's own aspect) and aspect (its
        width / height; 0: the film's). Set it with set_camera()."""
        return self._scene.camera()

    def set_camera(
        self,
        position: Sequence[float],
        target: Sequence[float],
        up: Sequence[float] = (0.0, 1.0, 0.0),
        fov: float = 60.0,
        aspect: float = 0.0,
    ) -> None:
        """Renders from here on look from `position` at `target`, `fov` degrees
        across the width (of `aspect`, or of the film where it is 0)."""
        self._scene.set_camera(
            [float(v) for v in position],
            [float(v) for v in target],
            [float(v) for v in up],
            float(fov),
            float(aspect),
        )

    def render(
        self,
        progress: Optional[Callable[[dict], Any]] = None,
        **keywords: Any,
    ) -> Render:
        """Renders with `vkpath render`'s flags as keywords (spp, size,
        max_depth, device, seed, sampler, time_budget, target_error, adaptive,
        aov, denoise, ...). `progress` is called after every wave with a dict
        (spp, spp_total, seconds, paths, estimated_rel_mse); an exception it
        raises stops the render and is raised. Ctrl-C stops at the next whole
        sample and returns the image so far (Render.interrupted). Files are
        written only where `output` is given (with it png, aov and denoise
        write theirs as the command does)."""
        loaded = sorted(set(keywords) & set(SCENE_KEYWORDS))
        if loaded:
            raise ValueError(
                f"{', '.join(loaded)}: the scene's own; give it to vkpath.Scene(path, ...)"
            )
        if "device" not in keywords and self._device:
            keywords["device"] = self._device
        aovs = keywords.get("aov") or ()
        if isinstance(aovs, str):
            aovs = tuple(aovs.split(","))
            keywords["aov"] = aovs
        write_files = keywords.get("output") is not None
        result = self._scene.render(_flags(keywords), write_files, progress)
        return Render(result, aovs)

    def sample_lights(
        self,
        points: Any,
        seed: int = 0,
        sampler: str = "independent",
        sample_index: int = 0,
        device: str = "gpu",
    ) -> dict:
        """Next-event estimation's light sample from each of `points` (N, 3),
        world space (shared/path/next_event.h sampleSceneLight: a light chosen
        as a render chooses it, by power or, with 8 lights with a position or
        more, through the light tree; then a point on it or a direction of
        the environment), with the sampler's numbers of (input index,
        sample_index, seed): a dict of light (index; -1 where the tree was
        chosen and none of its lights reaches the point), choice (its
        probability), direction, distance,
        radiance, pdf (of the direction given the light; 1 for delta),
        normal (area lights) and delta. A scene without lights raises."""
        points = _directions(points, np.asarray(points).reshape(-1, 3).shape[0], "points")
        zeros = np.zeros_like(points)
        zeros[:, 2] = 1
        return self._scene.lights(points, zeros, int(seed), sampler, int(sample_index), device)

    def environment(self, directions: Any, device: str = "gpu") -> tuple:
        """The environment's radiance (N, 3) in each of `directions` and the
        density (N,) with which its light sampling draws them (given it is
        the light chosen): shared/path/environment.h."""
        directions = _directions(directions, np.asarray(directions).reshape(-1, 3).shape[0], "directions")
        out = self._scene.lights(np.zeros_like(directions), directions, 0, "independent", 0, device)
        return out["environment_radiance"], out["environment_pdf"]


def render(
    scene: Union[str, os.PathLike, Scene],
    progress: Optional[Callable[[dict], Any]] = None,
    **keywords: Any,
) -> Union[np.ndarray, tuple]:
    """Renders `scene` (a path or a Scene) and returns the image, (H, W, 3)
    float32; with aov=[...] or denoise=True, (image, {name: array}) where the
    variance, albedo, normal and denoised images are (H, W, 3) and spp (H, W). Keywords as Scene.render's; a path also
    takes the scene's (env, camera, ...)."""
    if not isinstance(scene, Scene):
        scene_keywords = {k: keywords.pop(k) for k in SCENE_KEYWORDS if k in keywords}
        if "device" in keywords:
            scene_keywords["device"] = keywords["device"]
        scene = Scene(scene, **scene_keywords)
    made = scene.render(progress=progress, **keywords)
    if not made.aovs and made.denoised is None:
        return made.image
    aovs = dict(made.aovs)
    if made.denoised is not None:
        aovs["denoised"] = made.denoised
    return made.image, aovs


def _image(value: Union[np.ndarray, str, os.PathLike], what: str) -> np.ndarray:
    if isinstance(value, (str, os.PathLike)):
        return read_exr(value)
    array = np.ascontiguousarray(value, dtype=np.float32)
    if array.ndim != 3 or array.shape[2] != 3:
        raise ValueError(f"{what}: an image is an (H, W, 3) array or an EXR path, not {array.shape}")
    return array


def compare(a: Union[np.ndarray, str, os.PathLike], b: Union[np.ndarray, str, os.PathLike]) -> dict:
    """How far image `a` is from reference `b` (arrays or EXR paths), as
    `vkpath compare` measures it: rmse, rel_mse, rel_mse_trimmed, mae,
    max_error, max_at, psnr, per channel in `channels`."""
    return _vkpath.compare(_image(a, "a"), _image(b, "b"))


def _variance_beside(path: Union[str, os.PathLike]) -> np.ndarray:
    stem, extension = os.path.splitext(os.fspath(path))
    return read_exr(f"{stem}.variance{extension}")


def z_test(
    a: Union[np.ndarray, str, os.PathLike],
    b: Union[np.ndarray, str, os.PathLike],
    variance_a: Union[np.ndarray, str, os.PathLike, None] = None,
    variance_b: Union[np.ndarray, str, os.PathLike, None] = None,
    alpha: float = 0.01,
    block_size: int = 8,
) -> dict:
    """Whether two independent renders estimate the same image: `vkpath
    compare --ztest`'s per-block z-tests, Sidak-corrected. The variances (of
    each pixel's mean, Render.variance) default, for EXR paths, to the
    variance AOV beside each file."""
    if variance_a is None:
        if not isinstance(a, (str, os.PathLike)):
            raise ValueError("z_test: variance_a is needed for an array")
        variance_a = _variance_beside(a)
    if variance_b is None:
        if not isinstance(b, (str, os.PathLike)):
            raise ValueError("z_test: variance_b is needed for an array")
        variance_b = _variance_beside(b)
    return _vkpath.z_test(
        _image(a, "a"),
        _image(variance_a, "variance_a"),
        _image(b, "b"),
        _image(variance_b, "variance_b"),
        float(alpha),
        int(block_size),
    )


def read_exr(path: Union[str, os.PathLike], metadata: bool = False):
    """An EXR's RGB as (H, W, 3) float32; with metadata=True, (image, the
    vkpath:* header attributes)."""
    read = _vkpath.read_exr(os.fspath(path))
    return (read["image"], read["metadata"]) if metadata else read["image"]


def write_exr(path: Union[str, os.PathLike], image: np.ndarray) -> None:
    _vkpath.write_exr(os.fspath(path), _image(image, "image"))


def _directions(value: Any, count: int, what: str) -> np.ndarray:
    array = np.asarray(value, dtype=np.float32)
    if array.ndim == 1:
        array = array[np.newaxis]
    if array.ndim != 2 or array.shape[1] != 3 or array.shape[0] not in (1, count):
        raise ValueError(f"{what}: an (N, 3) array (or one 3-vector), not {array.shape}")
    return np.ascontiguousarray(np.broadcast_to(array, (count, 3)))


def _bsdf(material: Mapping[str, Any], wo: Any, wi: Any, u: Any, device: str, at_sample: bool = False) -> dict:
    arrays = [np.asarray(x) for x in (wo, wi, u)]
    count = max((a.shape[0] for a in arrays if a.ndim == 2), default=1)
    wo_, wi_, u_ = (_directions(a, count, name) for a, name in zip(arrays, ("wo", "wi", "u")))
    return _vkpath.bsdf(dict(material), wo_, wi_, u_, at_sample, device)


def bsdf_sample(material: Mapping[str, Any], wo: Any, u: Any, device: str = "gpu") -> dict:
    """shared/bsdf.h's sampleBsdf for each row of wo (unit, local shading
    frame: normal +z) and u (uniform numbers: u[:, :2] the direction, u[:, 2]
    the lobe choice), on the GPU kernel or the same C++ on the CPU: a dict of
    direction (N, 3), weight (N, 3) = f |cos| / pdf, pdf (N,), valid and delta
    (N,) as 0/1, and eval (N, 3) and eval_pdf (N,) (evalBsdf and bsdfPdf at
    the sampled direction)."""
    return _bsdf(material, wo, [0, 0, 1], u, device, at_sample=True)


def bsdf_eval(material: Mapping[str, Any], wo: Any, wi: Any, device: str = "gpu") -> np.ndarray:
    """evalBsdf(wo, wi), f |cos wi|, per row (local frame, normal +z): (N, 3)."""
    return _bsdf(material, wo, wi, np.full((1, 3), 0.5, np.float32), device)["eval"]


def bsdf_pdf(material: Mapping[str, Any], wo: Any, wi: Any, device: str = "gpu") -> np.ndarray:
    """bsdfPdf(wo, wi), the solid-angle density sampleBsdf draws wi with: (N,)."""
    return _bsdf(material, wo, wi, np.full((1, 3), 0.5, np.float32), device)["eval_pdf"]


def sampler_values(
    sampler: str = "sobol",
    samples: int = 16,
    dimensions: int = 2,
    pixels: int = 1,
    seed: int = 0,
    first_sample: int = 0,
    device: str = "gpu",
) -> np.ndarray:
    """The path tracer's random numbers (shared/rng.h rngUniform) of either
    sampler ("sobol", "independent"), (samples, dimensions, pixels) float32."""
    return _vkpath.sampler_values(
        sampler, int(seed), int(pixels), int(samples), int(dimensions), int(first_sample), device
    )
