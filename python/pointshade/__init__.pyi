"""Type stubs of pointshade's Python module (the reference is docs/python.md)."""

import os
from typing import Any, Callable, Literal, Mapping, Optional, Sequence, Tuple, Union, overload

import numpy as np
import numpy.typing as npt

PathLike = Union[str, os.PathLike]
Vec3 = Sequence[float]
AovName = Literal["normal", "position", "depth", "albedo", "samples"]

__version__: str

class InputError(ValueError):
    """A problem with a file's contents or a parameter; the message is the CLI's one line."""

class Rendered(dict[str, Any]):
    """render()'s result: color, the AOVs and stats; shows its image in Jupyter."""

    def _repr_png_(self) -> bytes: ...
    def save(self, path: PathLike, aov: str = ...) -> None: ...

def render(
    scene: Union[PathLike, "Scene"],
    *,
    confine: Optional[PathLike] = ...,
    progress: Union[None, bool, Callable[[int, int, str], Any]] = ...,
    quiet: bool = ...,
    width: Optional[int] = ...,
    height: Optional[int] = ...,
    spp: Optional[int] = ...,
    sampler: Optional[Literal["grid", "sobol", "independent", "adaptive", "cells"]] = ...,
    adaptive_threshold: Optional[float] = ...,
    time_budget: Optional[float] = ...,
    seed: Optional[int] = ...,
    crop: Optional[Tuple[int, int, int, int]] = ...,
    exposure: Optional[float] = ...,
    shadow_offset: Optional[Literal["error-bound", "mitsuba"]] = ...,
    shadow_terminator: Optional[Literal["smooth", "flat"]] = ...,
    match: Optional[Literal["mitsuba"]] = ...,
    view: Optional[Sequence[float]] = ...,
    look_from: Optional[Vec3] = ...,
    look_at: Optional[Vec3] = ...,
    fov: Optional[float] = ...,
    aovs: Optional[Union[AovName, Sequence[AovName]]] = ...,
    threads: Optional[int] = ...,
    camera: Optional[int] = ...,
) -> Rendered:
    """Render a scene file, mesh, glTF file or Scene; float32 (H, W, 3) arrays and stats."""

class Explorer:
    """pointshade explore's server in a thread; shown inline in Jupyter."""

    height: int
    def __init__(self, scene_or_image: Optional[PathLike] = ..., port: Optional[int] = ..., *, mitsuba_dir: Optional[PathLike] = ..., height: int = ...) -> None: ...
    @property
    def url(self) -> str: ...
    @property
    def running(self) -> bool: ...
    def stop(self) -> None: ...
    def __enter__(self) -> "Explorer": ...
    def __exit__(self, *exc: Any) -> None: ...
    def _repr_html_(self) -> str: ...

def explore(scene_or_image: Optional[PathLike] = ..., port: Optional[int] = ..., *, mitsuba_dir: Optional[PathLike] = ...) -> Explorer:
    """Start pointshade explore in a thread; returns the running Explorer."""

class Preview:
    """A scene held for renders while its materials and lights change (re-shades kept points)."""

    def __init__(self, scene: Union[PathLike, "Scene"], *, confine: Optional[PathLike] = ..., **options: Any) -> None: ...
    @property
    def materials(self) -> list[str]: ...
    def render(self) -> Rendered: ...
    def set_material(
        self, name: str, model: Literal["lambert", "blinn-phong", "cook-torrance"] = ..., **params: Any
    ) -> None: ...
    def set_camera(self, **params: Any) -> None: ...
    def set_lights(self, lights: Sequence[Mapping[str, Any]]) -> None: ...

@overload
def shade_normal_image(
    normals: Union[PathLike, npt.NDArray[np.uint8], npt.NDArray[np.uint16], npt.NDArray[np.floating]],
    *,
    preset: Literal["tp", "physical"],
    brdf: Optional[Literal["lambert", "blinn-phong", "cook-torrance"]] = ...,
    material: Optional[Mapping[str, Any]] = ...,
    lights: Optional[Sequence[Mapping[str, Any]]] = ...,
    camera: Optional[Mapping[str, Any]] = ...,
    threads: Optional[int] = ...,
    return_8bit: Literal[False] = ...,
    confine: Optional[PathLike] = ...,
) -> npt.NDArray[np.float32]: ...
@overload
def shade_normal_image(
    normals: Union[PathLike, npt.NDArray[np.uint8], npt.NDArray[np.uint16], npt.NDArray[np.floating]],
    *,
    preset: Literal["tp", "physical"],
    brdf: Optional[Literal["lambert", "blinn-phong", "cook-torrance"]] = ...,
    material: Optional[Mapping[str, Any]] = ...,
    lights: Optional[Sequence[Mapping[str, Any]]] = ...,
    camera: Optional[Mapping[str, Any]] = ...,
    threads: Optional[int] = ...,
    return_8bit: Literal[True],
    confine: Optional[PathLike] = ...,
) -> Tuple[npt.NDArray[np.float32], npt.NDArray[np.uint8]]: ...
def eval_brdf(
    material: Mapping[str, Any],
    n: npt.NDArray[np.floating],
    wi: npt.NDArray[np.floating],
    wo: npt.NDArray[np.floating],
    *,
    precision: Literal["float32", "float64"] = ...,
    defaults: Literal["scene", "tp"] = ...,
) -> npt.NDArray[np.floating]:
    """f_r per row of the (N, 3) direction arrays: (N, 3)."""

