#!/usr/bin/env python3
"""Peak bytes per pixel of `pointshade render`, per output configuration.

Renders scenes/lambert.toml at 1024² and 2048² pixels for each configuration, reads each run's
peak resident size (the child's ru_maxrss), and prints the difference divided by the difference
in pixels: the bytes a pixel costs at the peak, without the fixed part (binary, scene, BVH).
src/film/memory.rs rounds these up into its estimate.

    cargo build --release && python3 benches/film_memory.py
"""

import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BINARY = os.environ.get("POINTSHADE", os.path.join(ROOT, "target", "release", "pointshade"))
SIZES = (1024, 2048)
CONFIGURATIONS = [
    ("plain PNG", ["--spp", "1"], "png"),
    ("plain EXR", ["--spp", "1"], "exr"),
    ("+ normal AOV", ["--spp", "1", "--aov", "normal"], "exr"),
    ("+ depth AOV", ["--spp", "1", "--aov", "depth"], "exr"),
    ("+ samples AOV", ["--spp", "1", "--aov", "samples"], "exr"),
    ("+ all five AOVs", ["--spp", "1", "--aov", "normal,position,depth,albedo,samples"], "exr"),
    ("adaptive", ["--sampler", "adaptive", "--spp", "4"], "exr"),
    ("cells", ["--sampler", "cells", "--spp", "4"], "exr"),
    ("time budget (sobol)", ["--time-budget", "2"], "exr"),
    ("time budget (adaptive)", ["--sampler", "adaptive", "--spp", "4", "--time-budget", "3"], "exr"),
]


def peak_kib(args):
    """Peak resident KiB of one run (a fresh process, so ru_maxrss is its own)."""
    code = (
        "import resource, subprocess, sys\n"
        "subprocess.run(sys.argv[1:], check=True)\n"
        "print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)\n"
    )
    out = subprocess.run([sys.executable, "-c", code, *args], check=True, capture_output=True, text=True)
    return int(out.stdout.split()[-1])


def main():
    if not os.path.exists(BINARY):
        sys.exit(f"{BINARY} not found: run cargo build --release first")
    scene = os.path.join(ROOT, "scenes", "lambert.toml")
    print(f"{'configuration':<24} {'1024² MiB':>10} {'2048² MiB':>10} {'bytes/pixel':>12}")
    with tempfile.TemporaryDirectory() as tmp:
        for name, extra, ext in CONFIGURATIONS:
            peaks = []
            for side in SIZES:
                out = os.path.join(tmp, f"out.{ext}")
                args = [BINARY, "render", scene, "-o", out, "--quiet", "--width", str(side), "--height", str(side), *extra]
                peaks.append(peak_kib(args))
            per_pixel = (peaks[1] - peaks[0]) * 1024 / (SIZES[1] ** 2 - SIZES[0] ** 2)
            print(f"{name:<24} {peaks[0] / 1024:>10.1f} {peaks[1] / 1024:>10.1f} {per_pixel:>12.1f}")


if __name__ == "__main__":
    main()
