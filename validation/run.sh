#!/usr/bin/env bash
# The whole validation from scratch, as CI runs it: install Mitsuba 3.9.1 (install.sh), render
# fresh Mitsuba references of every validation scene, compare pointshade with them, fail if a
# committed reference in validation/references is stale, write the HTML report, and screenshot
# the report in headless Chromium.   Usage: validation/run.sh [REPORT_DIR]  (default
# target/validation)
set -euo pipefail
cd "$(dirname "$0")/.."
report=${1:-target/validation}
validation/install.sh
cargo build --release --quiet
start=$(date +%s)
./target/release/pointshade validate --report "$report" --check-references validation/references
echo "validate took $(( $(date +%s) - start )) s"
validation/screenshot.sh "$report/index.html" "$report/screenshot.png"
