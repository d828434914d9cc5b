"""pointshade: render OBJ/glTF scenes, shade normal images and evaluate BRDFs on numpy arrays.

Every function calls the Rust library the ``pointshade`` command line is built on, so a render
from Python equals the CLI's bit for bit. The API reference is docs/python.md.

    import pointshade
    out = pointshade.render("scenes/cornell-box.toml", width=320, height=240)
    out["color"]          # float32 (240, 320, 3) linear radiance

Errors are exceptions carrying the CLI's one-line message: ``FileNotFoundError`` for a missing
file, :class:`InputError` (a ``ValueError``) for bad contents or parameters, ``TypeError`` and
``ValueError`` for arrays of the wrong dtype, shape or layout. The GIL is released while
pointshade works, and Ctrl-C stops a render within about a tile per thread.
"""

import copy as _copy
import os as _os
import sys as _sys
import textwrap as _textwrap
import warnings as _warnings

import numpy as _np

from . import _native
from ._native import InputError

__version__ = _native.__version__

__all__ = [
    "InputError",
    "Preview",
    "Rendered",
    "Scene",
    "Explorer",
    "compare",
    "eval_brdf",
    "eval_terms",
    "explore",
    "material_keys",
    "read_image",
    "read_normal_image",
    "render",
    "shade_normal_image",
    "to_srgb8",
    "write_image",
]

def _path(value, what):
    if isinstance(value, (str, _os.PathLike)):
        return _os.fspath(value)
    raise TypeError(f"{what}: expected a path (str or os.PathLike), got {type(value).__name__}")


class Rendered(dict):
    """What :func:`render` returns: a dict (``color``, the AOVs, ``stats``) that also shows its
    colour image in Jupyter (as the PNG ``pointshade render -o x.png`` writes, with the scene's
    exposure) and saves it with :meth:`save`."""

    def _repr_png_(self):
        return _native.png_bytes(self["color"], exposure=self["stats"]["exposure"])

    def save(self, path, aov="color"):
        """Write the colour image (or ``aov``) to ``path`` as the CLI writes it: ``.png`` 8-bit
        sRGB with the scene's exposure, ``.exr`` linear float32."""
        write_image(path, self[aov], exposure=self["stats"]["exposure"])


class _StderrBar:
    """The progress line a render draws on stderr: percentage and units, redrawn in place."""

    def __init__(self):
        self.drawn = False

    def __call__(self, done, total, unit):
        what = "of the time budget" if unit == "ms" else f"({done}/{total} tiles)"
        _sys.stderr.write(f"\rrendering: {100 * done // max(total, 1):3d}% {what}")
        _sys.stderr.flush()
        self.drawn = True

    def close(self):
        if self.drawn:
            _sys.stderr.write("\n")
            _sys.stderr.flush()


class _TqdmBar:
    """A tqdm progress bar fed by a render's (done, total) advances."""

    def __init__(self, tqdm):
        self.tqdm, self.bar = tqdm, None

    def __call__(self, done, total, unit):
        if self.bar is None:
            self.bar = self.tqdm(total=total, unit=" tiles" if unit == "tiles" else " ms", desc="rendering")
        self.bar.update(done - self.bar.n)

    def close(self):
        if self.bar is not None:
            self.bar.close()


def _in_dask_worker():
    if "distributed" not in _sys.modules:
        return False
    try:
        _sys.modules["distributed"].get_worker()
        return True
    except (ValueError, AttributeError):
        return False


def _progress_receiver(progress, quiet):
    """What render()'s ``progress`` and ``quiet`` ask for: a callable(done, total, unit) with a
    ``close()``, or None."""
    if quiet or progress is False:
        return None
    if progress is None:  # automatic: a terminal's stderr, outside Dask workers
        stderr = getattr(_sys, "stderr", None)
        shown = stderr is not None and hasattr(stderr, "isatty") and stderr.isatty() and not _in_dask_worker()
        return _StderrBar() if shown else None
    if progress is True:
        try:
            from tqdm.auto import tqdm
        except ImportError:
            return _StderrBar()
        return _TqdmBar(tqdm)
    if callable(progress):
        return progress
    raise TypeError(f"progress: expected None, True, False or a callable(done, total, unit), got {type(progress).__name__}")


