#!/usr/bin/env bash
# Error against time on the dragon (issue 7's benchmark): renders a Mitsuba 3 reference with a
# 32×32 grid, then sweeps pointshade (sobol, grid) and Mitsuba (grid, independent) at 1…256
# samples per pixel and pointshade's adaptive samplers (adaptive, cells) over thresholds
# 0.04…0.0025 (at most 256 samples per pixel) and, as dashed lines, sobol, adaptive and cells to
# time budgets of 0.2…0.8 s, in one run, medians of 3 repeats. Needs ../shared and Mitsuba
# (validation/install.sh). Writes target/convergence-dragon/convergence.{csv,svg,png}.
#   Usage: benches/convergence-dragon.sh [OUT_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-target/convergence-dragon}
scene=scenes/shared/dragon-copper.toml
validation/install.sh >/dev/null
cargo build --release --quiet
mkdir -p "$out"
./target/release/pointshade export-mitsuba "$scene" --sampler grid --spp 1024 --per-light -o "$out/reference.xml" 2>/dev/null
validation/.venv/bin/python validation/render.py --out "$out/reference-32x32.exr" "$out"/reference.light*.xml
./target/release/pointshade convergence "$scene" --reference "$out/reference-32x32.exr" \
  --spp 1,4,16,64,256 --sampler sobol,adaptive,cells,grid --adaptive-threshold 0.04,0.02,0.01,0.0075,0.005,0.0025 \
  --time-budget 0.2,0.3,0.5,0.8 --mitsuba --repeats 3 --out "$out"
