"""pointshade.explore: the explorer's server in a thread of the Python process."""

import json
import urllib.request

import pytest

import pointshade


def get(url):
    with urllib.request.urlopen(url, timeout=30) as reply:
        return reply.status, reply.read()


def test_explore_serves_the_page_and_renders_then_stops():
    with pointshade.explore() as explorer:
        assert explorer.url.startswith("http://127.0.0.1:")
        assert explorer.running
        assert f'src="{explorer.url}"' in explorer._repr_html_()
        status, page = get(explorer.url)
        assert status == 200 and b"explore.js" in page
        _, session = get(explorer.url + "api/session")
        state = json.loads(session)["state"]
        request = urllib.request.Request(explorer.url + "api/render", data=json.dumps(state).encode(), method="POST")
        with urllib.request.urlopen(request, timeout=60) as reply:
            assert reply.read().startswith(b"\x89PNG")
    assert not explorer.running
    assert "stopped" in explorer._repr_html_()
    explorer.stop()  # twice: nothing
    with pytest.raises(OSError):
        get(explorer.url)


def test_explore_errors_are_python_exceptions():
    with pytest.raises(FileNotFoundError):
        pointshade.explore("no/such/scene.toml")
    with pytest.raises(ValueError, match="port"):
        pointshade.explore(port=70000)
    with pytest.raises(TypeError, match="scene_or_image"):
        pointshade.explore(3)


def test_explore_takes_the_validation_folder_of_its_mitsuba(tmp_path):
    with pointshade.explore(mitsuba_dir=tmp_path / "no-validation") as explorer:
        _, session = get(explorer.url + "api/session")
        mitsuba = json.loads(session)["mitsuba"]
        assert mitsuba["available"] is False and mitsuba["installed"] is False
        assert "no-validation" in mitsuba["message"] and "install.sh" in mitsuba["message"]
    with pytest.raises(TypeError, match="mitsuba_dir"):
        pointshade.explore(mitsuba_dir=3)
