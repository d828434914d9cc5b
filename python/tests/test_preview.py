"""pointshade.Preview: each render is render()'s image of the edited scene, bit for bit, and an
edit that leaves the view alone traces no camera ray."""

import subprocess
import sys
import textwrap

import numpy as np
import pytest

import pointshade
from conftest import REPO

SCENE = REPO / "scenes" / "mixed-lights.toml"
SMALL = dict(width=64, height=48, spp=2)


def same_bits(a, b):
    return a.shape == b.shape and np.array_equal(a.view(np.uint32), b.view(np.uint32))


def edited(**materials):
    """The scene file's Scene with materials replaced, as a Scene a render() takes."""
    scene = pointshade.Scene.from_toml(SCENE)
    for name, (model, params) in materials.items():
        scene.add_material(name, model, **params)
    return scene


def test_material_and_light_edits_render_as_the_edited_scene_without_tracing_the_view():
    preview = pointshade.Preview(SCENE, aovs=["normal"], **SMALL)
    assert "teal" in preview.materials
    first = preview.render()
    assert same_bits(first["color"], pointshade.render(SCENE, aovs=["normal"], **SMALL)["color"])
    assert first["stats"]["primary_rays"] == 64 * 48 * 2

    preview.set_material("teal", "cook-torrance", roughness=0.3, albedo=[0.2, 0.4, 0.6])
    second = preview.render()
    want = pointshade.render(edited(teal=("cook-torrance", dict(roughness=0.3, albedo=[0.2, 0.4, 0.6]))),
                             aovs=["normal"], **SMALL)
    assert same_bits(second["color"], want["color"])
    assert same_bits(second["normal"], want["normal"])
    assert not same_bits(second["color"], first["color"])
    stats = second["stats"]
    assert (stats["primary_rays"], stats["shadow_rays"]) == (0, 0)
    assert stats["shadow_rays_reused"] == first["stats"]["shadow_rays"]

    # A moved light: its rays are traced, the others reused; the image is the scene file's.
    lights = [
        {"type": "point", "position": [-3.0, 4.5, 2.0], "color": [1.0, 0.8, 0.55], "intensity": 30.0},
        {"type": "directional", "direction": [-0.3, -1.0, -0.5], "color": [0.55, 0.7, 1.0], "intensity": 0.35},
    ]
    preview.set_lights(lights)
    third = preview.render()
    scene = edited(teal=("cook-torrance", dict(roughness=0.3, albedo=[0.2, 0.4, 0.6])))
    scene.doc["light"] = lights
    assert same_bits(third["color"], pointshade.render(scene, **SMALL)["color"])
    assert third["stats"]["primary_rays"] == 0
    assert third["stats"]["shadow_rays"] > 0 and third["stats"]["shadow_rays_reused"] > 0


def test_a_new_camera_is_a_new_view_traced_with_the_same_tree():
    preview = pointshade.Preview(SCENE, **SMALL)
    preview.render()
    camera = dict(position=[5.0, 6.0, 9.0], look_at=[0.0, 0.5, 0.0], fov=40.0)
    preview.set_camera(**camera)
    got = preview.render()
    scene = pointshade.Scene.from_toml(SCENE)
    scene.set_camera(**camera)
    assert same_bits(got["color"], pointshade.render(scene, **SMALL)["color"])
    assert got["stats"]["primary_rays"] == 64 * 48 * 2
    with pytest.raises(pointshade.InputError, match="set_camera: a perspective camera needs fov"):
        preview.set_camera(position=[5.0, 6.0, 9.0], look_at=[0.0, 0.5, 0.0])


def test_bad_edits_are_input_errors_that_change_nothing():
    preview = pointshade.Preview(SCENE, **SMALL)
    before = preview.render()["color"]
    with pytest.raises(pointshade.InputError, match=r"set_material: material 'teal': roughness must be in \[0, 1\], got 1.5"):
        preview.set_material("teal", "cook-torrance", roughness=1.5)
    with pytest.raises(ValueError, match="roughness: NaN is not a finite number"):
        preview.set_material("teal", "cook-torrance", roughness=float("nan"))
    with pytest.raises(pointshade.InputError, match="no material 'gold' .*'teal'"):
        preview.set_material("gold", "lambert")
    with pytest.raises(pointshade.InputError, match="set_lights: light 1: light intensity must be finite"):
        preview.set_lights([{"type": "point", "position": [0, 1, 0], "intensity": -1.0}])
    with pytest.raises(TypeError, match="lights"):
        preview.set_lights({"type": "point"})
    after = preview.render()
    assert same_bits(after["color"], before)
    assert after["stats"]["shadow_rays"] == 0, "the kept frame survives refused edits"


def test_a_sampler_that_adapts_to_the_shading_is_refused():
    with pytest.raises(pointshade.InputError, match="fixed number of samples per pixel"):
        pointshade.Preview(SCENE, sampler="adaptive", **SMALL)


def test_a_preview_used_by_two_threads_at_once_answers_both():
    # A render holds the preview while it takes the GIL now and then (to see Ctrl-C). A second
    # thread's call on the same preview waits for it without the GIL; waiting with it, both threads
    # would wait for ever. In a process of its own, so that such a wait fails this test instead of
    # hanging the run.
    script = textwrap.dedent(
        f"""
        import threading, time
        import pointshade
        preview = pointshade.Preview({str(SCENE)!r}, width=256, height=192, spp=256)
        rendered = []
        renderer = threading.Thread(target=lambda: rendered.append(preview.render()))
        renderer.start()
        time.sleep(0.1)
        names = preview.materials
        renderer.join()
        assert "teal" in names and rendered[0]["color"].shape == (192, 256, 3)
        print("both answered")
        """
    )
    try:
        done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=60)
    except subprocess.TimeoutExpired:
        pytest.fail("a second thread's call on a rendering Preview and the render waited for each other")
    assert done.returncode == 0 and "both answered" in done.stdout, done.stderr
