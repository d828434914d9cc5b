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

# One check with render.py (validation/libllvm.py). The `ldconfig -p | grep -q` this replaces
# failed under pipefail when the listing outgrew the pipe: grep exits at its match, ldconfig gets
# SIGPIPE (status 141), and an installed libLLVM 19 was reported missing.
if ! python3 "$here/libllvm.py" >/dev/null; then
  apt_install libllvm19 || true
fi
if ! python3 "$here/libllvm.py"; then
  echo "WARNING: libLLVM 19 is missing and cannot be installed here: the references are rendered with scalar_rgb" >&2
fi
echo "validation environment ready in $(( $(date +%s) - start )) s"
