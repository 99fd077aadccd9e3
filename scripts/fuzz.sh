#!/usr/bin/env bash
# Fuzzes tumble: builds every target of tests/fuzz with clang (libFuzzer, with AddressSanitizer,
# UndefinedBehaviorSanitizer and float-cast-overflow) and runs each for SECONDS (default 60).
#
#   scripts/fuzz.sh [SECONDS]            (FUZZ_OPT=-O1: the faster build of a short run)
#
# Seeds: the repository's own inputs (scenes, malformed scenes, OBJ meshes, CCD sample queries,
# the query example of docs/scene-format.md) for the targets that read files, and
# tests/fuzz/seeds/TARGET.hex (one input per line, in hex) for the targets that draw shapes and
# settings from bytes. The corpus grows in build/fuzz/corpus; FUZZ_SAVE_SEEDS=1 merges it back
# into the .hex files (libFuzzer's -merge keeps one input per new feature).
#
# The long run: FUZZ_RUNS=N runs each target for N executions instead of a time, and
# FUZZ_TARGETS="fuzz_sdf fuzz_query_file" picks targets (default: all), for example
#
#   FUZZ_RUNS=10000000 FUZZ_TARGETS="fuzz_sdf fuzz_query_file" scripts/fuzz.sh
#
# Prints per target: executions, coverage (edges), corpus size and findings. Exits non-zero on any
# finding; each is kept in build/fuzz/findings/TARGET/ (crash-*, timeout-*, oom-*, leak-*), to be
# replayed with `build/fuzz/tests/fuzz/TARGET FILE`; a fixed finding gets a regression test in the
# suite, and its input goes into the target's seeds so that every later run replays it.
set -euo pipefail
seconds=${1:-60}
cd "$(dirname "$0")/.."
root=$PWD
build=${TUMBLE_FUZZ_BUILD:-build/fuzz}
targets=(fuzz_scene_loader fuzz_query_file fuzz_obj_reader fuzz_ccd_query_file fuzz_narrow_phase
         fuzz_gjk_epa fuzz_ccd fuzz_short_scene fuzz_sdf)
if [ -n "${FUZZ_TARGETS:-}" ]; then
  read -r -a targets <<<"$FUZZ_TARGETS"
fi
budget=(-max_total_time="$seconds")
if [ -n "${FUZZ_RUNS:-}" ]; then budget=(-runs="$FUZZ_RUNS"); fi

clang=$(command -v clang++-14 || command -v clang++ || true)
if [ -z "$clang" ]; then
  echo "fuzz: no clang++ (scripts/setup-debian.sh installs clang-14 and libclang-rt-14-dev)" >&2
  exit 2
fi
# -O2 and line tables: stack traces that name file and line, and a third less time per input than
# -O1 (an SDF body's mass integration, the slowest thing a scene loads, takes 4 to 6 s under the
# sanitizers and the fuzzer's coverage, 0.1 s in the optimised build). FUZZ_OPT=-O1 compiles
# faster, for short runs, where the build is most of the time (CI fuzzes from scripts/test.sh's
# sanitizer build instead: FUZZ_CONFIGURED below). The libraries only: no apps, renderer or
# oracles.
# Eigen is left out of the coverage instrumentation (tests/fuzz/coverage_ignorelist.txt): its
# small fixed-size loops, traced comparison by comparison, took over half of the time.
# FUZZ_CONFIGURED=1 takes TUMBLE_FUZZ_BUILD as it is configured: scripts/test.sh configures one
# clang build for the sanitized test suite and the fuzzers (TUMBLE_SANITIZE and TUMBLE_FUZZ), runs
# the tests, then fuzzes from it.
opt=${FUZZ_OPT:--O2}
ignore="-fsanitize-coverage-ignorelist=$PWD/tests/fuzz/coverage_ignorelist.txt"
if [ "${FUZZ_CONFIGURED:-0}" != 1 ]; then
  cmake -S . -B "$build" -G Ninja -DCMAKE_CXX_COMPILER="$clang" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="$opt -g1 $ignore" -DTUMBLE_FUZZ=ON -DTUMBLE_BUILD_TESTS=OFF \
    -DTUMBLE_WITH_RENDER=OFF -DTUMBLE_WITH_BULLET=OFF -DTUMBLE_WITH_MUJOCO=OFF -DTUMBLE_WITH_MPI=OFF \
    -DTUMBLE_UNITY_LIBRARIES=ON >/dev/null
elif ! grep -q '^TUMBLE_FUZZ:BOOL=ON' "$build/CMakeCache.txt" 2>/dev/null; then
  echo "fuzz: FUZZ_CONFIGURED=1, but $build is not configured with TUMBLE_FUZZ=ON" >&2
  exit 2
fi
cmake --build "$build" --target tumble_fuzzers -j "$(nproc)"

