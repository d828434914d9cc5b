"""material_keys(): every key a model takes, with the defaults the library really uses."""

import re

import numpy as np
import pytest

import pointshade

MODELS = ("lambert", "blinn-phong", "cook-torrance")


def directions(count=64, seed=3):
    rng = np.random.default_rng(seed)
    v = rng.normal(size=(2, count, 3))
    v[..., 2] = np.abs(v[..., 2])
    v /= np.linalg.norm(v, axis=-1, keepdims=True)
    return np.tile([0.0, 0.0, 1.0], (count, 1)), v[0], v[1]


@pytest.mark.parametrize("defaults", ["scene", "tp"])
@pytest.mark.parametrize("model", MODELS)
def test_each_listed_default_is_the_value_a_missing_key_takes(model, defaults):
    keys = pointshade.material_keys(model, defaults=defaults)
    assert keys["model"]["default"] == model
    assert all(k["takes"] and k["meaning"] for k in keys.values())
    explicit = {key: k["default"] for key, k in keys.items()}
    # Keys that only act with other terms are left out where they cannot act (writing them is an error).
    if explicit.get("fresnel") != "conductor":
        explicit.pop("eta", None), explicit.pop("k", None)
    if explicit.get("fresnel") in ("conductor", "constant"):
        explicit.pop("ior", None), explicit.pop("metallic", None)
    n, wi, wo = directions()
    given = pointshade.eval_brdf(explicit, n, wi, wo, defaults=defaults, precision="float64")
    alone = pointshade.eval_brdf({"model": model}, n, wi, wo, defaults=defaults, precision="float64")
    assert given.std() > 0 and np.array_equal(given, alone)


def test_the_keys_are_the_ones_scene_files_accept():
    n = np.array([[0.0, 0.0, 1.0]])
    with pytest.raises(pointshade.InputError) as e:
        pointshade.eval_brdf({"model": "lambert", "bogus": 1}, n, n, n)
    accepted = set(re.findall(r"`(\w+)`", str(e.value).split("expected one of", 1)[1]))
    listed = set().union(*(pointshade.material_keys(m) for m in MODELS))
    assert listed == accepted
    # A key of another model is refused, and a value outside what a key takes.
    with pytest.raises(pointshade.InputError, match="'roughness' does not apply to the lambert model"):
        pointshade.eval_brdf({"model": "lambert", "roughness": 0.3}, n, n, n)
    assert "[0, 1]" in pointshade.material_keys("cook-torrance")["roughness"]["takes"]
    with pytest.raises(pointshade.InputError, match=r"roughness must be in \[0, 1\]"):
        pointshade.eval_brdf({"model": "cook-torrance", "roughness": 1.5}, n, n, n)
    with pytest.raises(pointshade.InputError, match="unknown variant"):
        pointshade.material_keys("phong")


@pytest.mark.parametrize("key", ["d", "g", "fresnel"])
def test_each_term_name_listed_is_one_a_material_takes_and_no_other_is(key):
    takes = pointshade.material_keys("cook-torrance")[key]["takes"]
    names = re.findall(r"'([a-z-]+)'", takes)
    assert len(names) >= 2, takes
    n, wi, wo = directions(8)
    values = set()
    for name in names:
        material = {"model": "cook-torrance", key: name}
        if key == "fresnel" and name == "conductor":
            material.update(eta=[0.2, 0.9, 1.1], k=[3.9, 2.4, 2.2])
        values.add(pointshade.eval_brdf(material, n, wi, wo, precision="float64").tobytes())
    assert len(values) == len(names), "each term gives its own values"
    # The library's error for a name it does not know lists the same names.
    with pytest.raises(pointshade.InputError) as e:
        pointshade.eval_brdf({"model": "cook-torrance", key: "no-such-term"}, n, wi, wo)
    assert all(name in str(e.value) for name in names), str(e.value)