def render(scene, *, confine=None, progress=None, quiet=False, **options):
    """Render ``scene`` and return its images as float32 (H, W, 3) arrays.

    ``scene`` is a path (``.toml`` scene file, ``.obj``, ``.gltf``, ``.glb``) or a :class:`Scene`.
    The keywords replace the scene's settings, as ``pointshade render``'s options of the same
    names do (``shadow_offset=`` is ``--shadow-offset``); they are listed below. With ``confine``
    (a folder), every file the scene refers to must lie inside it, after links and ``..`` are
    resolved (for files from others: a glTF rendered on a server); a file outside is a
    ValueError, as ``pointshade render --confine DIR`` refuses it.

    Returns a dict (a :class:`Rendered`, which a notebook shows as its image): ``color``
    (linear radiance), one array per requested AOV, and ``stats`` (stage times in seconds, ray
    counts, samples per pixel, the region and frame, the exposure, the triangle count and the
    scene's warnings, which are also issued as Python warnings).

    Progress: by default a line on stderr when stderr is a terminal (not inside a Dask worker);
    ``progress=True`` a tqdm bar when tqdm is installed (else that line), ``progress=False`` or
    ``quiet=True`` nothing, and a callable is called as ``progress(done, total, unit)`` (``unit``
    ``"tiles"``, or ``"ms"`` of a time budget) on the calling thread, at most 20 times a second
    and once at the end; an exception it raises stops the render.

    A value of the wrong type is a TypeError naming the keyword, one out of range a
    :class:`InputError` (a ValueError) saying what it takes.

    Keywords:
    """
    confine = None if confine is None else _path(confine, "confine")
    receiver = _progress_receiver(progress, quiet)
    try:
        if isinstance(scene, Scene):
            out = _native.render(
                scene.name, text=scene.to_toml(), dir=scene.base_dir, meshes=scene.meshes, confine=confine,
                options=options, progress=receiver,
            )
        else:
            out = _native.render(_path(scene, "scene"), confine=confine, options=options, progress=receiver)
    finally:
        if hasattr(receiver, "close"):
            receiver.close()
    for w in out["stats"]["warnings"]:
        _warnings.warn(w, stacklevel=2)
    return Rendered(out)


render.__doc__ += "".join(
    f"\n    ``{name}`` ({placeholder})\n" + _textwrap.fill(help, 96, initial_indent=" " * 8, subsequent_indent=" " * 8) + "\n"
    for name, placeholder, help in _native.render_option_table()
)


