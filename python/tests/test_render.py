"""render(): equal to the CLI bit for bit, from files and from scenes built in Python."""

import multiprocessing
import signal
import threading
import time

import numpy as np
import pytest

import pointshade
from conftest import REPO, sphere

CORNELL = REPO / "scenes" / "cornell-box.toml"


def same_bits(a, b):
    return a.shape == b.shape and a.dtype == b.dtype and a.tobytes() == b.tobytes()


def test_a_shipped_scene_equals_the_cli_exr_bit_for_bit(cli, tmp_path):
    exr = tmp_path / "cornell.exr"
    cli("render", CORNELL, "-o", exr, "--width", 64, "--height", 48, "--spp", 4, "--aov", "normal,depth", "--quiet")
    out = pointshade.render(CORNELL, width=64, height=48, spp=4, aovs=["normal", "depth"])
    assert out["color"].dtype == np.float32 and out["color"].flags["C_CONTIGUOUS"]
    assert out["color"].shape == (48, 64, 3)
    assert same_bits(out["color"], pointshade.read_image(exr))
    for aov in ("normal", "depth"):
        assert same_bits(out[aov], pointshade.read_image(tmp_path / f"cornell.{aov}.exr"))
    s = out["stats"]
    assert s["primary_rays"] == 64 * 48 * 4 and s["spp"] == 4 and s["frame"] == (64, 48)
    assert s["shadow_rays"] > 0 and s["triangles"] > 0 and s["render_seconds"] > 0


@pytest.mark.parametrize("scene", ["lambert.toml", "mixed-lights.toml", "validation/spot.toml"])
def test_overrides_match_the_cli_options(cli, tmp_path, scene):
    path = REPO / "scenes" / scene
    exr = tmp_path / "out.exr"
    cli("render", path, "-o", exr, "--width", 40, "--height", 30, "--spp", 3, "--sampler", "independent",
        "--seed", 7, "--shadow-offset", "mitsuba", "--view", "30,20,1.5", "--quiet")
    out = pointshade.render(path, width=40, height=30, spp=3, sampler="independent", seed=7,
                            shadow_offset="mitsuba", view=(30, 20, 1.5))
    assert same_bits(out["color"], pointshade.read_image(exr))


def test_a_crop_is_that_part_of_the_frame():
    full = pointshade.render(CORNELL, width=48, height=32, spp=2)["color"]
    crop = pointshade.render(CORNELL, width=48, height=32, spp=2, crop=(8, 4, 40, 20))
    assert crop["stats"]["region"] == (8, 4, 40, 20)
    assert same_bits(crop["color"], np.ascontiguousarray(full[4:20, 8:40]))


def write_obj(path, v, f, n=None, uv=None):
    with open(path, "w") as out:
        for x in v:
            out.write("v %r %r %r\n" % tuple(float(c) for c in x))
        for x in uv if uv is not None else []:
            out.write("vt %r %r\n" % tuple(float(c) for c in x))
        for x in n if n is not None else []:
            out.write("vn %r %r %r\n" % tuple(float(c) for c in x))
        for tri in f:
            i = [int(k) + 1 for k in tri]
            if n is not None and uv is not None:
                out.write("f " + " ".join(f"{k}/{k}/{k}" for k in i) + "\n")
            elif n is not None:
                out.write("f " + " ".join(f"{k}//{k}" for k in i) + "\n")
            else:
                out.write("f " + " ".join(str(k) for k in i) + "\n")


def lit_scene(base_dir):
    s = pointshade.Scene(base_dir)
    s.add_material("glossy", "cook-torrance", albedo=[0.6, 0.4, 0.2], roughness=0.25)
    s.add_light("point", position=[2.0, 3.0, 4.0], intensity=30.0)
    s.add_light("directional", direction=[-0.3, -1.0, -0.2], intensity=0.5)
    s.set_camera(position=[0.5, 1.0, 3.5], look_at=[0.0, 0.0, 0.0], fov=45.0)
    s.set_film(width=40, height=30, spp=2)
    return s


