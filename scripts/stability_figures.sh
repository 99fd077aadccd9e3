#!/bin/sh
# Regenerates the figures of docs/stability.md: runs scenes of scenes/stability under both
# solvers with `tumble run`, extracts series from the trajectories and plots them with gnuplot
# (pngcairo). Usage: scripts/stability_figures.sh BUILD_DIR   (from the repository root)
set -eu
build=${1:-build-dev}
tumble="$build/apps/tumble"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
penalty() {  # a copy of scene $1 that asks for the penalty solver
  sed 's/^world:/world:\n  solver: penalty/' "scenes/stability/$1.yaml" >"$work/$1_penalty.yaml"
  echo "$work/$1_penalty.yaml"
}
"$tumble" run -q scenes/stability/tower20.yaml -o "$work/tower_impulse"
"$tumble" run -q "$(penalty tower20)" -o "$work/tower_penalty"
for k in 1e5 1e7 1e9; do
  "$tumble" run -q "scenes/stability/penalty_stack_$k.yaml" -o "$work/stack_$k"
done
"$tumble" run -q scenes/stability/bounce_dt30.yaml -o "$work/bounce_impulse"
"$tumble" run -q "$(penalty bounce_dt30)" -o "$work/bounce_penalty"
python3 scripts/stability_series.py "$work"
gnuplot -e "dir='$work'" scripts/stability_figures.gp