class Preview:
    """A scene held for renders while its materials and lights change: a notebook's sliders.

    ``Preview(scene, **options)`` loads ``scene`` as :func:`render` does (a path or a
    :class:`Scene`; the same keywords) and builds its BVH once. The first :meth:`render` traces
    the view and keeps its surface points and shadow verdicts; after :meth:`set_material` or
    :meth:`set_lights` the next one shades the kept points again and traces only the shadow rays
    that changed (a moved light's), so it takes a fraction of a render's time (``stats`` counts
    ``primary_rays`` 0 and ``shadow_rays_reused``); after :meth:`set_camera` it traces the new
    view with the same BVH. Every image is the one :func:`render` gives
    for the edited scene, bit for bit. The film must take a fixed number of samples per pixel
    (``sampler`` sobol, grid or independent, no ``time_budget``): anything else is an
    :class:`InputError` here. A bad edit is an :class:`InputError` naming the key, and changes
    nothing. One preview renders on one thread of Python at a time.
    """

    def __init__(self, scene, *, confine=None, **options):
        confine = None if confine is None else _path(confine, "confine")
        if isinstance(scene, Scene):
            self._native = _native.Preview(
                scene.name, text=scene.to_toml(), dir=scene.base_dir, meshes=scene.meshes, confine=confine,
                options=options,
            )
        else:
            self._native = _native.Preview(_path(scene, "scene"), confine=confine, options=options)

    @property
    def materials(self):
        """The scene's material names (what :meth:`set_material` takes)."""
        return self._native.material_names()

    def render(self):
        """The image of the scene as edited so far: what :func:`render` returns."""
        return Rendered(self._native.render())

    def set_material(self, name, model="lambert", **params):
        """Replace material ``name`` by a ``model`` material with scene-file keys, as
        :meth:`Scene.add_material` takes them (:func:`material_keys` lists them); keys left out
        take the scene files' defaults."""
        self._native.set_material(name, _material_toml({"model": model, **params}))

    def set_camera(self, **params):
        """Replace the camera by one with ``[camera]`` keys, as :meth:`Scene.set_camera` takes
        them (position, look_at, up, fov, type, ...): a new view, traced with the same BVH."""
        self._native.set_camera(_native.to_toml(params, "set_camera"))

    def set_lights(self, lights):
        """Replace every light by ``lights``, a list of dicts of ``[[light]]`` keys, as
        :meth:`Scene.add_light` takes them (``{"type": "point", "position": [...], ...}``)."""
        if not isinstance(lights, (list, tuple)):
            raise TypeError(f"lights: expected a list of dicts of [[light]] keys, got {type(lights).__name__}")
        texts = []
        for k, light in enumerate(lights):
            if not isinstance(light, dict):
                raise TypeError(f"lights[{k}]: expected a dict of [[light]] keys, got {type(light).__name__}")
            texts.append(_native.to_toml(light, f"set_lights: light {k + 1}"))
        self._native.set_lights(texts)

    def __repr__(self):
        return f"<pointshade.Preview of {len(self.materials)} material(s)>"


class Explorer:
    """``pointshade explore``'s server, running in a thread of this process (docs/explore.md).

    ``url`` is the page's address; in Jupyter the object shows the page inline (an IFrame).
    :meth:`stop` ends the server, as does leaving a ``with`` block.
    """

    def __init__(self, scene_or_image=None, port=None, *, mitsuba_dir=None, height=900):
        path = None if scene_or_image is None else _path(scene_or_image, "scene_or_image")
        mitsuba = None if mitsuba_dir is None else _path(mitsuba_dir, "mitsuba_dir")
        self._server = _native.ExploreServer(path, 0 if port is None else port, mitsuba)
        self.height = height

    @property
    def url(self):
        """The page's address, on 127.0.0.1."""
        return self._server.url

    @property
    def running(self):
        """Whether the server still answers."""
        return self._server.running

    def stop(self):
        """Stops the server; stopping twice does nothing."""
        self._server.stop()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.stop()

    def __repr__(self):
        state = "running" if self.running else "stopped"
        return f"<pointshade.Explorer {self.url} ({state})>"

    def _repr_html_(self):
        if not self.running:
            return f"<p>pointshade explore at {self.url} has stopped.</p>"
        return (
            f'<iframe src="{self.url}" width="100%" height="{int(self.height)}" '
            'style="border: 1px solid #ccc"></iframe>'
        )


def explore(scene_or_image=None, port=None, *, mitsuba_dir=None):
    """Start ``pointshade explore`` on ``scene_or_image`` (a PNG normal image, a scene file, a
    bare mesh or a glTF file; none: the assignment's setting on a normal image baked from a shipped
    scene) in a thread, on 127.0.0.1:``port`` (default: a free port). ``mitsuba_dir`` is the
    validation folder whose Mitsuba 3 the page's comparison runs (default: ``validation`` of the
    working folder, as ``pointshade explore`` has it). Returns an :class:`Explorer`: shown inline
    in Jupyter, ``.url`` for a browser, ``.stop()`` to end it."""
    return Explorer(scene_or_image, port, mitsuba_dir=mitsuba_dir)


