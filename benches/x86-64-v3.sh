#!/usr/bin/env bash
# The opt-in build for x86-64-v3 CPUs (AVX2, FMA, BMI1/2, F16C, MOVBE, LZCNT: Intel from Haswell,
# AMD from Zen). Builds pointshade with RUSTFLAGS="-C target-cpu=x86-64-v3" into
# target/x86-64-v3 and checks that it writes the same bytes as the portable release build for
# every shipped scene (scenes/ and scenes/validation/), the dragon at its equal-error setting and the normal-map presets (Rust
# never fuses a multiply and an add on its own, so wider instructions should not change a bit;
# this is the check). With --time N it then times both binaries on the equal-error dragon
# render, N alternating runs each, and prints the medians of the render stage and of the process.
#   Usage: benches/x86-64-v3.sh [--time N]
# Exit 1 when an output differs; a CPU without x86-64-v3 says SKIPPED and exits 0. The shared
# scenes and the normal image need ../shared (skipped loudly without it).
set -euo pipefail
cd "$(dirname "$0")/.."
runs=0
[ "${1:-}" = "--time" ] && runs=${2:?--time needs a run count}

flags=$(grep -m1 '^flags' /proc/cpuinfo 2>/dev/null || true)
for f in avx2 fma bmi1 bmi2 f16c movbe abm; do
  if ! grep -qw "$f" <<<"$flags"; then
    echo "SKIPPED: this CPU lacks $f, so it cannot run an x86-64-v3 build"
    exit 0
  fi
done

cargo build --release --quiet
RUSTFLAGS="-C target-cpu=x86-64-v3" cargo build --release --quiet --target-dir target/x86-64-v3
portable=target/release/pointshade
v3=target/x86-64-v3/release/pointshade
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

# name, then the command's arguments with OUT where the output path goes.
cases=()
for scene in scenes/*.toml scenes/validation/*.toml; do
  cases+=("${scene//\//-}|render $scene -o OUT.exr")
done
if [ -d ../shared/data ]; then
  for scene in scenes/shared/*.toml scenes/validation/shared/*.toml; do
    cases+=("${scene//\//-}|render $scene -o OUT.exr")
  done
  cases+=("dragon-equal-error|render scenes/shared/dragon-copper.toml --sampler cells --spp 256 --adaptive-threshold 0.0075 --shadow-offset mitsuba -o OUT.exr")
  for preset in tp physical; do
    for brdf in lambert blinn-phong cook-torrance; do
      cases+=("normalmap-$preset-$brdf|normalmap ../shared/data/normalmaps/normal.png --preset $preset --brdf $brdf -o OUT.exr")
    done
  done
else
  echo "SKIPPED: ../shared is absent: the shared scenes, the equal-error dragon and the normal-map presets are not compared"
fi

differ=0
for c in "${cases[@]}"; do
  name=${c%%|*}
  args=${c#*|}
  # shellcheck disable=SC2086 # the arguments are words on purpose
  $portable ${args//OUT/$out/$name-portable} -q
  # shellcheck disable=SC2086
  $v3 ${args//OUT/$out/$name-v3} -q
  if cmp -s "$out/$name-portable.exr" "$out/$name-v3.exr"; then
    echo "same bytes: $name"
  else
    echo "DIFFERS: $name"
    differ=1
  fi
done
[ $differ = 0 ] || { echo "FAILED: the x86-64-v3 build writes other bytes than the portable one"; exit 1; }

if [ "$runs" -gt 0 ]; then
  [ -d ../shared/data ] || { echo "SKIPPED: timing needs ../shared (the dragon)"; exit 0; }
  for _ in $(seq "$runs"); do
    for b in $portable $v3; do
      start=$(date +%s%N)
      stage=$($b render scenes/shared/dragon-copper.toml --sampler cells --spp 256 --adaptive-threshold 0.0075 \
        --shadow-offset mitsuba -o "$out/time.exr" 2>&1 | grep -o 'render [0-9.]* s' | grep -o '[0-9.]*')
      end=$(date +%s%N)
      echo "$b $stage $(( (end - start) / 1000 ))"
    done
  done | python3 -c '
import statistics, sys
times = {}
for line in sys.stdin:
    binary, stage, process = line.split()
    times.setdefault(binary, ([], []))
    times[binary][0].append(float(stage))
    times[binary][1].append(float(process) / 1e6)
for binary, (stage, process) in times.items():
    print(f"{binary}: render stage {statistics.median(stage):.4f} s, process {statistics.median(process):.4f} s (medians of {len(stage)})")
'
fi
