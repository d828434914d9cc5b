"""Every call in a process forked from one that used it (Python's multiprocessing on Linux,
fork its default before Python 3.14): the child inherits rayon's global pool without its
threads, so a call that ran its parallel work there would wait for ever. And a fork while
another thread is in a call: the child inherits no lock held by a thread it does not have."""

import json
import multiprocessing
import os
import signal
import tempfile
import threading
import time
import urllib.request
from pathlib import Path

import numpy as np
import pytest

import pointshade
from conftest import REPO

CORNELL = REPO / "scenes" / "cornell-box.toml"

# Large enough that the calls with parallel steps split their work (the blocks are 4,096 to
# 16,384 pixels or rows): work that is not split runs on the calling thread and would pass
# without the fix. Writing and reading a PNG's samples has no parallel step today (it answered
# before the fix too); it is here so that one added outside the process's workers shows.
SIDE = 256
ROWS = 200_000


def _normals():
    y, x = np.mgrid[0:SIDE, 0:SIDE] / (SIDE - 1) * 2 - 1
    z = np.sqrt(np.clip(1 - x * x - y * y, 0, 1))
    return np.round((np.stack([x, y, z], -1) * 0.5 + 0.5) * 255).astype(np.uint8)


def _float_image():
    return np.random.default_rng(3).random((SIDE, SIDE, 3), dtype=np.float32)


def _directions():
    rng = np.random.default_rng(5)
    d = rng.normal(size=(3, ROWS, 3))
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    d[:, :, 2] = np.abs(d[:, :, 2])
    return d


def _in_dir(write_and_read):
    with tempfile.TemporaryDirectory() as dir:
        return write_and_read(Path(dir))


def _explore_render():
    with pointshade.explore() as explorer:
        with urllib.request.urlopen(explorer.url + "api/session", timeout=60) as reply:
            state = json.loads(reply.read())["state"]
        request = urllib.request.Request(explorer.url + "api/render", data=json.dumps(state).encode(), method="POST")
        with urllib.request.urlopen(request, timeout=60) as reply:
            return reply.read()


_HELD = {}


def _preview_made_before_the_fork():
    # Made in the parent's call; the child's call renders the object it inherited.
    preview = _HELD.setdefault("preview", pointshade.Preview(CORNELL, width=96, height=72, spp=2))
    return preview.render()["color"]


CALLS = {
    "render": lambda: pointshade.render(CORNELL, width=96, height=72, spp=2)["color"],
    "Preview": lambda: pointshade.Preview(CORNELL, width=96, height=72, spp=2).render()["color"],
    "a Preview made before the fork": _preview_made_before_the_fork,
    "shade_normal_image": lambda: pointshade.shade_normal_image(_normals(), preset="tp", brdf="blinn-phong"),
    "eval_brdf": lambda: pointshade.eval_brdf({"model": "lambert"}, *_directions()),
    "compare": lambda: pointshade.compare(_float_image(), _float_image() * 1.01)["relative_error"],
    "to_srgb8": lambda: pointshade.to_srgb8(_float_image()),
    "png and read_normal_image": lambda: _in_dir(
        lambda d: (pointshade.write_image(d / "n.png", _normals()), pointshade.read_normal_image(d / "n.png"))[1]
    ),
    "exr and read_image": lambda: _in_dir(
        lambda d: (pointshade.write_image(d / "i.exr", _float_image()), pointshade.read_image(d / "i.exr"))[1]
    ),
    "export_mitsuba": lambda: _in_dir(
        lambda d: (pointshade.Scene.from_toml(CORNELL).export_mitsuba(d / "c.xml"), (d / "c.xml").read_text())[1]
        .replace(str(d), "DIR")
    ),
    "explore": _explore_render,
}


def _call(name):
    return CALLS[name]()


def _equal(a, b):
    if isinstance(a, np.ndarray):
        return a.shape == b.shape and a.dtype == b.dtype and a.tobytes() == b.tobytes()
    return a == b


@pytest.mark.parametrize("name", CALLS)
def test_a_call_in_a_forked_process_answers_as_in_its_parent(name):
    expected = _call(name)  # the parent's work on the global pool (started here if not before)
    with multiprocessing.get_context("fork").Pool(1) as pool:
        try:
            got = pool.apply_async(_call, (name,)).get(timeout=60)
        except multiprocessing.TimeoutError:
            pytest.fail(f"{name} gave no answer in 60 s in a forked process (waiting on its parent's threads)")
    assert _equal(got, expected)


def _exit_code_of_forked(child, waiting_for):
    """Forks; the child runs `child()` and exits with the code it returns (1 if it raises). The
    parent waits up to 30 s for it, then kills it and fails the test."""
    pid = os.fork()
    if pid == 0:
        code = 1
        try:
            code = child()
        finally:
            os._exit(code)
    deadline = time.monotonic() + 30
    while (waited := os.waitpid(pid, os.WNOHANG)) == (0, 0) and time.monotonic() < deadline:
        time.sleep(0.01)
    if waited == (0, 0):
        os.kill(pid, signal.SIGKILL)
        os.waitpid(pid, 0)
        pytest.fail(f"the forked child waited 30 s {waiting_for}")
    assert os.WIFEXITED(waited[1]), f"the forked child ended by a signal: status {waited[1]:#x}"
    return os.WEXITSTATUS(waited[1])


# Python 3.12+ warns that a fork in a threaded process may deadlock the child: that is the test.
@pytest.mark.filterwarnings("ignore:This process .* is multi-threaded")
def test_a_process_forked_while_another_thread_loads_a_file_can_load_one():
    # A load holds a process-wide lock (the confinement's turn) while it decodes, without the GIL.
    # A child forked meanwhile inherits that lock held by a thread it does not have; the
    # module's fork handlers (pointshade::process_fork) make the fork wait for the load to end
    # instead. The thread loads a large PNG again and again, so the forks below land in a load
    # almost surely; a child that waits on the lock is killed after 30 s and fails the test.
    with tempfile.TemporaryDirectory() as dir:
        path = Path(dir) / "large.png"
        rng = np.random.default_rng(7)
        pointshade.write_image(path, rng.integers(0, 256, size=(2048, 2048, 3), dtype=np.uint8))
        stop = threading.Event()

        def load_again_and_again():
            while not stop.is_set():
                pointshade.read_normal_image(path)

        def load_once():
            pointshade.read_normal_image(path)
            return 0

        loader = threading.Thread(target=load_again_and_again)
        loader.start()
        try:
            for _ in range(5):
                time.sleep(0.01)
                assert _exit_code_of_forked(load_once, "on the load's lock") == 0
        finally:
            stop.set()
            loader.join()


@pytest.mark.filterwarnings("ignore:This process .* is multi-threaded")
def test_a_preview_rendering_in_another_thread_at_the_fork_is_an_error_in_the_child():
    # The render holds the preview's lock, and its thread does not come along: the child's call
    # must say so instead of waiting for a release that never comes.
    preview = pointshade.Preview(CORNELL, width=256, height=192, spp=256)
    renderer = threading.Thread(target=preview.render)
    renderer.start()
    try:
        time.sleep(0.1)

        def refused():
            try:
                preview.materials
            except RuntimeError as e:
                return 0 if "make a new Preview" in str(e) else 2
            return 3

        code = _exit_code_of_forked(refused, "for a render of its parent's thread")
        assert code == 0, "the child's call answered (3) or raised another RuntimeError (2): " + str(code)
    finally:
        renderer.join()
