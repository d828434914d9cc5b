#!/usr/bin/env bash
# How far fresh Mitsuba references move when only the host changes, against how far a small
# change of a scene moves them: the measurements behind the staleness check of
# `pointshade validate --check-references` (src/validation/staleness.rs, docs/reference-drift.md).
#
#   validation/reference-drift.sh [--changed-only] [OUT_DIR]   (default target/reference-drift)
#
# Renders every validation scene's pixel-centre Mitsuba export again
#   - natively with llvm_ad_rgb (Dr.Jit compiles for this CPU: 16 lanes on AVX-512),
#   - with scalar_rgb (no vector kernels),
#   - with llvm_ad_rgb under `qemu-x86_64 -cpu EPYC` (an AMD Zen 1 without AVX-512: Dr.Jit and
#     Embree detect AVX2 and run their 8-lane code; qemu computes IEEE results exactly) and
#     `-cpu Haswell` (an Intel AVX2 CPU: another LLVM target-cpu). Mitsuba's wheel needs AVX2:
#     under `-cpu SandyBridge` or older it stops at an illegal instruction. Textured scenes
#     crash under qemu (a segmentation fault in the first kernel), so also
#   - natively with Dr.Jit told to compile for Zen 1 (render.py's POINTSHADE_DRJIT_LLVM_TARGET,
#     with the target qemu's Zen 1 reports): AVX2 kernels beside this CPU's Embree,
# and a few scenes with one deliberate small change (a light moved, a roughness, an exponent or
# a colour changed), and prints each against its committed reference in validation/references:
# the share of pixels beyond 1e-4, 1e-3 and 1e-2 relative error, the largest error, and the
# verdict of the staleness check. Installs qemu-user with apt when it is missing and it can.
# With --changed-only (CI's check, a minute) it renders only the changed scenes, natively, and
# exits 1 unless the check reports every one of them stale.
set -euo pipefail
cd "$(dirname "$0")/.."
changed_only=false
[ "${1:-}" = "--changed-only" ] && { changed_only=true; shift; }
out=${1:-target/reference-drift}
. validation/apt.sh
validation/install.sh >/dev/null
cargo build --release --quiet
ps=./target/release/pointshade
python=validation/.venv/bin/python
rm -rf "$out"
mkdir -p "$out"
if ! $changed_only; then
  command -v qemu-x86_64 >/dev/null || apt_install qemu-user ||
    { echo "error: qemu-user is needed (apt-get install qemu-user)" >&2; exit 1; }
  # What Dr.Jit compiles for on a Zen 1 (CPU;features;lanes), read under qemu.
  zen1=$(qemu-x86_64 -cpu EPYC "$python" -c 'import sys; sys.path.insert(0, "validation"); import libllvm
libllvm.point_drjit_at_libllvm19()
import ctypes, os, drjit as dr, mitsuba as mi
mi.set_variant("llvm_ad_rgb"); dr.eval(dr.llvm.Float(0))
core = ctypes.CDLL(os.path.join(os.path.dirname(dr.__file__), "libdrjit-core.so"))
get = lambda name, t: (setattr(getattr(core, name), "restype", t), getattr(core, name)())[1]
print("%s;%s;%d" % (get("_Z19jit_llvm_target_cpuv", ctypes.c_char_p).decode(),
  get("_Z24jit_llvm_target_featuresv", ctypes.c_char_p).decode(), get("_Z21jit_llvm_vector_widthv", ctypes.c_uint32)))' 2>/dev/null)
  case $zen1 in znver1\;*\;8) ;; *) echo "error: qemu's Zen 1 reported the target '$zen1'" >&2; exit 1 ;; esac
  # Kernels compiled for one target must not be served to another from Dr.Jit's cache.
  DRJIT_CACHE_DIR=$(mktemp -d)
  export DRJIT_CACHE_DIR
  trap 'rm -rf "$DRJIT_CACHE_DIR"' EXIT
  # The exports: one `pointshade validate` run writes every scene's XML (and a native render).
  $ps validate --report "$out/report" --grid 1 >/dev/null 2>&1 || true
fi