def eval_terms(
    material: Mapping[str, Any],
    n: npt.NDArray[np.floating],
    wi: npt.NDArray[np.floating],
    wo: npt.NDArray[np.floating],
    *,
    defaults: Literal["scene", "tp"] = ...,
) -> dict[str, npt.NDArray[np.float64]]:
    """D (N,), G (N,), F (N, 3) and f_r (N, 3) of a Cook-Torrance material, float64."""

def material_keys(
    model: Literal["lambert", "blinn-phong", "cook-torrance"], defaults: Literal["scene", "tp"] = ...
) -> dict[str, dict[str, Any]]:
    """A model's material keys: default (scene files' or the tp preset's), accepted values, meaning."""

def read_image(path: PathLike) -> npt.NDArray[np.float32]:
    """A linear EXR as float32 (H, W, 3)."""

def read_normal_image(path: PathLike) -> Union[npt.NDArray[np.uint8], npt.NDArray[np.uint16]]:
    """A PNG normal image's samples as stored: (H, W, 3) or (H, W, 4), uint8 or uint16."""

def write_image(
    path: PathLike, array: Union[npt.NDArray[np.floating], npt.NDArray[np.uint8]], exposure: float = ...
) -> None:
    """Write an image as the CLI does: .png 8-bit sRGB (exposure, clamp), .exr linear float32."""

def to_srgb8(array: npt.NDArray[np.floating], exposure: float = ...) -> npt.NDArray[np.uint8]:
    """The 8-bit sRGB pixels a PNG of the image holds, uint8 (H, W, 3)."""

def compare(
    ours: Union[PathLike, npt.NDArray[np.floating]],
    ref: Union[PathLike, npt.NDArray[np.floating]],
    tol: float = ...,
    worst: int = ...,
    count_non_finite: bool = ...,
) -> dict[str, Any]:
    """pointshade compare's metrics and the per-pixel relative error (H, W)."""

class Scene:
    """A scene built in Python, kept as the document a scene file parses to."""

    base_dir: str
    name: str
    doc: dict[str, Any]
    meshes: dict[str, tuple]
    def __init__(self, base_dir: Optional[PathLike] = ...) -> None: ...
    @classmethod
    def from_toml(cls, path: PathLike) -> "Scene": ...
    def add_mesh(
        self,
        vertices: npt.NDArray[np.floating],
        faces: npt.NDArray[np.integer],
        *,
        normals: Optional[npt.NDArray[np.floating]] = ...,
        uvs: Optional[npt.NDArray[np.floating]] = ...,
        material: Optional[str] = ...,
        transform: Optional[Mapping[str, Any]] = ...,
        name: Optional[str] = ...,
    ) -> str: ...
    def add_object(
        self, path: PathLike, *, material: Optional[str] = ..., transform: Optional[Mapping[str, Any]] = ...
    ) -> None: ...
    def add_material(
        self, name: str, model: Literal["lambert", "blinn-phong", "cook-torrance"] = ..., **params: Any
    ) -> None: ...
    def add_light(self, type: Literal["point", "directional", "spot"] = ..., **params: Any) -> None: ...
    def set_camera(self, **params: Any) -> None: ...
    def set_film(self, **params: Any) -> None: ...
    def set_render(self, **params: Any) -> None: ...
    def to_toml(self) -> str: ...
    def save(self, path: PathLike) -> None: ...
    def export_mitsuba(
        self,
        path: PathLike,
        *,
        spp: Optional[int] = ...,
        sampler: Optional[str] = ...,
        match: Optional[Literal["mitsuba"]] = ...,
        per_light: bool = ...,
    ) -> list[str]: ...