@pytest.mark.parametrize("attributes", ["positions", "normals", "normals+uvs"])
def test_a_mesh_from_arrays_renders_as_the_same_mesh_read_from_obj(tmp_path, attributes):
    v, f, n, uv = sphere()
    n = n if "normals" in attributes else None
    uv = uv if "uvs" in attributes else None
    write_obj(tmp_path / "sphere.obj", v, f, n, uv)
    from_file = lit_scene(tmp_path)
    from_file.add_object("sphere.obj", material="glossy", transform={"scale": 0.8, "rotate": [10.0, 20.0, 0.0]})
    from_arrays = lit_scene(tmp_path)
    from_arrays.add_mesh(v.astype(np.float32), f.astype(np.int32), normals=n, uvs=uv, material="glossy",
                         transform={"scale": 0.8, "rotate": [10.0, 20.0, 0.0]})
    a = pointshade.render(from_file)["color"]
    b = pointshade.render(from_arrays)["color"]
    assert a.std() > 0 and same_bits(a, b)


def test_to_toml_round_trips_and_the_saved_file_renders_the_same(cli, tmp_path):
    v, f, n, _ = sphere()
    scene = lit_scene(tmp_path)
    scene.add_mesh(v, f, normals=n, material="glossy", name="ball")
    scene.add_object(REPO / "meshes" / "plane.obj", transform={"translate": [0.0, -1.0, 0.0], "scale": 3.0})
    text = scene.to_toml()
    (tmp_path / "saved").mkdir()
    scene.save(tmp_path / "saved" / "scene.toml")
    again = pointshade.Scene.from_toml(tmp_path / "saved" / "scene.toml")
    assert again.to_toml() == text  # absolute mesh paths and the array mesh's name are kept
    assert again.doc == scene.doc
    ours = pointshade.render(scene)["color"]
    cli("render", tmp_path / "saved" / "scene.toml", "-o", tmp_path / "cli.exr", "--quiet")
    assert same_bits(ours, pointshade.read_image(tmp_path / "cli.exr"))
    assert same_bits(ours, pointshade.render(tmp_path / "saved" / "scene.toml")["color"])


def test_export_mitsuba_writes_the_cli_xml(cli, tmp_path):
    scene = pointshade.Scene.from_toml(REPO / "scenes" / "validation" / "diffuse-sphere.toml")
    scene.export_mitsuba(tmp_path / "py.xml", spp=4)
    cli("export-mitsuba", REPO / "scenes" / "validation" / "diffuse-sphere.toml", "-o", tmp_path / "cli.xml", "--spp", 4)
    assert (tmp_path / "py.xml").read_text() == (tmp_path / "cli.xml").read_text()
    # A scene built from arrays: test_mitsuba.py renders its export in Mitsuba.


