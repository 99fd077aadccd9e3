#!/usr/bin/env bash
# Runs the broad-phase benchmark (tumble and Bullet side by side) and writes
# docs/broad-phase-benchmark.md and docs/broad-phase-scaling.png. Takes a few minutes.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build/release --target bench_broad_phase -j "$(nproc)"
results=$(mktemp)
build/release/tests/benchmarks/bench_broad_phase --benchmark_min_time=0.3 \
  --benchmark_out="$results" --benchmark_out_format=json "$@"
machine="$(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs), $(uname -sr)"
python3 scripts/broad_phase_report.py "$results" docs/broad-phase-benchmark.md \
  docs/broad-phase-scaling.png "$machine"
rm -f "$results"
echo "wrote docs/broad-phase-benchmark.md and docs/broad-phase-scaling.png"
