"""pointshade against Mitsuba 3 from Python: one validation scene rendered by both, compared pixel by
pixel, and drawn with matplotlib beside a polar plot of a Cook-Torrance lobe from eval_brdf.

The scene (default scenes/validation/conductor-sphere.toml: a GGX copper sphere with exact conductor
Fresnel on a diffuse plane, one point light, one sample at each pixel centre) is exported with
`pointshade.Scene.from_toml(path).export_mitsuba(xml)` and rendered by Mitsuba through
validation/render.py, the script `pointshade validate` uses (it picks the variant, registers
pointshade's BSDF plugin and writes the EXR), run by an interpreter that has Mitsuba: `--python`,
else $POINTSHADE_MITSUBA_PYTHON, else this one if it imports `mitsuba`, else
validation/.venv/bin/python (validation/install.sh makes it). Both sides use the like-for-like
switch (`export_mitsuba(xml, match="mitsuba")`, `render(scene, match="mitsuba")`: the grid
sampler and Mitsuba's shadow offset, docs/validation.md), and `pointshade.compare` measures the
relative error per pixel. Drawing needs matplotlib (`pip install matplotlib`).

The figure (default out/python-mitsuba/compare.png) has both renders, the relative-error heat map
(log scale) and the polar lobe f_r·cos θ_i of the scene's copper at three roughnesses for ω_o at 45°,
ω_i swept through the plane of incidence (eval_brdf, float64).

It exits 1 if fewer than 99.9% of the pixels agree to 1e-3 (the validation's requirement for a
scene Mitsuba renders exactly), and 0 with a SKIPPED line when Mitsuba 3 or matplotlib is missing.
The exported scene is one XML with every light in it: keep to scenes of one light (Mitsuba samples
one light per sample; for several, `pointshade export-mitsuba --per-light` writes one XML each and
render.py sums them).

    python examples/python/mitsuba_compare.py [--scene scenes/validation/conductor-sphere.toml] [--out out/python-mitsuba/compare.png] [--python PATH]
"""

import argparse
import json
import os
import subprocess
import sys
import time

import numpy as np

import pointshade

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
VALIDATION = os.path.join(REPO, "validation")
DEFAULT_SCENE = os.path.join(REPO, "scenes", "validation", "conductor-sphere.toml")
REQUIRED_WITHIN = 0.999

# The copper of conductor-sphere.toml, for the lobe plot.
COPPER = {
    "model": "cook-torrance",
    "kd": 0.0,
    "g": "smith-ggx",
    "fresnel": "conductor",
    "eta": [0.200, 0.924, 1.102],
    "k": [3.912, 2.452, 2.142],
}


def skipped(what):
    print(f"\n*** SKIPPED: {what}\n", file=sys.stderr)
    return 0


def mitsuba_python(given):
    """An interpreter that imports mitsuba: `given` (--python, else $POINTSHADE_MITSUBA_PYTHON) if
    set, else this one, else the validation's virtual environment."""
    given = given or os.environ.get("POINTSHADE_MITSUBA_PYTHON")
    if given:
        probe = subprocess.run([given, "-c", "import mitsuba"], capture_output=True, text=True)
        if probe.returncode != 0:
            sys.exit(f"error: {given} cannot import mitsuba: {probe.stderr.strip().splitlines()[-1:]}")
        return given
    candidates = [sys.executable, os.path.join(VALIDATION, ".venv", "bin", "python")]
    for python in candidates:
        if os.path.isfile(python):
            probe = subprocess.run([python, "-c", "import mitsuba"], capture_output=True)
            if probe.returncode == 0:
                return python
    return None


def to_srgb(linear):
    """Display encoding of a linear render: clamped to [0, 1], the sRGB transfer curve."""
    x = np.clip(linear, 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)


def lobe(roughness, angles):
    """f_r·cos θ_i (mean over RGB) of the copper for ω_o at 45° and ω_i at `angles` (radians from
    the normal, in the plane of incidence; negative on the far side from ω_o)."""
    count = len(angles)
    n = np.tile([0.0, 0.0, 1.0], (count, 1))
    wo = np.tile([np.sin(np.pi / 4), 0.0, np.cos(np.pi / 4)], (count, 1))
    wi = np.stack([np.sin(angles), np.zeros(count), np.cos(angles)], axis=-1)
    material = dict(COPPER, roughness=roughness)
    f = pointshade.eval_brdf(material, n, wi, wo, precision="float64")
    return f.mean(axis=-1) * np.cos(angles)


