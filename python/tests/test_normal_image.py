"""shade_normal_image(): the CLI's images from arrays and paths; eval_brdf() is the renderer's f_r."""

import numpy as np
import pytest
from PIL import Image

import pointshade
from conftest import REPO

BRDFS = ["lambert", "blinn-phong", "cook-torrance"]


def png_pixels(path):
    return np.asarray(Image.open(path).convert("RGB"))


@pytest.fixture(scope="module")
def baked(tmp_path_factory):
    """A normal image baked from a shipped scene: what the tour shades without ../shared."""
    from conftest import cli_binary
    import subprocess

    path = tmp_path_factory.mktemp("baked") / "torus.png"
    subprocess.run([str(cli_binary()), "bake", str(REPO / "scenes" / "cook-torrance.toml"), "-o", str(path),
                    "--width", "96", "--height", "72", "--quiet"], check=True)
    return path


@pytest.mark.parametrize("brdf", BRDFS)
def test_the_three_tp_images_equal_the_cli_pngs(cli, tmp_path, shared, brdf):
    normal = shared / "normalmaps" / "normal.png"
    cli("normalmap", normal, "--preset", "tp", "--brdf", brdf, "-o", tmp_path / "cli.png", "--quiet")
    lo, eight = pointshade.shade_normal_image(normal, preset="tp", brdf=brdf, return_8bit=True)
    assert eight.dtype == np.uint8 and eight.shape == lo.shape
    assert np.array_equal(eight, png_pixels(tmp_path / "cli.png"))


@pytest.mark.parametrize("preset", ["tp", "physical"])
def test_an_array_shades_as_its_png_and_as_the_cli_exr(cli, tmp_path, baked, preset):
    rgba = np.asarray(Image.open(baked))
    assert rgba.shape[2] == 4 and rgba.dtype == np.uint8
    from_path = pointshade.shade_normal_image(baked, preset=preset, brdf="cook-torrance")
    from_array = pointshade.shade_normal_image(rgba, preset=preset, brdf="cook-torrance")
    assert from_array.dtype == np.float32 and from_array.tobytes() == from_path.tobytes()
    cli("normalmap", baked, "--preset", preset, "--brdf", "cook-torrance", "-o", tmp_path / "cli.exr", "--quiet")
    assert from_array.tobytes() == pointshade.read_image(tmp_path / "cli.exr").tobytes()


def test_sixteen_bit_samples_are_read_at_their_depth(baked):
    rgb8 = np.asarray(Image.open(baked))[..., :3]
    rgb16 = rgb8.astype(np.uint16) * 257  # the same values at 16 bits: v·257/65535 = v/255
    a = pointshade.shade_normal_image(np.ascontiguousarray(rgb8), preset="physical", brdf="blinn-phong")
    b = pointshade.shade_normal_image(rgb16, preset="physical", brdf="blinn-phong")
    assert np.allclose(a, b, rtol=1e-6, atol=1e-7) and a.max() > 0


def test_rgba_arrays_read_in_place_shade_as_converted_ones(baked):
    # (H, W, 4) uint8 and uint16 arrays are read where they lie; three channels are converted
    # to RGBA first. Both ways give the same bits, and the caller's array is left as it was.
    # (Writing to it afterwards would prove nothing: numpy's borrow flags bind Rust code only.)
    rgba8 = np.asarray(Image.open(baked))
    assert not rgba8.flags.writeable  # PIL's arrays are read-only: an in-place read must accept them
    rgba16 = rgba8.astype(np.uint16) * 257  # the same levels at 16 bits, writeable
    before = rgba16.copy()
    opaque = np.ascontiguousarray(rgba8[..., :3])  # converted, alpha at full scale
    for brdf in BRDFS:
        in_place = pointshade.shade_normal_image(rgba8, preset="tp", brdf=brdf)
        assert in_place.max() > 0
        assert pointshade.shade_normal_image(rgba16, preset="tp", brdf=brdf).tobytes() == in_place.tobytes()
        assert pointshade.shade_normal_image(opaque, preset="tp", brdf=brdf).tobytes() == in_place.tobytes()
    assert np.array_equal(rgba16, before)


