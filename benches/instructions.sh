#!/usr/bin/env bash
# Instruction counts of fixed renders, per stage, against a committed baseline: the regression
# gate for speed that timing cannot be on a shared, noisy 2-core machine. Each case runs once
# under valgrind's callgrind on one thread (`--threads 1`: the counts are then the same from run
# to run, to about 1e-5), and callgrind dumps its counters as each stage's function returns, so
# that each dump counts one stage:
#   load    start-up and pointshade::scene::load::load_with
#   bvh     the plan and pointshade::accel::Bvh::build
#   render  the rest of pointshade::render::render_scene_until
#   output  encoding, writing and exit (reported, not checked: PNG compression)
# (Inclusive costs from callgrind_annotate split inlined functions across source files
# unreliably; the dumps do not depend on inlining, only on those three functions existing.)
# A case fails when load + bvh + render, or one of those stages on its own (those of at least
# STAGE_FLOOR instructions), moves by more than TOLERANCE_PERCENT from the baseline, either way:
# a regression, or a gain the baseline should record (then rerun with --update and commit
# benches/instructions.baseline with the change that made it). The cases: the dragon at the
# equal-error setting and at its defaults (OBJ load, BVH, packets, adaptive sampling), the
# Cornell box (own meshes, large flat walls) and DamagedHelmet (glTF, JPEG textures, normal
# mapping, emission, three lights, point-by-point shading).
#
# Counts depend on the compiler and on the CPU path the shader picks (AVX2 or SSE2), which the
# baseline records: when either differs here, the check says SKIPPED and why, and exits 0.
#   Usage: benches/instructions.sh [--update]      (needs valgrind: installed with apt when missing
#   and run as root, as in CI). POINTSHADE_BIN=path measures another build (an A/B of two
#   binaries: copy target/instructions/pointshade aside first). It builds the `instructions`
#   profile (Cargo.toml): the release build with pointshade in one codegen unit.
set -euo pipefail
cd "$(dirname "$0")/.."
TOLERANCE_PERCENT=3
# Stages with fewer instructions than this (the Cornell box's load and build) are checked only
# within their case's sum: a few thousand instructions would be percents of them.
STAGE_FLOOR=100000000
baseline=benches/instructions.baseline
update=false
[ "${1:-}" = "--update" ] && update=true

if ! command -v valgrind >/dev/null; then
  . validation/apt.sh
  apt_install valgrind || { echo "FAILED: valgrind is not installed (apt-get install valgrind)" >&2; exit 1; }
fi
if [ -z "${POINTSHADE_BIN:-}" ]; then
  cargo build --profile instructions --quiet
fi
bin=${POINTSHADE_BIN:-./target/instructions/pointshade}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

rustc_version=$(rustc --version)
avx2=$(grep -qw avx2 /proc/cpuinfo && echo yes || echo no)
config="rustc=${rustc_version// /_} avx2=$avx2"

# name | scene | extra arguments (all render at one thread into a PNG)
cases=(
  "dragon-equal-error|scenes/shared/dragon-copper.toml|--sampler cells --spp 256 --adaptive-threshold 0.0075 --shadow-offset mitsuba"
  "dragon-default|scenes/shared/dragon-copper.toml|"
  "cornell-box|scenes/cornell-box.toml|"
  "damaged-helmet|scenes/shared/damaged-helmet.toml|--spp 1"
)

# The instructions counted in callgrind dump file $1.
counted() {
  sed -n 's/^summary: \([0-9]*\)$/\1/p' "$1"
}

