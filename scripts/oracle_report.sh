#!/bin/sh
# Regenerates the Bullet oracle outputs committed under docs/: error-against-run-time reports
# (docs/reports/<scene>/), side-by-side comparisons (docs/reports/compare/<scene>/) and the
# side-by-side benchmarks (docs/benchmarks/*.csv; docs/benchmarks.md quotes them).
# Needs a Release build with Bullet (TUMBLE_WITH_BULLET) and gnuplot. Run from the repository
# root: scripts/oracle_report.sh [path/to/tumble]. Takes about 10 minutes on one core.
set -eu
TUMBLE=${1:-build-dev/apps/tumble}
[ -x "$TUMBLE" ] || { echo "oracle_report.sh: no tumble binary at $TUMBLE" >&2; exit 1; }

for scene in free_flight spinning_box bounce incline_slide incline_stick stack10 demo; do
  echo "== report $scene"
  "$TUMBLE" report "scenes/$scene.yaml" -o "docs/reports/$scene" 2>/dev/null
  echo "== compare $scene"
  "$TUMBLE" compare "scenes/$scene.yaml" -q -o "docs/reports/compare/$scene" >/dev/null
done
# The benchmark pyramid: 4 s are enough to settle it, and keep the sweep's fine reference short.
echo "== report pyramid_20"
"$TUMBLE" report scenes/bench/pyramid_20.yaml --duration 4 -o docs/reports/pyramid_20 2>/dev/null
for scene in pyramid_20 bullet_1000_stack bullet_3000_boxes; do
  echo "== compare $scene"
  "$TUMBLE" compare "scenes/bench/$scene.yaml" -q -o "docs/reports/compare/$scene" >/dev/null
  # Per-body errors of a thousand bodies are large and say little for a chaotic scene.
  rm -f "docs/reports/compare/$scene/errors.csv"
done
mkdir -p docs/benchmarks
echo "== bench"
"$TUMBLE" bench scenes/bench/*.yaml --repetitions 3 -o docs/benchmarks | tee docs/benchmarks/oracle_bench.txt
