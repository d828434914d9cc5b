"""Renders Mitsuba 3 XML scenes and writes their sum as one float32 EXR.

    render.py --out REF.exr [--variant llvm_ad_rgb|scalar_rgb] SCENE.xml [SCENE.xml ...]

pointshade exports one XML per light (Mitsuba samples one light per sample, so a deterministic
reference renders each light alone and sums: the render is linear in the lights). The pointshade
BSDF plugin is registered first. Prints one JSON line: variant, seconds to load and to render.
"""

import argparse
import ctypes.util
import glob
import json
import os
import sys
import time


def pick_llvm():
    """Points Dr.Jit at libLLVM 19 when present (LLVM 15 aborts on conductor kernels)."""
    if "DRJIT_LIBLLVM_PATH" in os.environ:
        return True
    for pattern in ("/usr/lib/x86_64-linux-gnu/libLLVM.so.19*", "/usr/lib/*/libLLVM-19.so*", "/usr/lib/llvm-19/lib/libLLVM*.so*"):
        found = sorted(glob.glob(pattern))
        if found:
            os.environ["DRJIT_LIBLLVM_PATH"] = found[0]
            return True
    return False


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--out", required=True)
    parser.add_argument("--variant", default=None, help="default: llvm_ad_rgb with LLVM 19, else scalar_rgb")
    parser.add_argument("scenes", nargs="+")
    args = parser.parse_args()

    variant = args.variant or ("llvm_ad_rgb" if pick_llvm() else "scalar_rgb")
    if variant.startswith("llvm"):
        pick_llvm()
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import drjit as dr
    import mitsuba as mi

    mi.set_variant(variant)
    import pointshade_bsdf

    pointshade_bsdf.register()

    total = None
    load_s = render_s = 0.0
    for path in args.scenes:
        t0 = time.perf_counter()
        scene = mi.load_file(path)
        t1 = time.perf_counter()
        image = mi.render(scene)
        dr.eval(image)
        dr.sync_thread()
        t2 = time.perf_counter()
        load_s += t1 - t0
        render_s += t2 - t1
        total = image if total is None else total + image
    bitmap = mi.Bitmap(total, pixel_format=mi.Bitmap.PixelFormat.RGB)
    bitmap.write(args.out)
    print(json.dumps({"variant": variant, "load_s": load_s, "render_s": render_s}))


if __name__ == "__main__":
    main()
