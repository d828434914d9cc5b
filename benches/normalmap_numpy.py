#!/usr/bin/env python3
"""A straightforward numpy (float64) implementation of the NPM3D TP4 shading, for the speed
comparison in benches/normalmap.rs.

The shading itself is examples/python/tp_numpy.py's `shade` (one implementation, shared with the
Python examples and python/bench.py): the `tp` preset's formulas exactly as
../shared/notes/tp-assignment.md states them, vectorised over the whole image the way a numpy user
would write them: one array operation per term, every pixel (background included) computed,
float64 throughout.

Input: a .npy array of shape (H, W, 3), dtype uint8 (the normal image's RGB, as decoded by the
bench). Output: lines `numpy_shade_seconds_median=<s>` and `numpy_shade_seconds_min=<s>` on stdout, and optionally (--save) the
radiance L_o of the last run as a float64 .npy so the bench can check both implementations agree.

    python3 benches/normalmap_numpy.py IMAGE.npy --brdf cook-torrance --repeats 5 [--save OUT.npy]
"""

import argparse
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "examples", "python"))
from tp_numpy import shade  # noqa: E402


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("image", help="(H, W, 3) uint8 .npy")
    p.add_argument("--brdf", default="cook-torrance", choices=["lambert", "blinn-phong", "cook-torrance"])
    p.add_argument("--repeats", type=int, default=5)
    p.add_argument("--save", help="write the last L_o here (.npy, float64)")
    args = p.parse_args()
    rgb = np.load(args.image)
    shade(rgb, args.brdf)  # warm-up: first-touch page faults, caches
    times = []
    for _ in range(max(1, args.repeats)):
        t0 = time.perf_counter()
        lo = shade(rgb, args.brdf)
        times.append(time.perf_counter() - t0)
    if args.save:
        np.save(args.save, lo)
    print(f"numpy_shade_seconds_median={sorted(times)[len(times) // 2]:.6f}")
    print(f"numpy_shade_seconds_min={min(times):.6f}")
    print(f"numpy_version={np.__version__}")


if __name__ == "__main__":
    main()