def _normal_map_toml(image, preset, brdf, material, lights, camera):
    section = {"image": image, "preset": preset}
    doc = {"normal_map": section}
    if material is not None:
        if brdf is not None:
            raise ValueError("brdf: give either brdf (the preset's material) or material (a dict), not both")
        section["material"] = "material"
        doc["material"] = {"material": dict(material)}
    elif brdf is not None:
        section["brdf"] = brdf
    else:
        raise ValueError("brdf: give brdf='lambert' | 'blinn-phong' | 'cook-torrance', or material={...}")
    if lights is not None:
        doc["light"] = [dict(light) for light in lights]
    if camera is not None:
        doc["camera"] = dict(camera)
    return _native.to_toml(doc, "shade_normal_image")


def shade_normal_image(
    normals,
    *,
    preset=None,
    brdf=None,
    material=None,
    lights=None,
    camera=None,
    threads=None,
    return_8bit=False,
    confine=None,
):
    """Shade a normal image as ``pointshade normalmap`` does; return L_o as float32 (H, W, 3).

    ``normals`` is a PNG path or an (H, W, 3) or (H, W, 4) uint8 or uint16 array of the samples
    a PNG stores (what ``imageio.imread`` or ``PIL`` give), or a float32/float64 array of them
    divided by full scale, in [0, 1] (unit normals n go in as (n + 1) / 2). ``preset`` is
    required: ``"tp"`` (the NPM3D TP4 assignment's conventions, exactly: its images) or
    ``"physical"`` (radiometric units and pointshade's physical defaults). The material is the preset's of model
    ``brdf`` (lambert, blinn-phong, cook-torrance), or ``material``, a dict of scene-file
    material keys (``{"model": "cook-torrance", "roughness": 0.3}``) with the preset's defaults.
    ``lights`` (a list of dicts of ``[[light]]`` keys) and ``camera`` (a dict of the normal-map
    ``[camera]`` keys) replace the preset's. With ``return_8bit=True`` (tp preset) the result is
    a tuple ``(L_o, image)``, ``image`` the uint8 (H, W, 3) PNG ``normalmap --preset tp`` writes.
    With ``confine`` (a folder), a PNG path must lie inside it (links and ``..`` resolved).
    """
    if preset is None:
        raise TypeError(
            "shade_normal_image: preset is required: preset='tp' for the NPM3D TP4 assignment's "
            "images, or preset='physical' for radiometric units"
        )
    if isinstance(normals, (str, _os.PathLike)):
        image, array = _os.path.abspath(_os.fspath(normals)), None
    else:
        image, array = "normals", normals
    text = _normal_map_toml(image, preset, brdf, material, lights, camera)
    confine = None if confine is None else _path(confine, "confine")
    lo, eight, warnings = _native.shade_normal_image(
        text, normals=array, threads=threads, eight_bit=return_8bit, confine=confine
    )
    for w in warnings:
        _warnings.warn(w, stacklevel=2)
    return (lo, eight) if return_8bit else lo


def _material_toml(material):
    if not isinstance(material, dict):
        raise TypeError(f"material: expected a dict of scene-file material keys, got {type(material).__name__}")
    return _native.to_toml(material, "material")


def _one_of(names):
    quoted = [f"'{n}'" for n in names]
    return quoted[0] if len(quoted) == 1 else ", ".join(quoted[:-1]) + " or " + quoted[-1]


# The names of the D, G and F terms, from the library.
_TERM_NAMES = _native.term_names()

