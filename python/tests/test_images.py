"""Saving and showing images from Python: the CLI's files byte for byte, sRGB arrays, notebook
display, and the normal-image call that must say which preset it follows."""

import numpy as np
import pytest

import pointshade
from conftest import REPO

CORNELL = REPO / "scenes" / "cornell-box.toml"
SIZE = dict(width=48, height=36, spp=4)


def test_a_render_saves_to_the_cli_files_byte_for_byte(cli, tmp_path):
    for exposure in (0.0, 1.5):
        flags = ["--width", 48, "--height", 36, "--spp", 4, "--exposure", exposure, "--quiet"]
        cli("render", CORNELL, "-o", tmp_path / "cli.png", *flags)
        cli("render", CORNELL, "-o", tmp_path / "cli.exr", *flags)
        out = pointshade.render(CORNELL, exposure=exposure, **SIZE)
        out.save(tmp_path / "py.png")
        pointshade.write_image(tmp_path / "py.exr", out["color"])
        pointshade.write_image(tmp_path / "explicit.png", out["color"], exposure=exposure)
        cli_png = (tmp_path / "cli.png").read_bytes()
        assert (tmp_path / "py.png").read_bytes() == cli_png
        assert (tmp_path / "explicit.png").read_bytes() == cli_png
        assert (tmp_path / "py.exr").read_bytes() == (tmp_path / "cli.exr").read_bytes()
        # A notebook shows the same PNG; the result is still the dict it was.
        assert out._repr_png_() == cli_png
        assert isinstance(out, dict) and out["color"].shape == (36, 48, 3)


def test_to_srgb8_holds_the_pixels_of_the_png(tmp_path):
    color = pointshade.render(CORNELL, **SIZE)["color"]
    pointshade.write_image(tmp_path / "a.png", color, exposure=-0.5)
    srgb = pointshade.to_srgb8(color, exposure=-0.5)
    assert srgb.dtype == np.uint8 and srgb.shape == (36, 48, 3)
    assert np.array_equal(pointshade.read_normal_image(tmp_path / "a.png"), srgb)
    # The sRGB curve itself (IEC 61966-2-1), clamping, and exposure as a power of two.
    ramp = np.array([[[0.0, 0.0031308, 0.5], [1.0, 2.0, -1.0], [0.25, 0.25, 0.25]]], np.float32)
    expected = [[[0, 10, 188], [255, 255, 0], [137, 137, 137]]]
    assert pointshade.to_srgb8(ramp).tolist() == expected
    assert pointshade.to_srgb8(ramp[:, 2:] / 2, exposure=1.0).tolist() == [expected[0][2:]]
    # uint8 arrays are written as they are, and read back so.
    pointshade.write_image(tmp_path / "b.png", srgb)
    assert np.array_equal(pointshade.read_normal_image(tmp_path / "b.png"), srgb)


def test_images_that_cannot_be_written_are_refused_and_nothing_is_written(tmp_path):
    bad = np.zeros((4, 5, 3), np.float32)
    bad[2, 3, 1] = np.nan
    with pytest.raises(ValueError, match=r"array: pixel \(x 3, y 2\) is not finite"):
        pointshade.write_image(tmp_path / "nan.png", bad)
    with pytest.raises(ValueError, match="exposure: must be a finite number"):
        pointshade.write_image(tmp_path / "inf.png", np.zeros((2, 2, 3)), exposure=float("inf"))
    with pytest.raises(ValueError, match="EXR .* cannot hold"):
        pointshade.write_image(tmp_path / "u8.exr", np.zeros((2, 2, 3), np.uint8))
    with pytest.raises(ValueError, match=r"expected shape \(H, W, 3\), got \[2, 2\]"):
        pointshade.write_image(tmp_path / "grey.png", np.zeros((2, 2), np.float32))
    with pytest.raises(pointshade.InputError, match="unsupported output type"):
        pointshade.write_image(tmp_path / "x.jpg", np.zeros((2, 2, 3)))
    with pytest.raises(pointshade.InputError, match="does not exist"):
        pointshade.write_image(tmp_path / "no" / "x.png", np.zeros((2, 2, 3)))
    assert list(tmp_path.iterdir()) == []


def test_a_normal_image_call_must_name_its_preset():
    normals = np.full((4, 4, 3), 128, np.uint8)
    with pytest.raises(TypeError, match="preset is required: preset='tp' .* or preset='physical'"):
        pointshade.shade_normal_image(normals, brdf="lambert")