@pytest.mark.parametrize("preset", ["tp", "physical"])
def test_float_samples_are_the_integers_divided_by_full_scale(baked, preset):
    rgba = np.asarray(Image.open(baked))
    ints = pointshade.shade_normal_image(rgba, preset=preset, brdf="cook-torrance")
    for dtype in (np.float32, np.float64):
        floats = pointshade.shade_normal_image(rgba.astype(dtype) / dtype(255), preset=preset, brdf="cook-torrance")
        assert floats.dtype == np.float32 and np.allclose(floats, ints, rtol=1e-5, atol=1e-6 * ints.max())


def test_material_lights_and_camera_are_the_scene_file_keys(baked):
    rgba = np.asarray(Image.open(baked))
    default = pointshade.shade_normal_image(rgba, preset="physical", material={"model": "cook-torrance"})
    rough = pointshade.shade_normal_image(rgba, preset="physical", material={"model": "cook-torrance", "roughness": 0.6})
    moved = pointshade.shade_normal_image(rgba, preset="physical", brdf="lambert",
                                          lights=[{"type": "directional", "direction": [0.0, 0.0, -1.0]}])
    assert not np.array_equal(default, rough) and moved.max() > 0


def test_eval_brdf_is_the_renderers_value_at_the_same_point():
    """A flat quad of normal +z seen by an orthographic camera straight down (ω_o = +z), under one
    directional light of irradiance 1: each pixel is f_r(n, ω_i, ω_o) · cos θ_i."""
    material = {"model": "cook-torrance", "albedo": [0.3, 0.5, 0.7], "roughness": 0.2, "fresnel": "schlick-sg"}
    v = np.array([[-2.0, -2.0, 0.0], [2.0, -2.0, 0.0], [2.0, 2.0, 0.0], [-2.0, 2.0, 0.0]])
    f = np.array([[0, 1, 2], [0, 2, 3]])
    wi = np.array([0.0, 0.6, 0.8])
    s = pointshade.Scene()
    s.add_material("m", **material)
    s.add_mesh(v, f, normals=np.tile([0.0, 0.0, 1.0], (4, 1)), material="m")
    s.add_light("directional", direction=(-wi).tolist(), intensity=1.0)
    s.set_camera(type="orthographic", position=[0.0, 0.0, 5.0], look_at=[0.0, 0.0, 0.0], scale=1.0)
    s.set_film(width=8, height=8, spp=1, sampler="grid")
    s.set_render(shadows=False)
    pixel = pointshade.render(s)["color"][4, 4]
    n = np.array([[0.0, 0.0, 1.0]])
    fr = pointshade.eval_brdf(material, n, wi[None], n)[0]
    assert fr.dtype == np.float32
    assert np.allclose(pixel, fr * np.float32(0.8), rtol=2e-6, atol=0)
    f64 = pointshade.eval_brdf(material, n, wi[None], n, precision="float64")
    assert f64.dtype == np.float64 and np.allclose(f64, fr, rtol=1e-6)


def test_eval_brdf_is_reciprocal_and_zero_below_the_surface():
    rng = np.random.default_rng(1)
    wi = rng.normal(size=(1000, 3))
    wo = rng.normal(size=(1000, 3))
    wi /= np.linalg.norm(wi, axis=1, keepdims=True)
    wo /= np.linalg.norm(wo, axis=1, keepdims=True)
    n = np.tile([0.0, 0.0, 1.0], (1000, 1))
    m = {"model": "cook-torrance", "roughness": 0.3, "two_sided": False}
    a = pointshade.eval_brdf(m, n, wi, wo, precision="float64")
    b = pointshade.eval_brdf(m, n, wo, wi, precision="float64")
    assert np.array_equal(a, b)
    below = (wi[:, 2] <= 0) | (wo[:, 2] <= 0)
    assert np.all(a[below] == 0) and np.all(a[~below] > 0)