results="$work/results"
: > "$results"
for case in "${cases[@]}"; do
  IFS='|' read -r name scene args <<< "$case"
  if [ ! -f "$scene" ]; then
    echo "FAILED: $scene is missing" >&2
    exit 1
  fi
  if [[ "$scene" == scenes/shared/* ]] && [ ! -d ../shared/data ]; then
    echo "SKIPPED: $name needs ../shared/data, which is missing" >&2
    continue
  fi
  out="$work/$name.cg"
  # shellcheck disable=SC2086 # $args is a list of arguments
  valgrind --tool=callgrind --callgrind-out-file="$out" \
    --dump-after='pointshade::scene::load::load_with' --dump-after='pointshade::accel::Bvh::build' \
    --dump-after='pointshade::render::render_scene_until' \
    "$bin" render "$scene" $args -o "$work/$name.png" --threads 1 --quiet 2>"$work/$name.log" || {
    cat "$work/$name.log" >&2
    echo "FAILED: $name did not render" >&2
    exit 1
  }
  if [ ! -f "$out.3" ]; then
    echo "FAILED: $name: callgrind did not dump at each stage's end (is a stage function inlined? they must stay #[inline(never)])" >&2
    exit 1
  fi
  echo "$name load=$(counted "$out.1") bvh=$(counted "$out.2") render=$(counted "$out.3") output=$(counted "$out")" >> "$results"
done

if $update; then
  {
    echo "# benches/instructions.sh --update, $(date -u +%Y-%m-%d) (git log names the commit it belongs to)"
    echo "config $config"
    cat "$results"
  } > "$baseline"
  echo "wrote $baseline"
fi

# A count in G (or M below 0.1 G), for the table.
g() { awk -v n="$1" 'BEGIN { if (n < 1e8) printf "%.1f M", n / 1e6; else printf "%.3f G", n / 1e9 }'; }
field() { sed -n "s/.*\b$2=\([0-9]*\).*/\1/p" <<< "$1"; }
# The change from $2 to $1 in percent, signed.
change_of() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%+.2f", 100 * (a - b) / b }'; }
# Whether a change (percent) lies outside the tolerance.
outside() { awk -v d="$1" -v t="$TOLERANCE_PERCENT" 'BEGIN { exit !(d > t || d < -t) }'; }
echo
echo "| case | load | bvh | render | load+bvh+render | baseline | change | output (not checked) |"
echo "|---|---|---|---|---|---|---|---|"
failed=0
base_config=$(sed -n 's/^config //p' "$baseline" 2>/dev/null || true)
comparable=true
if [ "$base_config" != "$config" ]; then
  comparable=false
fi
while read -r line; do
  name=${line%% *}
  sum=$(( $(field "$line" load) + $(field "$line" bvh) + $(field "$line" render) ))
  base_line=$(grep "^$name " "$baseline" 2>/dev/null || true)
  if [ -n "$base_line" ]; then
    base=$(( $(field "$base_line" load) + $(field "$base_line" bvh) + $(field "$base_line" render) ))
    d=$(change_of "$sum" "$base")
    change="$d%"
    $comparable && outside "$d" && change="$change **outside ±$TOLERANCE_PERCENT%**"
    # Each stage of at least STAGE_FLOOR instructions on its own too, so that a stage's
    # regression cannot hide behind another's gain or a large stage (the helmet's JPEG decoding).
    for stage in load bvh render; do
      b=$(field "$base_line" "$stage")
      if [ "$b" -ge "$STAGE_FLOOR" ]; then
        ds=$(change_of "$(field "$line" "$stage")" "$b")
        $comparable && outside "$ds" && change="$change **$stage $ds% outside ±$TOLERANCE_PERCENT%**"
      fi
    done
    [[ "$change" == *outside* ]] && failed=1
  else
    base="none"
    change="no baseline"
    $comparable && failed=1
  fi
  echo "| $name | $(g "$(field "$line" load)") | $(g "$(field "$line" bvh)") | $(g "$(field "$line" render)") | $(g "$sum") | $( [ "$base" = none ] && echo none || g "$base") | $change | $(g "$(field "$line" output)") |"
done < "$results"
echo
if ! $comparable; then
  echo "SKIPPED: the baseline was counted with '$base_config', this machine is '$config': counts not compared" >&2
  exit 0
fi
if [ "$failed" = 1 ]; then
  echo "FAILED: instruction counts moved by more than ±$TOLERANCE_PERCENT% (a regression, or a gain: rerun with --update and commit the baseline)" >&2
  exit 1
fi
echo "ok: every case within ±$TOLERANCE_PERCENT% of $baseline"