# What each material key takes and means (docs/scene-format.md, "Every material key"); the
# defaults and the terms' names come from the library itself (_native.material_defaults,
# _native.term_names).
_MATERIAL_KEYS = {
    "model": ("'lambert', 'blinn-phong' or 'cook-torrance'", "the BRDF: f_r = kd·albedo/π + f_s"),
    "albedo": ("3 finite numbers ≥ 0", "diffuse colour"),
    "kd": ("a finite number ≥ 0", "weight of the diffuse term (0 by default for a conductor)"),
    "two_sided": ("bool", "shade the back of a surface as its front"),
    "ks": ("a finite number ≥ 0", "weight of the Blinn-Phong lobe"),
    "shininess": ("a finite number ≥ 0", "Blinn-Phong exponent of n·ω_h"),
    "specular_color": ("3 finite numbers ≥ 0", "specular tint (Schlick's F0 when metallic)"),
    "roughness": ("a number in [0, 1]", "GGX or Beckmann α, used directly"),
    "d": (_one_of(_TERM_NAMES["d"]), "microfacet distribution D"),
    "g": (_one_of(_TERM_NAMES["g"]), "masking-shadowing G"),
    "fresnel": (_one_of(_TERM_NAMES["fresnel"]), "Fresnel term F ('conductor' when eta or k is written)"),
    "metallic": ("bool (Schlick Fresnel only)", "F0 = specular_color instead of the dielectric's"),
    "ior": ("a finite number > 0 (Schlick Fresnel, not metallic)", "F0 = ((ior − 1)/(ior + 1))²"),
    "eta": ("3 finite numbers ≥ 0 (conductor Fresnel)", "real part of the conductor's index per channel"),
    "k": ("3 finite numbers ≥ 0 (conductor Fresnel)", "imaginary part (absorption) per channel"),
}


def material_keys(model, defaults="scene"):
    """Every key a ``model`` material takes (``"lambert"``, ``"blinn-phong"``,
    ``"cook-torrance"``), as a dict of key → ``{"default", "takes", "meaning"}``: what it
    defaults to (the scene files' defaults, or the tp preset's with ``defaults="tp"``, read from
    the library), the values it accepts and what it does. The keys of :func:`eval_brdf`'s
    ``material``, :meth:`Scene.add_material` and ``shade_normal_image(material=...)``; the
    formulas are in docs/scene-format.md."""
    values = _native.material_defaults(model, defaults)
    return {
        key: {"default": default, "takes": _MATERIAL_KEYS[key][0], "meaning": _MATERIAL_KEYS[key][1]}
        for key, default in values.items()
    }


def eval_brdf(material, n, wi, wo, *, precision="float32", defaults="scene"):
    """f_r of ``material`` for each row of the (N, 3) arrays ``n``, ``wi``, ``wo``: (N, 3).

    The very function the renderer's shader multiplies by E·cos θ_i: a two-sided material turns
    ``n`` towards ``wo``; rows where ``wi`` or ``wo`` is below the surface give 0. ``wi`` and
    ``wo`` are unit directions towards the light and the viewer (a row whose length is off 1 by
    more than 1e-4 is a ValueError naming it: normalise them); ``n`` may have any length but
    zero.
    ``material`` is a dict of scene-file material keys (:func:`material_keys` lists a model's,
    with their defaults and ranges); ``defaults`` ``"scene"`` (scene files')
    or ``"tp"`` (the tp preset's) fills the rest. ``precision``: ``"float32"`` (the renderer's)
    or ``"float64"`` (for checking): double-precision arithmetic on the material's parameters
    as pointshade stores them, in float32 (roughness 0.3 is 0.30000001192...). So at α = 0.3,
    D and G differ from a float64 evaluation at exactly 0.3 by up to 8e-8 and 3e-8 relative,
    and agree with one at float32(0.3) to 1e-14 (docs/python.md).
    The arrays (float32 or float64, C-contiguous) are read in place on every core without the
    GIL: do not write to them from another thread during the call.
    """
    return _native.eval_brdf(_material_toml(material), n, wi, wo, precision=precision, defaults=defaults)


def eval_terms(material, n, wi, wo, *, defaults="scene"):
    """The Cook-Torrance terms of ``material`` for each row, in float64: a dict of ``D`` (N,),
    ``G`` (N,), ``F`` (N, 3) and ``f_r`` (N, 3), the functions its ``d``, ``g`` and ``fresnel``
    keys name (ggx, beckmann; smith-ggx, smith-ggx-correlated, schlick-smith, ...; schlick,
    schlick-sg, conductor, constant)."""
    return _native.eval_terms(_material_toml(material), n, wi, wo, defaults=defaults)


def read_image(path):
    """A linear image file (EXR as pointshade writes it) as float32 (H, W, 3)."""
    return _native.read_image(_path(path, "path"))


