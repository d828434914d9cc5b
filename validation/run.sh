#!/usr/bin/env bash
# The whole validation from scratch, as CI runs it: install Mitsuba 3.9.1 (install.sh), render
# fresh Mitsuba references of every validation scene, compare pointshade with them, fail if a
# committed reference in validation/references is stale (`pointshade validate --help` says what
# counts as stale), write the HTML report, and screenshot the report in headless Chromium. The
# report and its screenshot are written even when a comparison fails; the script then exits
# with validate's status.   Usage: validation/run.sh [REPORT_DIR]  (default
# target/validation)
set -euo pipefail
cd "$(dirname "$0")/.."
report=${1:-target/validation}
validation/install.sh
cargo build --release --quiet
start=$(date +%s)
status=0
rm -f "$report/index.html"  # never screenshot an earlier run's report
./target/release/pointshade validate --report "$report" --check-references validation/references || status=$?
echo "validate took $(( $(date +%s) - start )) s"
if [ -f "$report/index.html" ]; then
  validation/screenshot.sh "$report/index.html" "$report/screenshot.png"
else
  echo "no report to screenshot: validate stopped before writing $report/index.html" >&2
fi
if [ "$status" != 0 ]; then
  echo "validation FAILED (pointshade validate exited with $status); the report is $report/index.html" >&2
fi
exit "$status"
