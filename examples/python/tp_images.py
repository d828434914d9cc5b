"""The NPM3D TP4 assignment's three images (Lambert, Blinn-Phong, Cook-Torrance) from Python, checked
against a plain numpy implementation of the same shading (tp_numpy.py).

For each BRDF, `pointshade.shade_normal_image(path, preset="tp", brdf=..., return_8bit=True)` gives
L_o (float32, computed in float64) and the assignment's 8-bit image (the PNG `pointshade normalmap
--preset tp` writes); the 8-bit image is saved as OUT/tp-BRDF.png (pointshade.write_image). The
same samples (pointshade.read_normal_image: as the file stores them) go through tp_numpy.shade (float64) and tp_numpy.to_8bit, and the script reports

- the largest |L_o difference| relative to the peak L_o: float32 storage of a float64 value is off
  by at most 2^-24 ≈ 6e-8 of it, so anything near the 1e-5 limit is a real disagreement;
- the share of 8-bit values (and of pixels) that differ: the float32 rounding moves a value across
  a level boundary only where it lies within ~6e-8·peak of one, a few values in a million; the
  limit is 0.1%;
- whether pointshade's 8-bit image is exactly the assignment's normalisation of its own L_o, and
  whether a decoded array input gives the same L_o as the path.

It exits 1 if the L_o differ by more than 1e-5 of the peak, more than 0.1% of the 8-bit values
differ, or one of the two exactness checks fails. Without the assignment's normal.png (it lives in
../shared/data beside the repository), it says SKIPPED and exits 0.

    python examples/python/tp_images.py [--image ../shared/data/normalmaps/normal.png] [--out out/python-tp]
"""

import argparse
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
DEFAULT_IMAGE = os.path.join(REPO, "..", "shared", "data", "normalmaps", "normal.png")
sys.path.insert(0, HERE)

import tp_numpy  # noqa: E402

import pointshade  # noqa: E402

MAX_FLOAT_DIFFERENCE = 1e-5  # of the peak L_o
MAX_8BIT_SHARE = 1e-3  # of the 8-bit values


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--image", help="normal image (PNG); default: the assignment's normal.png in ../shared/data")
    parser.add_argument("--out", default=os.path.join("out", "python-tp"), help="output folder (default out/python-tp)")
    args = parser.parse_args()

    image = args.image or os.path.normpath(DEFAULT_IMAGE)
    if not os.path.isfile(image):
        if args.image:
            print(f"error: {image}: no such file", file=sys.stderr)
            return 2
        print(
            f"\n*** SKIPPED: {image} is missing "
            "(the assignment's normal.png is in ../shared/data; pass --image)\n",
            file=sys.stderr,
        )
        return 0
    os.makedirs(args.out, exist_ok=True)
    samples = pointshade.read_normal_image(image)
    rgb = samples[..., :3]
    h, w = rgb.shape[:2]
    print(f"{image}: {w}x{h}, {samples.shape[2]} channels, {samples.dtype}")
    print(f"{'brdf':<14} {'pointshade ms':>13} {'numpy ms':>9} {'max |ΔL_o|/peak':>16} {'8-bit values differing':>24} {'pixels':>8}  written")

    failures = []
    for brdf in tp_numpy.BRDFS:
        t0 = time.perf_counter()
        lo, img8 = pointshade.shade_normal_image(image, preset="tp", brdf=brdf, return_8bit=True)
        ours_s = time.perf_counter() - t0
        t0 = time.perf_counter()
        ref = tp_numpy.shade(rgb, brdf)
        numpy_s = time.perf_counter() - t0
        ref8 = tp_numpy.to_8bit(ref)

        if lo.shape != (h, w, 3) or lo.dtype != np.float32 or img8.shape != (h, w, 3) or img8.dtype != np.uint8:
            failures.append(f"{brdf}: unexpected arrays {lo.dtype}{lo.shape}, {img8.dtype}{img8.shape}")
            continue
        difference = float(np.abs(lo.astype(np.float64) - ref).max() / ref.max())
        differ = img8 != ref8
        value_share = differ.mean()
        pixel_share = differ.any(axis=-1).mean()
        out = os.path.join(args.out, f"tp-{brdf}.png")
        pointshade.write_image(out, img8)
        print(
            f"{brdf:<14} {ours_s * 1e3:>13.1f} {numpy_s * 1e3:>9.1f} {difference:>16.1e} "
            f"{differ.sum():>8} ({value_share:>8.4%}) {pixel_share:>8.4%}  {out}"
        )

        if difference > MAX_FLOAT_DIFFERENCE:
            failures.append(f"{brdf}: L_o differs from numpy's by {difference:.1e} of the peak (limit {MAX_FLOAT_DIFFERENCE:.0e})")
        if value_share > MAX_8BIT_SHARE:
            failures.append(f"{brdf}: {value_share:.3%} of the 8-bit values differ from numpy's (limit {MAX_8BIT_SHARE:.1%})")
        own = tp_numpy.to_8bit(lo)
        if not np.array_equal(own, img8):
            failures.append(
                f"{brdf}: the returned 8-bit image is not the min-max normalisation of the returned L_o "
                f"({int((own != img8).sum())} values differ)"
            )
        from_array = pointshade.shade_normal_image(samples, preset="tp", brdf=brdf)
        if not np.array_equal(from_array, lo):
            failures.append(f"{brdf}: the decoded array gives another L_o than the PNG path")

    for f in failures:
        print(f"FAILED: {f}", file=sys.stderr)
    if failures:
        return 1
    print(
        f"all three agree with numpy (L_o within {MAX_FLOAT_DIFFERENCE:.0e} of the peak, "
        f"at most {MAX_8BIT_SHARE:.1%} of the 8-bit values differing)"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
