#!/usr/bin/env bash
# Installs Mitsuba 3.9.1 (pinned in requirements.txt) into validation/.venv, and libLLVM 19 for
# Mitsuba's llvm_ad_rgb variant where apt is available (LLVM 15, Debian 12's default, aborts on
# conductor kernels; without LLVM 19 the references fall back to the slower scalar_rgb variant).
# Idempotent: a second run only checks. Prints what it did and how long it took.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
venv="$here/.venv"
start=$(date +%s)
. "$here/apt.sh"

if "$venv/bin/python" -c 'import mitsuba, sys; sys.exit(mitsuba.__version__ != "3.9.1")' 2>/dev/null; then
  echo "mitsuba 3.9.1 already installed in $venv"
else
  echo "installing mitsuba 3.9.1 into $venv"
  python3 -m venv "$venv"
  "$venv/bin/pip" install --quiet --upgrade pip
  "$venv/bin/pip" install --quiet -r "$here/requirements.txt"
fi

if ldconfig -p 2>/dev/null | grep -q 'libLLVM.so.19\|libLLVM-19'; then
  echo "libLLVM 19 present"
elif ! apt_install libllvm19; then
  echo "WARNING: libLLVM 19 is missing and cannot be installed here: references will use scalar_rgb (slower)" >&2
fi
echo "validation environment ready in $(( $(date +%s) - start )) s"