def test_eval_terms_multiply_to_f_r():
    rng = np.random.default_rng(2)
    w = rng.normal(size=(2, 500, 3))
    w[..., 2] = np.abs(w[..., 2]) + 0.1
    w /= np.linalg.norm(w, axis=2, keepdims=True)
    n = np.tile([0.0, 0.0, 1.0], (500, 1))
    m = {"model": "cook-torrance", "roughness": 0.4, "kd": 0.0, "d": "beckmann", "g": "smith-ggx"}
    t = pointshade.eval_terms(m, n, w[0], w[1])
    expected = (t["D"] * t["G"] / (4 * w[0][:, 2] * w[1][:, 2]))[:, None] * t["F"]
    assert np.allclose(t["f_r"], expected, rtol=1e-12)


def test_eval_terms_are_zero_where_f_r_is():
    # ω_i below the surface: f_r is 0, and so are the terms (G was once −79 here).
    n = np.array([[0.0, 0.0, 1.0]])
    wi = np.array([[0.6, 0.0, -0.8]])
    wo = np.array([[0.0, 0.0, 1.0]])
    t = pointshade.eval_terms({"model": "cook-torrance", "roughness": 0.3, "two_sided": False}, n, wi, wo)
    assert t["D"][0] == 0 and t["G"][0] == 0 and np.all(t["F"][0] == 0) and np.all(t["f_r"][0] == 0)
    # Two-sided: n turns towards ω_o first, as f_r's does, so the terms are those of the mirrored frame.
    above = wi * [1, 1, -1]
    flipped = pointshade.eval_terms({"model": "cook-torrance", "roughness": 0.3}, -n, above, wo)
    plain = pointshade.eval_terms({"model": "cook-torrance", "roughness": 0.3}, n, above, wo)
    assert plain["G"][0] > 0
    for k in ("D", "G", "F", "f_r"):
        assert np.array_equal(flipped[k], plain[k])


def test_float64_evaluates_the_float32_parameters_the_renderer_stores():
    # GGX D and separable Smith G at α = 0.3, ω_o at 45°, ω_i swept through the plane of incidence.
    angles = np.radians(np.linspace(-85, 85, 341))
    count = len(angles)
    n = np.tile([0.0, 0.0, 1.0], (count, 1))
    wo = np.tile([np.sin(np.pi / 4), 0.0, np.cos(np.pi / 4)], (count, 1))
    wi = np.stack([np.sin(angles), np.zeros(count), np.cos(angles)], axis=-1)
    material = {"model": "cook-torrance", "roughness": 0.3, "d": "ggx", "g": "smith-ggx"}
    t = pointshade.eval_terms(material, n, wi, wo)
    h = (wi + wo) / np.linalg.norm(wi + wo, axis=1)[:, None]

    def d_and_g(a):
        d = a * a / (np.pi * (h[:, 2] ** 2 * (a * a - 1) + 1) ** 2)
        g1 = lambda c: 2 * c / (c + np.sqrt(a * a + (1 - a * a) * c * c))  # noqa: E731
        return d, g1(wi[:, 2]) * g1(wo[:, 2])

    def worst(a):
        d, g = d_and_g(a)
        return np.max(np.abs(t["D"] / d - 1)), np.max(np.abs(t["G"] / g - 1))

    exact, stored = worst(0.3), worst(float(np.float32(0.3)))
    print(f"D, G relative to float64 at 0.3: {exact[0]:.1e}, {exact[1]:.1e}; at float32(0.3): {stored[0]:.0e}, {stored[1]:.0e}")
    assert max(stored) < 1e-13  # the documented behaviour: float32 parameters, float64 arithmetic
    assert 1e-8 < exact[0] < 2e-7 and 1e-9 < exact[1] < 1e-7
