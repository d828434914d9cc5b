#!/usr/bin/env bash
# The explorer in a real browser: Debian's chromium (installed with apt when missing and
# possible), driven by Playwright from PyPI (no browser download) in target/browser-venv.
# Screenshots and the speed table go to target/explore/.
#   Usage: tests/browser/run.sh   (after `cargo build --release`)
set -euo pipefail
cd "$(dirname "$0")/../.."
. validation/apt.sh
if ! command -v chromium >/dev/null 2>&1; then
  if ! apt_install chromium; then
    echo "error: chromium is missing and cannot be installed here (apt as root): the browser test cannot run" >&2
    exit 1
  fi
fi
venv=target/browser-venv
if [ ! -x "$venv/bin/python" ]; then
  python3 -m venv "$venv"
fi
"$venv/bin/python" -m pip install --quiet --upgrade pip
"$venv/bin/python" -m pip install --quiet "playwright==1.*" pytest pillow
mkdir -p target/explore
POINTSHADE_CLI=${POINTSHADE_CLI:-target/release/pointshade} "$venv/bin/python" -m pytest tests/browser -q -rs -p no:cacheprovider "$@"
