#!/usr/bin/env bash
# The figures of docs/scale-out.md: a sweep in one process and over 2 and 3 MPI ranks (1 and 2
# workers), the per-run hand-out cost (a sweep of one-step runs), and the RL batch of
# examples/python/mpi_rollout.py on 1 and 2 ranks. Each measurement runs 3 times; prints
# min / median / max. Usage: scripts/scale_out_figures.sh [build dir]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build/release}
cli=$(realpath "$build/apps/tumble")
python=/usr/bin/python3
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cp scenes/stack10.yaml "$work/scene.yaml"
cat > "$work/long.yaml" <<'SPEC'
scene: scene.yaml
duration: 20
vary:
  world.dt: [0.01, 0.005]
  materials.default.friction: {from: 0.2, to: 0.8, count: 8}
SPEC
cat > "$work/short.yaml" <<'SPEC'
scene: scene.yaml
duration: 0.01
vary:
  materials.default.friction: {from: 0.2, to: 0.8, count: 400}
SPEC
spread() { sort -g | awk '{v[NR]=$1} END {printf "%.4g / %.4g / %.4g", v[1], v[int((NR+1)/2)], v[NR]}'; }
seconds() {
  local t0 t1
  t0=$(date +%s%N)
  "$@" > /dev/null
  t1=$(date +%s%N)
  awk -v ns=$((t1 - t0)) 'BEGIN {printf "%.4f\n", ns / 1e9}'
}
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs), load $(cut -d' ' -f1 /proc/loadavg)"
for spec in long short; do
  runs=400
  [ "$spec" = long ] && runs=16
  for ranks in 1 2 3; do
    times=()
    for rep in 1 2 3; do
      rm -rf "$work/out"
      if [ "$ranks" = 1 ]; then
        times+=("$(seconds "$cli" sweep "$work/$spec.yaml" -o "$work/out")")
      else
        times+=("$(seconds mpirun -n "$ranks" "$cli" sweep "$work/$spec.yaml" -o "$work/out")")
      fi
    done
    echo "sweep $spec ($runs runs), $( [ "$ranks" = 1 ] && echo "one process" || echo "mpirun -n $ranks")," \
      "seconds min/median/max: $(printf '%s\n' "${times[@]}" | spread)"
    # The phases of one more run, as the sweep reports them (checking, running, tables).
    rm -rf "$work/out"
    if [ "$ranks" = 1 ]; then
      "$cli" sweep "$work/$spec.yaml" -o "$work/out" | grep -E "checked|ran " | sed 's/^/    /'
    else
      mpirun -n "$ranks" "$cli" sweep "$work/$spec.yaml" -o "$work/out" | grep -E "checked|ran " |
        sed 's/^/    /'
    fi
  done
done
export PYTHONPATH=$build/python
for ranks in 1 2; do
  for rep in 1 2 3; do
    if [ "$ranks" = 1 ]; then
      $python examples/python/mpi_rollout.py --envs 1024 --steps 100 --json "$work/r$rep.json" > /dev/null
    else
      mpirun -n 2 $python examples/python/mpi_rollout.py --envs 1024 --steps 100 --json "$work/r$rep.json" > /dev/null
    fi
  done
  echo "rollout 1024 worlds, $ranks rank(s), env-steps/s min/median/max:" \
    "$(for r in 1 2 3; do $python -c "import json; print(json.load(open('$work/r$r.json'))['env_steps_per_second'])"; done | spread);" \
    "gather us/step: $(for r in 1 2 3; do $python -c "import json; print(1e6 * json.load(open('$work/r$r.json'))['gather_seconds_per_step'])"; done | spread)"
done