def read_normal_image(path):
    """A PNG normal image's samples exactly as the file stores them: uint8 or uint16, (H, W, 3),
    or (H, W, 4) with alpha; what :func:`shade_normal_image` takes as an array."""
    return _native.read_normal_image(_path(path, "path"))


def write_image(path, array, exposure=0.0):
    """Write a float (H, W, 3) image to ``path`` as ``pointshade render -o`` writes one:
    ``.png`` 8-bit sRGB after scaling by 2^``exposure`` and clamping to [0, 1] (the same bytes
    as the CLI's file of the same render), ``.exr`` linear float32 (exposure not applied). A
    uint8 (H, W, 3) array, 8-bit sRGB already, is written to a ``.png`` as it is. A NaN or
    infinite pixel is a ValueError naming it; nothing is written on an error."""
    _native.write_image(_path(path, "path"), array, exposure=exposure)


def to_srgb8(array, exposure=0.0):
    """The uint8 (H, W, 3) sRGB pixels of a float (H, W, 3) image, as a PNG of it holds them:
    scaled by 2^``exposure``, clamped to [0, 1], encoded with the sRGB curve, rounded."""
    return _native.to_srgb8(array, exposure=exposure)


def compare(ours, ref, tol=1e-3, worst=10, count_non_finite=False):
    """The metrics ``pointshade compare`` prints, for two (H, W, 3) float arrays or EXR paths.

    Images of different sizes, and images with a NaN or infinite pixel, raise ValueError naming
    the image; with ``count_non_finite=True`` such pixels count as mismatches instead.

    Returns a dict: pixels, rmse, rel_mse, mean_relative_error, within_tolerance, tolerance,
    non_finite_ours, non_finite_reference, worst (the worst pixels, worst first), summary (the
    CLI's text) and relative_error, the float32 (H, W) per-pixel relative error.
    """
    ours = read_image(ours) if isinstance(ours, (str, _os.PathLike)) else ours
    ref = read_image(ref) if isinstance(ref, (str, _os.PathLike)) else ref
    return _native.compare(ours, ref, tol=tol, worst=worst, count_non_finite=count_non_finite)


