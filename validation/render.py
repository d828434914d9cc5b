"""Renders Mitsuba 3 XML scenes and writes their sum as one float32 EXR.

    render.py --out REF.exr [--variant llvm_ad_rgb|scalar_rgb] SCENE.xml [SCENE.xml ...]

pointshade exports one XML per light (Mitsuba samples one light per sample, so a deterministic
reference renders each light alone and sums: the render is linear in the lights). The pointshade
BSDF plugin is registered first. The variant is llvm_ad_rgb where libLLVM 19 is installed and
scalar_rgb elsewhere (validation/libllvm.py decides, as it does for install.sh), unless --variant or
POINTSHADE_MITSUBA_VARIANT names one. Prints one JSON line: the variant, the libLLVM it loaded,
seconds to load and to render.
"""

import argparse
import json
import os
import sys
import time


def compile_for(target):
    """Makes Dr.Jit compile its kernels for another CPU: `target` is "CPU;FEATURES;LANES", as
    Dr.Jit detects them on that CPU (validation/reference-drift.sh measures another host's
    rounding this way where qemu cannot run the scene). Embree keeps this host's kernels."""
    import ctypes

    import drjit as dr

    cpu, features, lanes = target.split(";")
    dr.eval(dr.llvm.Float(0))  # starts the LLVM backend, which detects this host first
    core = ctypes.CDLL(os.path.join(os.path.dirname(dr.__file__), "libdrjit-core.so"))
    set_target = core._Z19jit_llvm_set_targetPKcS0_j  # jit_llvm_set_target(cpu, features, lanes)
    set_target.argtypes = [ctypes.c_char_p, ctypes.c_char_p, ctypes.c_uint32]
    set_target(cpu.encode(), features.encode(), int(lanes))


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--out", required=True)
    parser.add_argument(
        "--variant",
        default=os.environ.get("POINTSHADE_MITSUBA_VARIANT"),
        help="default: $POINTSHADE_MITSUBA_VARIANT, else llvm_ad_rgb with libLLVM 19, else scalar_rgb",
    )
    parser.add_argument("scenes", nargs="+")
    args = parser.parse_args()

    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import libllvm

    library = libllvm.point_drjit_at_libllvm19()
    variant = args.variant or libllvm.variant()
    if variant.startswith("llvm") and not library:
        sys.exit(f"error: variant {variant} needs libLLVM 19, which is missing (validation/install.sh)")
    import drjit as dr
    import mitsuba as mi

    mi.set_variant(variant)
    if os.environ.get("POINTSHADE_DRJIT_LLVM_TARGET") and variant.startswith("llvm"):
        compile_for(os.environ["POINTSHADE_DRJIT_LLVM_TARGET"])
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
    print(json.dumps({"variant": variant, "llvm": library if variant.startswith("llvm") else None, "load_s": load_s, "render_s": render_s}))


if __name__ == "__main__":
    main()
