#!/usr/bin/env bash
# Screenshots an HTML page with headless Chromium (Debian's chromium package, installed with apt
# when missing and possible) and checks the picture is not blank.
#   Usage: validation/screenshot.sh PAGE.html OUT.png
set -euo pipefail
page=$(realpath "$1")
out=$(realpath -m "$2")
. "$(dirname "$0")/apt.sh"
if ! command -v chromium >/dev/null 2>&1; then
  if ! apt_install chromium; then
    echo "SKIPPED: chromium is missing and cannot be installed here; the report was not screenshot" >&2
    exit 0
  fi
fi
profile=$(mktemp -d)
trap 'rm -rf "$profile"' EXIT
# The flags keep Chromium off the network (this machine has none) and out of the user's profile.
timeout 120 chromium --headless --no-sandbox --disable-gpu --disable-quic --no-first-run \
  --disable-background-networking --disable-component-update --disable-sync \
  --user-data-dir="$profile" --window-size=1280,2000 --screenshot="$out" "file://$page" >/dev/null 2>&1
size=$(stat -c %s "$out")
if [ "$size" -lt 50000 ]; then
  echo "error: $out: screenshot of the report is only $size bytes: the page did not render" >&2
  exit 1
fi
echo "screenshot: $out ($size bytes)"