class Scene:
    """A scene built in Python: meshes from numpy arrays or files, materials, lights, a camera.

    It is kept as the document a scene file parses to (docs/scene-format.md), so every key,
    default and check is the scene file's; :meth:`to_toml` writes that file. Meshes given as
    arrays are named ``NAME.obj`` in it, and :meth:`save` writes them beside the scene file as
    OBJ files that load exactly as the arrays do.
    """

    def __init__(self, base_dir=None):
        """An empty scene; relative mesh paths are relative to ``base_dir`` (default: the
        current directory)."""
        self.base_dir = _os.path.abspath(base_dir or _os.getcwd())
        self.name = "Scene"
        self.doc = {}
        self.meshes = {}

    @classmethod
    def from_toml(cls, path):
        """The scene of a scene file (its mesh paths stay relative to the file's folder)."""
        path = _path(path, "path")
        with open(path, encoding="utf-8") as f:
            text = f.read()
        scene = cls(_os.path.dirname(_os.path.abspath(path)))
        scene.name = path
        scene.doc = _native.parse_toml(text, path)
        return scene

    def _section(self, key, default):
        return self.doc.setdefault(key, default)

    def add_mesh(self, vertices, faces, *, normals=None, uvs=None, material=None, transform=None, name=None):
        """Add a mesh of (N, 3) float ``vertices`` and (M, 3) integer ``faces`` (0-based), with
        optional (N, 3) ``normals`` (else angle-weighted normals, as for an OBJ without them) and
        (N, 2) ``uvs`` (v pointing up, as in OBJ). ``material`` names a material of the scene;
        ``transform`` is a dict of ``translate``, ``rotate`` (degrees about x, y, z) and
        ``scale``. Returns the mesh's name in the scene file. The arrays are kept, not copied:
        do not change them before rendering."""
        name = name or f"mesh{len(self.meshes)}"
        file = f"{name}.obj"
        if file in self.meshes:
            raise ValueError(f"name: a mesh named '{name}' is already in the scene")
        self.meshes[file] = (vertices, faces, normals, uvs)
        self._add_object(file, material, transform)
        return name

    def add_object(self, path, *, material=None, transform=None):
        """Add a mesh file (.obj, .gltf, .glb), with its own materials unless ``material``
        names one of the scene's."""
        self._add_object(_path(path, "path"), material, transform)

    def _add_object(self, mesh, material, transform):
        obj = {"mesh": mesh}
        if material is not None:
            obj["material"] = material
        if transform is not None:
            obj["transform"] = dict(transform)
        _native.to_toml(obj, "object")  # a value no scene file can hold fails here, named
        self._section("object", []).append(obj)

    def add_material(self, name, model="lambert", **params):
        """Add material ``name`` of ``model`` (lambert, blinn-phong, cook-torrance) with
        scene-file keys (albedo, kd, two_sided, ks, shininess, specular_color, roughness,
        metallic, ior, d, g, fresnel, eta, k)."""
        material = {"model": model, **params}
        _native.to_toml(material, f"add_material('{name}')")
        self._section("material", {})[name] = material

    def add_light(self, type="point", **params):
        """Add a light of ``type`` (point, directional, spot) with its ``[[light]]`` keys
        (position, direction, look_at, intensity, irradiance, color, angles, range, ...)."""
        light = {"type": type, **params}
        _native.to_toml(light, "add_light")
        self._section("light", []).append(light)

    def set_camera(self, **params):
        """Set the camera's ``[camera]`` keys (position, look_at, up, fov, type, ...)."""
        _native.to_toml(params, "set_camera")
        self.doc["camera"] = dict(params)

    def set_film(self, **params):
        """Set the ``[film]`` keys (width, height, spp, sampler, seed, exposure, ...)."""
        _native.to_toml(params, "set_film")
        self._section("film", {}).update(params)

    def set_render(self, **params):
        """Set the ``[render]`` keys (shadows, shadow_offset, shadow_terminator, match)."""
        _native.to_toml(params, "set_render")
        self._section("render", {}).update(params)

    def to_toml(self):
        """The scene file of this scene (array meshes named ``NAME.obj``; see :meth:`save`)."""
        return _native.to_toml(self.doc, "Scene")

    def save(self, path):
        """Write the scene file to ``path`` and each array mesh beside it as ``NAME.obj``;
        relative mesh paths are rewritten to stay valid from the new folder."""
        path = _os.path.abspath(_path(path, "path"))
        folder = _os.path.dirname(path)
        doc = _copy.deepcopy(self.doc)
        for obj in doc.get("object", []):
            if obj["mesh"] not in self.meshes and not _os.path.isabs(obj["mesh"]):
                obj["mesh"] = _os.path.relpath(_os.path.join(self.base_dir, obj["mesh"]), folder)
        for file, (vertices, faces, normals, uvs) in self.meshes.items():
            _native.write_obj(_os.path.join(folder, file), vertices, faces, normals, uvs)
        with open(path, "w", encoding="utf-8") as f:
            f.write(_native.to_toml(doc, "Scene"))

    def export_mitsuba(self, path, *, spp=None, sampler=None, match=None, per_light=False):
        """Write the scene as Mitsuba 3 XML at ``path``, as ``pointshade export-mitsuba`` does:
        meshes Mitsuba cannot read, and every mesh given as arrays, are written beside it as
        PLY files. With ``match="mitsuba"`` it samples as ``render(scene, match="mitsuba")``
        does (the grid sampler), so the two images compare pixel by pixel. Returns the export's
        notes and what has no Mitsuba equivalent."""
        return _native.export_mitsuba(
            self.name, _path(path, "path"), text=self.to_toml(), dir=self.base_dir, meshes=self.meshes,
            spp=spp, sampler=sampler, matching=match, per_light=per_light,
        )

    def __repr__(self):
        counts = {k: len(self.doc.get(k, ())) for k in ("object", "material", "light")}
        return f"Scene({counts['object']} objects, {counts['material']} materials, {counts['light']} lights)"
