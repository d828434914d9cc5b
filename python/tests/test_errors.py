"""Every kind of bad input is a Python exception with the CLI's one-line message."""

import numpy as np
import pytest

import pointshade
from conftest import REPO


def test_a_missing_file_is_file_not_found_with_the_cli_message(cli):
    with pytest.raises(FileNotFoundError, match=r"^/nonexistent/mesh\.obj: file not found$"):
        pointshade.render("/nonexistent/mesh.obj")
    with pytest.raises(FileNotFoundError):
        pointshade.shade_normal_image("/nonexistent.png", preset="physical", brdf="lambert")


def test_a_malformed_scene_file_is_an_input_error_naming_file_and_line(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("[film]\nwidth = 'wide'\n")
    with pytest.raises(pointshade.InputError, match=r"bad\.toml: line 2, column 9: ") as e:
        pointshade.render(bad)
    assert isinstance(e.value, ValueError) and "\n" not in str(e.value)


def test_bad_keywords_are_value_errors_naming_them():
    cornell = REPO / "scenes" / "cornell-box.toml"
    for kwargs, pattern in [
        ({"sampler": "bogus"}, "^sampler: expected grid, sobol, independent, adaptive or cells, got 'bogus'$"),
        ({"width": -3}, "^width: must be a whole number from 1 to 65536, got -3$"),
        ({"width": 2**40}, "^width: must be a whole number from 1 to 65536, got 1099511627776$"),
        ({"threads": -1}, "^threads: must be a whole number from 1 to "),
        ({"adaptive_threshold": float("nan")}, r"^adaptive_threshold: must be a number in \(0, 1\), got NaN$"),
        ({"spp": 0}, "^spp: must be a whole number from 1 to 65536, got 0$"),
        ({"fov": float("nan")}, "^fov: "),
        ({"crop": (0, 0, 9999, 10)}, "crop"),
        ({"aovs": ["colour"]}, "^aovs: "),
        ({"threads": 0}, "^threads: must be a whole number from 1 to"),
        ({"threads": 10**6}, "^threads: 1000000 is more than"),
        ({"view": (1.0,)}, "^view: "),
        ({"camera": 3}, "camera"),
    ]:
        with pytest.raises(ValueError, match=pattern):
            pointshade.render(cornell, **{"width": 16, "height": 12, "spp": 1, **kwargs})


def test_keywords_of_the_wrong_type_are_type_errors_naming_them():
    cornell = REPO / "scenes" / "cornell-box.toml"
    for kwargs, pattern in [
        ({"width": 3.5}, "^width: expected an int, got float 3.5$"),
        ({"width": True}, "^width: expected an int, got bool True$"),
        ({"spp": "4"}, "^spp: expected an int, got str '4'$"),
        ({"sampler": 3}, "^sampler: expected a str, got int 3$"),
        ({"look_at": "0,0,0"}, "^look_at: expected a sequence of numbers, got str"),
        ({"crop": (0, 0, 4.5, 4)}, "^crop: expected a sequence of ints"),
        ({"fov": "wide"}, "^fov: expected a number, got str 'wide'$"),
        ({"aovs": [1]}, "^aovs: expected a str or a list of str"),
    ]:
        with pytest.raises(TypeError, match=pattern):
            pointshade.render(cornell, **{"width": 16, "height": 12, "spp": 1, **kwargs})
    with pytest.raises(TypeError, match="^render\\(\\) got an unexpected keyword argument 'widht'$"):
        pointshade.render(cornell, widht=16)


def square():
    return np.array([[0.0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]), np.array([[0, 1, 2], [0, 2, 3]])


def render_mesh(v, f, **kw):
    s = pointshade.Scene()
    s.add_mesh(v, f, **kw)
    return pointshade.render(s, width=8, height=8, spp=1)


def test_wrong_mesh_arrays_are_clear_exceptions():
    v, f = square()
    with pytest.raises(TypeError, match="vertices: expected a float32 or float64 array, got dtype int64"):
        render_mesh(v.astype(np.int64), f)
    with pytest.raises(ValueError, match=r"vertices: expected shape \(N, 3\), got \[4, 2\]"):
        render_mesh(np.ascontiguousarray(v[:, :2]), f)
    with pytest.raises(ValueError, match="C-contiguous"):
        render_mesh(np.asfortranarray(np.tile(v, (1, 1)).T.copy().T), f)
    nan = v.copy()
    nan[2, 1] = np.nan
    with pytest.raises(ValueError, match="element 7 is NaN"):
        render_mesh(nan, f)
    with pytest.raises(ValueError, match="no faces"):
        render_mesh(v, np.zeros((0, 3), dtype=np.int64))
    with pytest.raises(pointshade.InputError, match="face index 9 out of range"):
        render_mesh(v, np.array([[0, 1, 9]]))
    with pytest.raises(ValueError, match="negative"):
        render_mesh(v, np.array([[0, 1, -1]]))
    with pytest.raises(TypeError, match="faces: expected an integer array"):
        render_mesh(v, f.astype(np.float64))
    with pytest.raises(TypeError, match="expected a numpy array, got list"):
        render_mesh(v.tolist(), f)


def test_wrong_normal_images_are_clear_exceptions():
    with pytest.raises(TypeError, match="uint8, uint16 or float"):
        pointshade.shade_normal_image(np.zeros((4, 4, 3), np.int32), preset="physical", brdf="lambert")
    with pytest.raises(ValueError, match=r"row 0, column 1, channel 2 is 1.5: float samples .* in \[0, 1\]"):
        pointshade.shade_normal_image(np.array([[[0.5, 0.5, 1.0], [0.2, 0.3, 1.5]]]), preset="physical", brdf="lambert")
    with pytest.raises(ValueError, match="row 0, column 0, channel 0 is NaN"):
        pointshade.shade_normal_image(np.full((2, 2, 3), np.nan, np.float32), preset="physical", brdf="lambert")
    with pytest.raises(ValueError, match=r"\(H, W, 3\) or \(H, W, 4\)"):
        pointshade.shade_normal_image(np.zeros((4, 4, 2), np.uint8), preset="physical", brdf="lambert")
    with pytest.raises(ValueError, match="C-contiguous"):
        pointshade.shade_normal_image(np.zeros((4, 6, 3), np.uint8)[:, ::2], preset="physical", brdf="lambert")
    with pytest.raises(ValueError, match="empty"):
        pointshade.shade_normal_image(np.zeros((0, 4, 3), np.uint8), preset="physical", brdf="lambert")
    with pytest.raises(ValueError, match="brdf"):
        pointshade.shade_normal_image(np.zeros((4, 4, 3), np.uint8), preset="physical")
    with pytest.raises(pointshade.InputError, match="unknown variant `pt`, expected `tp` or `physical`"):
        pointshade.shade_normal_image(np.zeros((4, 4, 3), np.uint8), preset="pt", brdf="lambert")
    with pytest.raises(ValueError, match="tp preset"):
        pointshade.shade_normal_image(np.zeros((4, 4, 3), np.uint8), preset="physical", brdf="lambert", return_8bit=True)


def test_wrong_brdf_inputs_are_clear_exceptions():
    n = np.array([[0.0, 0.0, 1.0]])
    with pytest.raises(pointshade.InputError, match="unknown field `rougness`"):
        pointshade.eval_brdf({"model": "cook-torrance", "rougness": 0.2}, n, n, n)
    with pytest.raises(pointshade.InputError, match="roughness"):
        pointshade.eval_brdf({"model": "cook-torrance", "roughness": -1.0}, n, n, n)
    with pytest.raises(ValueError, match="^material: roughness: NaN is not a finite number$"):
        pointshade.eval_brdf({"model": "cook-torrance", "roughness": float("nan")}, n, n, n)
    with pytest.raises(ValueError, match=r"^wi: row 1 has length 2 \(directions must be unit vectors, to 1e-4\)"):
        pointshade.eval_brdf({"model": "lambert"}, np.tile(n, (2, 1)), np.array([n[0], 2 * n[0]]), np.tile(n, (2, 1)))
    with pytest.raises(ValueError, match="^wo: row 0 has length 0.5"):
        pointshade.eval_brdf({"model": "lambert"}, n, n, 0.5 * n)
    with pytest.raises(ValueError, match="^n: row 0 is zero"):
        pointshade.eval_brdf({"model": "lambert"}, 0 * n, n, n)
    # n may have any other length; wi and wo within 1e-4 of unit length pass.
    tilted = np.array([[0.6, 0.0, 0.8 * (1 + 5e-5)]])
    assert pointshade.eval_brdf({"model": "lambert"}, 3 * n, tilted, n).shape == (1, 3)
    with pytest.raises(ValueError, match="one row each"):
        pointshade.eval_brdf({"model": "lambert"}, n, np.tile(n, (2, 1)), n)
    with pytest.raises(ValueError, match="is NaN"):
        pointshade.eval_brdf({"model": "lambert"}, np.array([[np.nan, 0.0, 1.0]]), n, n)
    with pytest.raises(ValueError, match="precision"):
        pointshade.eval_brdf({"model": "lambert"}, n, n, n, precision="float16")
    with pytest.raises(ValueError, match="Cook-Torrance terms"):
        pointshade.eval_terms({"model": "lambert"}, n, n, n)


def test_eval_brdf_names_a_bad_row_deep_in_a_large_array_and_reads_mixed_dtypes():
    # Rows are checked as they are evaluated, many at a time on every core: the error still
    # names the first bad row, and a row just inside the 1e-4 limit still passes.
    count = 50_000
    n = np.tile([0.0, 0.0, 2.0], (count, 1))
    wi = np.tile([0.6, 0.0, 0.8], (count, 1))
    wi[31_337] *= 1 + 9e-5
    f = pointshade.eval_brdf({"model": "cook-torrance"}, n, wi, wi, precision="float64")
    assert f.shape == (count, 3) and np.all(np.delete(f, 31_337, axis=0) == f[0]) and np.all(f[31_337] > 0)
    wi[40_001] = [0.0, 0.0, np.inf]
    wi[45_000] *= 2
    with pytest.raises(ValueError, match="^wi: element 120005 is inf"):
        pointshade.eval_brdf({"model": "lambert"}, n, wi, wi)
    wi[40_001] = [0.6, 0.0, 0.8]
    with pytest.raises(ValueError, match="^wi: row 45000 has length 2"):
        pointshade.eval_brdf({"model": "lambert"}, n, wi, wi, precision="float64")
    wi[45_000] /= 2
    # float32 and float64 arrays may be mixed: each value is rounded once to the precision.
    mixed = pointshade.eval_brdf({"model": "cook-torrance"}, n.astype(np.float32), wi, wi, precision="float64")
    assert np.array_equal(mixed, pointshade.eval_brdf({"model": "cook-torrance"}, n, wi, wi, precision="float64"))


def test_compare_gives_the_cli_metrics_and_a_per_pixel_error():
    ref = np.full((4, 5, 3), 0.5, np.float32)
    ours = ref.copy()
    ours[1, 2] = 0.6
    c = pointshade.compare(ours, ref, tol=1e-3)
    assert c["pixels"] == 20 and c["within_tolerance"] == pytest.approx(19 / 20)
    assert c["relative_error"].shape == (4, 5) and c["relative_error"][1, 2] == pytest.approx(0.2, rel=1e-5)
    assert c["worst"][0]["x"] == 2 and c["worst"][0]["y"] == 1
    assert "RMSE" in c["summary"]
    with pytest.raises(ValueError, match="size"):
        pointshade.compare(ours, ref[:3])
    with pytest.raises(ValueError, match="tol"):
        pointshade.compare(ours, ref, tol=float("nan"))


def test_confine_refuses_files_outside_the_folder(tmp_path):
    inside, outside = tmp_path / "inside", tmp_path / "outside"
    inside.mkdir()
    outside.mkdir()
    triangle = "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n"
    (outside / "tri.obj").write_text(triangle)
    (inside / "tri.obj").write_text(triangle)
    (inside / "up.toml").write_text('[[object]]\nmesh = "../outside/tri.obj"\n')
    (inside / "own.toml").write_text('[[object]]\nmesh = "tri.obj"\n')
    small = {"width": 8, "height": 6, "spp": 1}
    assert pointshade.render(inside / "own.toml", confine=inside, **small)["color"].shape == (6, 8, 3)
    with pytest.raises(pointshade.InputError, match=r"outside/tri\.obj: lies outside .*the folder reads are confined to"):
        pointshade.render(inside / "up.toml", confine=inside, **small)
    # Without the confinement the same scene renders.
    assert pointshade.render(inside / "up.toml", **small)["color"].shape == (6, 8, 3)
    with pytest.raises(ValueError, match=r"^confine: .*folder not found"):
        pointshade.render(inside / "own.toml", confine=inside / "nowhere", **small)
    with pytest.raises(pointshade.InputError, match="confined to"):
        pointshade.shade_normal_image(outside / "n.png", preset="physical", brdf="lambert", confine=inside)


def test_values_of_a_built_scene_are_named_by_call_and_key():
    s = pointshade.Scene()
    with pytest.raises(ValueError, match=r"^add_light: intensity: NaN is not a finite number$") as e:
        s.add_light("point", position=[0, 1, 0], intensity=float("nan"))
    assert not isinstance(e.value, TypeError)
    with pytest.raises(ValueError, match=r"^add_light: position\[2\]: inf is not a finite number$"):
        s.add_light("point", position=[0, 1, float("inf")])
    with pytest.raises(TypeError, match="^set_film: width: cannot write a object in a scene file$"):
        s.set_film(width=object())
    assert "light" not in s.doc and "film" not in s.doc  # nothing of a refused call is kept


def test_documents_written_from_python_values_name_keys_not_lines(tmp_path):
    s = pointshade.Scene(tmp_path)
    s.add_object(REPO / "meshes" / "torus.obj")
    s.add_light("point", positon=[1.0, 2.0, 3.0])
    with pytest.raises(pointshade.InputError, match=r"light\[0\]\.positon: unknown field `positon`") as e:
        pointshade.render(s, width=8, height=6)
    assert "line" not in str(e.value)
    with pytest.raises(pointshade.InputError, match=r"light\[1\]: missing field `type`") as e:
        pointshade.shade_normal_image(np.full((4, 4, 3), 128, np.uint8), preset="physical", brdf="lambert",
                                      lights=[{"type": "directional"}, {"position": [0.0, 0.0, 1.0]}])
    assert "line" not in str(e.value)
    # A file someone wrote is named by line and column, in one line.
    bad = tmp_path / "bad.toml"
    bad.write_text("[film]\nwidth = [\n")
    with pytest.raises(pointshade.InputError, match=r"bad\.toml: line 3, column 1: ") as e:
        pointshade.Scene.from_toml(bad)
    assert "\n" not in str(e.value)