def draw(path, ours, ref, comparison, scene_name):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import LogNorm

    fig = plt.figure(figsize=(13, 10))
    for i, (image, title) in enumerate(((ours, "pointshade"), (ref, "Mitsuba 3"))):
        ax = fig.add_subplot(2, 2, i + 1)
        ax.imshow(to_srgb(image), interpolation="nearest")
        ax.set_title(f"{title} ({scene_name})")
        ax.axis("off")

    ax = fig.add_subplot(2, 2, 3)
    error = np.asarray(comparison["relative_error"], dtype=np.float64)
    shown = ax.imshow(np.clip(error, 1e-6, 1e-1), norm=LogNorm(vmin=1e-6, vmax=1e-1), cmap="turbo", interpolation="nearest")
    fig.colorbar(shown, ax=ax, fraction=0.046, pad=0.04, label="relative error (max over channels)")
    ax.set_title(
        f"relative error: {comparison['within_tolerance']:.3%} of pixels within {comparison['tolerance']:g}, "
        f"mean {comparison['mean_relative_error']:.1e}",
        fontsize=10,
    )
    ax.axis("off")

    ax = fig.add_subplot(2, 2, 4, projection="polar")
    angles = np.radians(np.linspace(-89.5, 89.5, 717))
    for roughness in (0.1, 0.3, 0.6):
        values = lobe(roughness, angles)
        ax.plot(angles, values / values.max(), label=f"α = {roughness} (peak f_r·cos θ_i = {values.max():.3g})")
    ax.plot([np.pi / 4, np.pi / 4], [0, 1.05], "k--", linewidth=1, label="ω_o (45°)")
    ax.set_theta_zero_location("N")
    ax.set_theta_direction(-1)
    ax.set_thetamin(-90)
    ax.set_thetamax(90)
    ax.set_title("Cook-Torrance copper (GGX, separable Smith, conductor F):\nf_r·cos θ_i over ω_i, each curve / its peak", fontsize=10)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, 0.05), fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scene", default=DEFAULT_SCENE, help="a scene file of one light (default: the conductor-sphere validation scene)")
    parser.add_argument("--out", default=os.path.join("out", "python-mitsuba", "compare.png"), help="figure (PNG)")
    parser.add_argument("--python", help="an interpreter that imports mitsuba (default: $POINTSHADE_MITSUBA_PYTHON, "
                        "this one, or validation/.venv/bin/python)")
    args = parser.parse_args()

    python = mitsuba_python(args.python)
    if python is None:
        return skipped(
            "Mitsuba 3 is not installed (run validation/install.sh: this script then renders the "
            "reference with validation/.venv/bin/python, or run it with a Python that imports mitsuba)"
        )
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        return skipped(f"matplotlib is not installed for {sys.executable} (pip install matplotlib)")

    out_dir = os.path.dirname(os.path.abspath(args.out))
    os.makedirs(out_dir, exist_ok=True)
    stem = os.path.splitext(os.path.basename(args.scene))[0]
    xml = os.path.join(out_dir, f"{stem}.xml")
    ref_exr = os.path.join(out_dir, f"{stem}.mitsuba.exr")

    pointshade.Scene.from_toml(args.scene).export_mitsuba(xml, match="mitsuba")
    t0 = time.perf_counter()
    run = subprocess.run(
        [python, os.path.join(VALIDATION, "render.py"), "--out", ref_exr, xml], capture_output=True, text=True
    )
    mitsuba_s = time.perf_counter() - t0
    if run.returncode != 0:
        sys.stderr.write(run.stderr)
        sys.exit(f"error: Mitsuba failed on {xml} ({python})")
    report = json.loads([line for line in run.stdout.splitlines() if line.startswith("{")][-1])
    ref = pointshade.read_image(ref_exr)

    t0 = time.perf_counter()
    rendered = pointshade.render(args.scene, match="mitsuba")
    ours_s = time.perf_counter() - t0
    ours = rendered["color"]
    comparison = pointshade.compare(ours, ref, tol=1e-3)

    h, w = ours.shape[:2]
    print(f"{os.path.relpath(os.path.abspath(args.scene), REPO)}: {w}x{h}, {rendered['stats']['spp']} spp")
    print(f"  Mitsuba 3 ({report['variant']}, {python}): load {report['load_s']:.2f} s, render {report['render_s']:.2f} s, {mitsuba_s:.2f} s with start-up")
    print(f"  pointshade: {ours_s:.3f} s (render {rendered['stats']['render_seconds']:.3f} s)")
    print(
        f"  {comparison['pixels']} pixels: {comparison['within_tolerance']:.3%} within {comparison['tolerance']:g}, "
        f"mean relative error {comparison['mean_relative_error']:.2e}, RMSE {comparison['rmse']:.3e}, "
        f"non-finite {comparison['non_finite_ours']}/{comparison['non_finite_reference']}"
    )
    for worst in comparison["worst"][:3]:
        print(
            f"    worst ({worst['x']}, {worst['y']}): relative error {worst['relative_error']:.2e}, "
            f"ours {np.round(worst['ours'], 6).tolist()}, Mitsuba {np.round(worst['reference'], 6).tolist()}"
        )
    draw(args.out, ours, ref, comparison, stem)
    print(f"  figure: {args.out}")
    if comparison["within_tolerance"] < REQUIRED_WITHIN:
        print(f"FAILED: fewer than {REQUIRED_WITHIN:.1%} of the pixels agree to 1e-3", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
