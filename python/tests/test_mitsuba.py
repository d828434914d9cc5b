"""Mitsuba 3 round trips from Python: a Scene built from arrays exports every mesh it refers to,
Mitsuba renders the export, and render(..., match="mitsuba") agrees with it pixel by pixel.

Mitsuba runs in an interpreter that imports it: this one, else validation/.venv/bin/python
(validation/install.sh makes it; CI runs that before these tests). Without one, the Mitsuba
render is skipped with its reason in pytest's summary; the export's own checks always run."""

import os
import re
import subprocess
import sys

import numpy as np
import pytest

import pointshade
from conftest import REPO, sphere

VALIDATION = REPO / "validation"


def mitsuba_python():
    for python in (sys.executable, VALIDATION / ".venv" / "bin" / "python"):
        if python and os.path.isfile(python):
            if subprocess.run([str(python), "-c", "import mitsuba"], capture_output=True).returncode == 0:
                return str(python)
    return None


def built_scene(base_dir):
    """A smooth sphere over a ground square, both from arrays, one point light: shadows, a
    highlight and a terminator, everything pixel-exact comparison is sensitive to."""
    s = pointshade.Scene(base_dir)
    s.add_material("copper", "cook-torrance", kd=0.0, roughness=0.3, g="smith-ggx", fresnel="conductor",
                   eta=[0.2, 0.924, 1.102], k=[3.912, 2.452, 2.142])
    s.add_material("floor", "lambert", albedo=[0.7, 0.7, 0.7])
    v, f, n, _ = sphere(16, 24)
    s.add_mesh(v, f, normals=n, material="copper", name="ball")
    ground_v = np.array([[-3.0, -1.0, -3.0], [3.0, -1.0, -3.0], [3.0, -1.0, 3.0], [-3.0, -1.0, 3.0]])
    s.add_mesh(ground_v, np.array([[0, 2, 1], [0, 3, 2]]), material="floor", name="ground")
    s.add_light("point", position=[2.0, 4.0, 3.0], intensity=40.0)
    s.set_camera(position=[0.0, 1.5, 5.0], look_at=[0.0, -0.2, 0.0], fov=40.0)
    s.set_film(width=96, height=72, spp=1)
    return s


# The settings compared with Mitsuba's render (docs/validation.md, "Like for like", quotes what
# `pytest python/tests/test_mitsuba.py -s` prints).
SETTINGS = {
    "defaults": {},
    "sampler=grid": {"sampler": "grid"},
    "shadow_offset=mitsuba": {"shadow_offset": "mitsuba"},
    "match=mitsuba": {"match": "mitsuba"},
}


def test_a_scene_from_arrays_exports_every_mesh_and_mitsuba_renders_it_like_pointshade(tmp_path):
    scene = built_scene(tmp_path)
    out = tmp_path / "export"
    out.mkdir()
    xml = out / "built.xml"
    scene.export_mitsuba(xml, match="mitsuba")
    text = xml.read_text()
    names = re.findall(r'name="filename" value="([^"]+)"', text)
    assert len(names) == 2, text
    for name in names:
        assert (out / name).is_file(), f"{xml} refers to {name}, which the export did not write"

    python = mitsuba_python()
    if python is None:
        pytest.skip("Mitsuba 3 is not installed (validation/install.sh makes validation/.venv)")
    reference = tmp_path / "mitsuba.exr"
    run = subprocess.run([python, str(VALIDATION / "render.py"), "--out", str(reference), str(xml)],
                         capture_output=True, text=True, cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    ref = pointshade.read_image(reference)
    share = {}
    for name, settings in SETTINGS.items():
        share[name] = pointshade.compare(pointshade.render(scene, **settings)["color"], ref)["within_tolerance"]
        print(f"{name:<24} {share[name]:8.3%} of the pixels within 1e-3 of Mitsuba 3")  # pytest -s shows it
    assert share["match=mitsuba"] >= 0.999, share
    # Each setting alone falls short: the sample positions and the shadow offset both matter.
    assert all(share[name] < share["match=mitsuba"] for name in SETTINGS if name != "match=mitsuba"), share


def test_match_sets_the_sampler_and_offset_and_refuses_a_contradiction(tmp_path):
    scene = built_scene(tmp_path)
    matched = pointshade.render(scene, match="mitsuba")["color"]
    explicit = pointshade.render(scene, sampler="grid", shadow_offset="mitsuba")["color"]
    assert matched.tobytes() == explicit.tobytes()
    with pytest.raises(pointshade.InputError, match="match: mitsuba renders with the grid sampler, but sampler is sobol"):
        pointshade.render(scene, match="mitsuba", sampler="sobol")
    with pytest.raises(pointshade.InputError, match="expected mitsuba"):
        pointshade.render(scene, match="pbrt")
    scene.set_render(match="mitsuba")
    assert pointshade.render(scene)["color"].tobytes() == matched.tobytes()
    scene.set_render(match="mitsuba", shadow_offset="error-bound")
    with pytest.raises(pointshade.InputError, match=r"\[render\] shadow_offset is error-bound"):
        pointshade.render(scene)
