"""Finds libLLVM 19 for Dr.Jit's llvm variants: the one check that install.sh and render.py share.

    python3 validation/libllvm.py

prints the library and the Mitsuba variant the references will be rendered with, and exits 0 when
libLLVM 19 is there (variant llvm_ad_rgb), 1 when it is not (variant scalar_rgb). Standard library
only, so that install.sh can run it before the virtual environment exists.

Why a library of one version: Debian 12 ships LLVM 14 and 15 too; Dr.Jit 1.5 does not load 14, and
with 15 the conductor kernels abort ("Cannot select: fmaximum"). DRJIT_LIBLLVM_PATH, when set,
is used as it is (Dr.Jit reads it), provided the file exists.
"""

import glob
import os
import subprocess
import sys

# Where Debian's libllvm19 package and LLVM's own packages put the library.
PATTERNS = (
    "/usr/lib/x86_64-linux-gnu/libLLVM.so.19*",
    "/usr/lib/x86_64-linux-gnu/libLLVM-19.so*",
    "/lib/x86_64-linux-gnu/libLLVM.so.19*",
    "/usr/lib/*/libLLVM.so.19*",
    "/usr/lib/*/libLLVM-19.so*",
    "/usr/lib/llvm-19/lib/libLLVM*.so*",
)


def _from_ldconfig():
    """libLLVM 19 as the dynamic linker's cache lists it (no shell pipe: see install.sh)."""
    try:
        listing = subprocess.run(
            ["ldconfig", "-p"], capture_output=True, text=True, check=False
        ).stdout
    except OSError:
        return None
    for line in listing.splitlines():
        name, _, path = line.partition("=>")
        name = name.strip().split(" ")[0]
        if name.startswith(("libLLVM.so.19", "libLLVM-19.so")) and os.path.isfile(path.strip()):
            return path.strip()
    return None


def find_libllvm19():
    """The path of libLLVM 19, or None."""
    given = os.environ.get("DRJIT_LIBLLVM_PATH")
    if given:
        return given if os.path.isfile(given) else None
    for pattern in PATTERNS:
        found = sorted(p for p in glob.glob(pattern) if os.path.isfile(p))
        if found:
            return found[0]
    return _from_ldconfig()


def variant():
    """The Mitsuba variant the references use here: llvm_ad_rgb with libLLVM 19, else scalar_rgb."""
    return "llvm_ad_rgb" if find_libllvm19() else "scalar_rgb"


def point_drjit_at_libllvm19():
    """Sets DRJIT_LIBLLVM_PATH so that Dr.Jit loads libLLVM 19 and not an older LLVM it finds
    first; returns the path, or None when libLLVM 19 is missing."""
    path = find_libllvm19()
    if path:
        os.environ["DRJIT_LIBLLVM_PATH"] = path
    return path


def main():
    path = find_libllvm19()
    if path:
        print(f"libLLVM 19: {path}; Mitsuba references use llvm_ad_rgb")
        return 0
    print("libLLVM 19: missing; Mitsuba references use scalar_rgb (slower)")
    return 1


if __name__ == "__main__":
    sys.exit(main())
