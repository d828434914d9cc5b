#!/usr/bin/env python3
"""A straightforward numpy (float64) implementation of the NPM3D TP4 shading, for the speed
comparison in benches/normalmap.rs.

It implements the `tp` preset's formulas exactly as ../shared/notes/tp-assignment.md states them,
vectorised over the whole image the way a numpy user would write them: one array operation per
term, every pixel (background included) computed, float64 throughout.

Input: a .npy array of shape (H, W, 3), dtype uint8 (the normal image's RGB, as decoded by the
bench). Output: lines `numpy_shade_seconds_median=<s>` and `numpy_shade_seconds_min=<s>` on stdout, and optionally (--save) the
radiance L_o of the last run as a float64 .npy so the bench can check both implementations agree.

    python3 benches/normalmap_numpy.py IMAGE.npy --brdf cook-torrance --repeats 5 [--save OUT.npy]
"""

import argparse
import sys
import time

import numpy as np

# The report's parameter values (the tp preset's defaults).
LIGHT_POSITION = np.array([0.0, 1.0, 1.0])
LIGHT_COLOR = np.array([0.5, 0.5, 0.5])
LIGHT_INTENSITY = 1.0
ALBEDO = np.array([0.4, 0.7, 0.4])
KD = 1.0
KS = 1.0
SHININESS = 1.0
CAMERA = np.array([1.0, 300.0, 1.0])
ALPHA = 0.7
METALLIC = True
SPECULAR_COLOR = np.array([0.98, 0.82, 0.76])
FRESNEL_INDEX = 5.0
# Pixels whose largest 8-bit channel is at most this are background: n = 0 (shared/data/README.md).
BACKGROUND_LEVEL = 4


def normalize(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def dot(a, b):
    return np.sum(a * b, axis=-1)


def shade(rgb, brdf):
    """L_o for every pixel: (H, W, 3) float64."""
    c = rgb.astype(np.float64)
    # Convention 1: one global min-max over the RGB array, used as the normal without decoding.
    n = c - c.min()
    n = n / n.max()
    n[rgb.max(axis=-1) <= BACKGROUND_LEVEL] = 0.0
    # Convention 2: pixel (row, col) is the point (row, col, 0).
    h, w, _ = rgb.shape
    rows, cols = np.meshgrid(np.arange(h, dtype=np.float64), np.arange(w, dtype=np.float64), indexing="ij")
    x = np.stack([rows, cols, np.zeros_like(rows)], axis=-1)
    # ω_i from the light towards the point, ω_o from the point towards the camera.
    wi = normalize(x - LIGHT_POSITION)
    wo = normalize(CAMERA - x)
    li = LIGHT_COLOR * LIGHT_INTENSITY
    # Convention 3: every dot product clamped to [0, 1].
    n_wi = np.clip(dot(n, wi), 0.0, 1.0)
    f = np.broadcast_to(KD * ALBEDO / np.pi, c.shape)
    if brdf == "blinn-phong":
        wh = normalize(wo + wi)
        n_wh = np.clip(dot(n, wh), 0.0, 1.0)
        f = f + (KS * n_wh**SHININESS)[..., None]
    elif brdf == "cook-torrance":
        wh = normalize(wo + wi)
        n_wh = np.clip(dot(n, wh), 0.0, 1.0)
        n_wo = np.clip(dot(n, wo), 0.0, 1.0)
        wi_wh = np.clip(dot(wi, wh), 0.0, 1.0)
        a2 = ALPHA * ALPHA
        d = a2 / (np.pi * (1.0 + (a2 - 1.0) * n_wh**2) ** 2)
        f0 = SPECULAR_COLOR if METALLIC else np.full(3, ((FRESNEL_INDEX - 1) / (FRESNEL_INDEX + 1)) ** 2)
        fr = f0 + (1.0 - f0) * ((1.0 - np.maximum(0.0, wi_wh)) ** 5)[..., None]
        k = ALPHA * np.sqrt(2.0 / np.pi)
        g = (n_wi / (n_wi * (1.0 - k) + k)) * (n_wo / (n_wo * (1.0 - k) + k))
        denominator = 4.0 * n_wi * n_wo
        denominator[denominator == 0.0] = 1.0
        f = f + (d * g / denominator)[..., None] * fr
    elif brdf != "lambert":
        sys.exit(f"unknown brdf {brdf}")
    return li * f * n_wi[..., None]


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