work="$root/$build"
# The seed directory of one target, filled from the repository.
seed_dir() {
  local target=$1 dir="$work/seeds/$1"
  rm -rf "$dir"
  mkdir -p "$dir"
  case $target in
    fuzz_scene_loader)
      find scenes tests/data/scenes tests/data/malformed -name '*.yaml' -size -64k \
        -exec cp -t "$dir" --backup=numbered {} +
      # SDF bodies at the coarsest resolution: the same loader paths, a hundredth of the mass
      # integration (0.5 to 2.5 s a scene at 48 cells under the sanitizers, where the other
      # inputs take under a millisecond).
      sed -i -E -e 's/^( *)type: sdf$/&\n\1resolution: 8/' \
        -e 's/\{type: sdf([,}])/{type: sdf, resolution: 8\1/' "$dir"/* ;;
    fuzz_query_file)
      awk '/^queries:/ {on = 1} on && /^```/ {exit} on {print}' docs/scene-format.md \
        >"$dir/scene_format_example.yaml" ;;
    fuzz_obj_reader)
      find scenes tests/data -name '*.obj' -size -64k -exec cp -t "$dir" --backup=numbered {} + ;;
    fuzz_ccd_query_file)
      # The first two queries of each sample file (16 rows): the format, not the bulk.
      local i=0
      while IFS= read -r f; do
        head -n 16 "$f" >"$dir/query_$i.csv"
        i=$((i + 1))
      done < <(find tests/data/external/ccd-sample-queries -name '*.csv' | sort) ;;
  esac
  if [ -f "tests/fuzz/seeds/$target.hex" ]; then
    local n=0
    while IFS= read -r line; do
      [ -n "$line" ] && printf '%s' "$line" | xxd -r -p >"$dir/saved_$n"
      n=$((n + 1))
    done <"tests/fuzz/seeds/$target.hex"
  fi
  echo "$dir"
}

run_target() {
  local target=$1
  local corpus="$work/corpus/$target" findings="$work/findings/$target" log="$work/logs/$target.log"
  rm -rf "$findings"  # this run's findings only
  mkdir -p "$corpus" "$findings" "$(dirname "$log")"
  local seeds
  seeds=$(seed_dir "$target")
  local status=0
  # -timeout: one input may take 60 s (a hang is a finding; a scene of several SDF bodies takes
  # 10 or more under the sanitizers); -rss_limit_mb: memory beyond 2 GB is a finding (a limit that
  # should have refused the input before allocating).
  "$work/tests/fuzz/$target" "${budget[@]}" -timeout=60 -rss_limit_mb=2048 \
    -print_final_stats=1 -artifact_prefix="$findings/" "$corpus" "$seeds" >"$log" 2>&1 || status=$?
  local executions coverage corpus_size found
  executions=$(grep -o 'stat::number_of_executed_units: [0-9]*' "$log" | awk '{print $2}' | tail -1)
  coverage=$(grep -o 'cov: [0-9]*' "$log" | awk '{print $2}' | tail -1)
  corpus_size=$(find "$corpus" -type f | wc -l)
  # slow-unit-* files are inputs that took over 10 s, kept for a look but not findings: on a
  # loaded machine an ordinary input can take that long; a hang is a timeout-* (60 s).
  found=$(find "$findings" -type f ! -name 'slow-unit-*' | wc -l)
  if [ "$status" -ne 0 ] && [ "$found" -eq 0 ]; then found=1; fi
  printf '%-22s %12s executions  %6s edges  %6s inputs  %s findings\n' "$target" \
    "${executions:-0}" "${coverage:-0}" "$corpus_size" "$found"
  if [ "$found" -ne 0 ]; then
    grep -E 'ERROR|SUMMARY|runtime error|: .*finding|narrow phase|gjk/epa|ccd:|sdf:|short scene' \
      "$log" | head -5 | sed 's/^/    /'
    return 1
  fi
  if [ "${FUZZ_SAVE_SEEDS:-0}" = 1 ] && [ -f "tests/fuzz/seeds/$target.hex" ]; then
    local merged="$work/merged/$target"
    rm -rf "$merged" && mkdir -p "$merged"
    "$work/tests/fuzz/$target" -merge=1 "$merged" "$corpus" >/dev/null 2>&1
    for f in "$merged"/*; do xxd -p "$f" | tr -d '\n'; echo; done | sort >"tests/fuzz/seeds/$target.hex"
  fi
}

if [ -n "${FUZZ_RUNS:-}" ]; then per="$FUZZ_RUNS executions"; else per="$seconds s"; fi
echo "== fuzzing, $per per target, $(nproc) at a time =="
failed=0
pids=()
names=()
for target in "${targets[@]}"; do
  run_target "$target" >"$work/logs.$target.summary" 2>&1 &
  pids+=($!)
  names+=("$target")
  # One target per core.
  while [ "$(jobs -rp | wc -l)" -ge "$(nproc)" ]; do sleep 1; done
done
for i in "${!pids[@]}"; do
  wait "${pids[$i]}" || failed=1
  cat "$work/logs.${names[$i]}.summary"
done
if [ "$failed" -ne 0 ]; then
  echo "fuzz: findings above (build/fuzz/findings/)" >&2
  exit 1
fi
echo "fuzz: no findings"
