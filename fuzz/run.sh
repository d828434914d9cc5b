#!/usr/bin/env bash
# Runs fuzz targets: fuzz/run.sh SECONDS [TARGET...] (default: every target).
# Each runs from the committed corpus (fuzz/corpus/TARGET) plus, where present, the shared seeds
# (fuzz/corpus-shared/TARGET, from make_seeds.py --shared), growing its working corpus in
# fuzz/work/TARGET (not committed), with libFuzzer's -rss_limit_mb=2048 -timeout=10. A crash,
# leak, OOM or time-out fails the run (exit non-zero) and leaves the input in fuzz/artifacts/.
set -euo pipefail
cd "$(dirname "$0")"
seconds=${1:?usage: fuzz/run.sh SECONDS [TARGET...]}
shift
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  targets=(obj gltf scene_file normal_map_scene normal_image exr geometry)
fi
declare -A dict=([obj]=dicts/obj.dict [gltf]=dicts/gltf.dict [scene_file]=dicts/toml.dict [normal_map_scene]=dicts/toml.dict)
bin=target/x86_64-unknown-linux-gnu/release
for t in "${targets[@]}"; do
  mkdir -p "work/$t" "artifacts/$t"
  seeds=("corpus/$t")
  [ -d "corpus-shared/$t" ] && seeds+=("corpus-shared/$t")
  flags=(-max_total_time="$seconds" -rss_limit_mb=2048 -timeout=10 -print_final_stats=1
         -artifact_prefix="artifacts/$t/")
  [ -n "${dict[$t]:-}" ] && flags+=(-dict="${dict[$t]}")
  echo "== fuzz $t for $seconds s"
  "$bin/$t" "${flags[@]}" "work/$t" "${seeds[@]}" 2> "work/$t.log" || {
    tail -40 "work/$t.log" >&2
    echo "FAILED: fuzz target $t (input in fuzz/artifacts/$t/)" >&2
    exit 1
  }
  grep -E "^#[0-9]+.*DONE|stat::number_of_executed_units|cov:" "work/$t.log" | tail -2
done