def test_two_threads_render_at_once_and_give_what_one_thread_gives():
    expected = pointshade.render(CORNELL, width=64, height=48, spp=8, threads=1)["color"]
    results = [None, None]

    def work(k):
        results[k] = pointshade.render(CORNELL, width=64, height=48, spp=8, threads=1)["color"]

    threads = [threading.Thread(target=work, args=(k,)) for k in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert all(same_bits(r, expected) for r in results)


def _small_render_on_two_threads():
    return pointshade.render(CORNELL, width=32, height=24, spp=2, threads=2)["color"]


def test_a_forked_process_renders_on_threads_of_its_own():
    # The parent's pool of two threads is kept for its next call; a process forked from it
    # inherits that pool but not its threads, and must start its own instead of waiting on them.
    expected = _small_render_on_two_threads()
    with multiprocessing.get_context("fork").Pool(1) as pool:
        color = pool.apply_async(_small_render_on_two_threads).get(timeout=120)
    assert same_bits(color, expected)


def test_keyboard_interrupt_stops_a_long_render():
    # A process started in the background by a shell without job control inherits SIGINT
    # ignored, and Python then installs no KeyboardInterrupt handler, so interrupt_main would do
    # nothing: the handler a terminal's Python has is installed for this test.
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        # Minutes of work on one thread; interrupted after 0.5 s it must stop within about a second.
        timer = threading.Timer(0.5, __import__("_thread").interrupt_main)
        start = time.monotonic()
        timer.start()
        with pytest.raises(KeyboardInterrupt):
            pointshade.render(CORNELL, width=640, height=480, spp=4096, threads=1)
        elapsed = time.monotonic() - start
        timer.cancel()
    finally:
        signal.signal(signal.SIGINT, previous)
    assert elapsed < 5.0, f"the render went on for {elapsed - 0.5:.1f} s after the interrupt"


def test_scene_warnings_are_python_warnings(tmp_path):
    scene = pointshade.Scene(tmp_path)
    with pytest.warns(UserWarning, match="no \\[\\[object\\]\\]"):
        out = pointshade.render(scene, width=8, height=8, spp=1)
    assert out["color"].max() == 0.0


def test_the_stub_lists_every_render_keyword_of_the_library():
    import ast

    stub = ast.parse((REPO / "python" / "pointshade" / "__init__.pyi").read_text())
    render = next(f for f in stub.body if isinstance(f, ast.FunctionDef) and f.name == "render")
    keywords = [a.arg for a in render.args.kwonlyargs]
    table = [name for name, _, _ in pointshade._native.render_option_table()]
    assert keywords == ["confine", "progress", "quiet", *table]
    for name in table:
        assert f"``{name}``" in pointshade.render.__doc__


def test_progress_reaches_a_callable_on_the_calling_thread_up_to_the_whole_render():
    calls = []
    caller = threading.get_ident()

    def record(done, total, unit):
        calls.append((done, total, unit, threading.get_ident()))

    out = pointshade.render(CORNELL, width=160, height=120, spp=16, threads=1, progress=record)
    assert out["color"].std() > 0
    assert calls, "no progress reported"
    assert all(t == caller for *_, t in calls)
    dones = [d for d, *_ in calls]
    assert dones == sorted(dones) and len(set(dones)) == len(dones)
    done, total, unit, _ = calls[-1]
    assert (done, unit) == (total, "tiles") and total > 1
    # quiet wins over a callable.
    calls.clear()
    pointshade.render(CORNELL, width=16, height=12, spp=1, progress=record, quiet=True)
    assert calls == []
    with pytest.raises(TypeError, match="^progress: expected None, True, False or a callable"):
        pointshade.render(CORNELL, width=16, height=12, progress="yes")


def test_an_exception_raised_by_the_progress_callable_stops_the_render():
    class Enough(Exception):
        pass

    def stop(done, total, unit):
        raise Enough()

    start = time.monotonic()
    with pytest.raises(Enough):
        pointshade.render(CORNELL, width=640, height=480, spp=4096, threads=1, progress=stop)
    assert time.monotonic() - start < 5.0


def test_the_default_progress_line_is_drawn_on_a_terminal_only(monkeypatch):
    drawn = []

    class Line:
        def __call__(self, done, total, unit):
            drawn.append(done)

        def close(self):
            pass

    class Terminal:
        def isatty(self):
            return True

        def write(self, text):
            pass

        def flush(self):
            pass

    monkeypatch.setattr(pointshade, "_StderrBar", Line)
    small = {"width": 32, "height": 24, "spp": 1}
    pointshade.render(CORNELL, **small)  # pytest captures stderr: no terminal
    assert drawn == []
    monkeypatch.setattr(pointshade._sys, "stderr", Terminal())
    for off in ({"quiet": True}, {"progress": False}):
        pointshade.render(CORNELL, **small, **off)
        assert drawn == []
    pointshade.render(CORNELL, **small)
    assert drawn, "no progress line on a terminal"