# Deliberately changed copies of a few scenes (two folders below the repository, like
# scenes/validation, so their mesh paths resolve).
changed="$out/changed/scenes"
mkdir -p "$changed"
change() { # NAME SCENE SED-EXPRESSION: a copy of scenes/validation/SCENE.toml with one change
  local paths="s|\"\.\./\.\./|\"$PWD/|g"
  sed -e "$3" -e "$paths" "scenes/validation/$2.toml" >"$changed/$1.toml"
  # Against the copy with only its mesh paths made absolute: the edit itself must change a line.
  sed -e "$paths" "scenes/validation/$2.toml" | cmp -s - "$changed/$1.toml" &&
    { echo "error: $1: the edit '$3' changed nothing in scenes/validation/$2.toml" >&2; exit 1; }
  ./target/release/pointshade validate "$changed/$1.toml" --report "$out/changed/report" --grid 1 >/dev/null 2>&1 || true
  # validate names a scene's folder after its file: render it under the original's name.
  echo "$1 $2"
}
{
  change blinn-phong.light-1cm blinn-phong 's/^position = \[2.0, 4.0, 3.0\]/position = [2.01, 4.0, 3.0]/'
  change blinn-phong.shininess-41 blinn-phong 's/^shininess = 40.0/shininess = 41.0/'
  change cook-torrance-terms.roughness-0.36 cook-torrance-terms '30s/^roughness = 0.35/roughness = 0.36/'
  change conductor-sphere.roughness-0.31 conductor-sphere '24s/^roughness = 0.3/roughness = 0.31/'
  change spot.light-1cm spot 's/^position = \[0.0, 4.0, 0.0\]/position = [0.0, 4.01, 0.0]/'
  change diffuse-sphere.albedo-0.5% diffuse-sphere '23s/^albedo = \[0.8,/albedo = [0.804,/'
} >"$out/changed/list"

row() { # LABEL FRESH.exr COMMITTED.exr
  local a=$2 b=$3 t4 t3 t2
  t4=$($ps compare "$a" "$b" --tol 1e-4 --worst 1)
  t3=$($ps compare "$a" "$b" --tol 1e-3 --worst 0)
  t2=$($ps compare "$a" "$b" --tol 1e-2 --worst 0)
  within() { awk '/^within/ {sub("%", "", $3); printf "%.4f", 100 - $3}'; }
  local worst verdict
  worst=$(awk '/^  \(/ {print $4; exit}' <<<"$t4" | tr -d ':')
  verdict=$($ps compare "$a" "$b" --reference-check 2>&1 | sed "s|^error: [^:]*: ||" || true)
  printf '| %s | %s | %s | %s | %s | %s |\n' "$1" "$(within <<<"$t4")" "$(within <<<"$t3")" \
    "$(within <<<"$t2")" "${worst:-0}" "$verdict"
}

render() { # REPORT_SCENE_DIR OUT.exr [WRAPPER...] -- ARGS
  local dir=$1 exr=$2
  shift 2
  "$@" "$python" validation/render.py --out "$exr" "$dir"/mitsuba-spp1.*.xml 2>/dev/null >/dev/null
}

if $changed_only; then
  failed=0
  while read -r label name; do
    dir="$out/changed/report/$label"
    render "$dir" "$dir/native.exr" env
    if verdict=$($ps compare "$dir/native.exr" "validation/references/$name.exr" --reference-check 2>&1); then
      echo "FAILED: $label is not reported stale against validation/references/$name.exr: $verdict" >&2
      failed=1
    else
      echo "ok: $label is stale: ${verdict#*stale: }"
    fi
  done <"$out/changed/list"
  exit "$failed"
fi

echo "| scene, host | % beyond 1e-4 | % beyond 1e-3 | % beyond 1e-2 | largest error | staleness check |"
echo "|---|---|---|---|---|---|"
for dir in "$out"/report/*/; do
  name=$(basename "$dir")
  ref=validation/references/$name.exr
  [ -f "$ref" ] || continue
  for host in "llvm here|native|env" "scalar_rgb|scalar|env POINTSHADE_MITSUBA_VARIANT=scalar_rgb" \
    "llvm AVX2 (Zen 1)|avx2|qemu-x86_64 -cpu EPYC" "llvm AVX2 (Haswell)|haswell|qemu-x86_64 -cpu Haswell" \
    "llvm, Zen 1 kernels, this CPU's Embree|zen1-kernels|env POINTSHADE_DRJIT_LLVM_TARGET=$zen1"; do
    IFS='|' read -r label file wrapper <<<"$host"
    # shellcheck disable=SC2086 # $wrapper is a command and its arguments
    if render "$dir" "$dir/$file.exr" $wrapper; then
      row "$name, $label" "$dir/$file.exr" "$ref"
    else
      # scalar_rgb: the texture plugin (pointshade_textures.py) needs an llvm variant's arrays;
      # qemu: textured scenes crash in their first kernel.
      echo "| $name, $label | | | | | Mitsuba failed |"
    fi
  done
done
while read -r label name; do
  dir="$out/changed/report/$label"
  render "$dir" "$dir/native.exr" env
  row "**$label**, llvm here" "$dir/native.exr" "validation/references/$name.exr"
done <"$out/changed/list"
echo
echo "CPU: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs), $(grep -q -w avx512f /proc/cpuinfo && echo AVX-512 || echo 'no AVX-512')"
