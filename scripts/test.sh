#!/usr/bin/env bash
# Installs everything, builds tumble twice (optimised, and with AddressSanitizer +
# UndefinedBehaviorSanitizer) and runs the whole test suite under each, then checks the golden
# state hashes from a clang build (scripts/clang_golden_hashes.sh) and builds the fuzz targets
# with clang and runs each briefly (scripts/fuzz.sh). `.ci/run` calls this.
set -euo pipefail
cd "$(dirname "$0")/.."

# Each part's wall time, printed at the end (CI runs this on 2 cores and should stay under 35
# minutes).
parts=()
part_start=$SECONDS
finish_part() {
  parts+=("$(printf '%5d s  %s' $((SECONDS - part_start)) "$1")")
  part_start=$SECONDS
}
print_parts() {
  echo "== time per part =="
  printf '%s\n' "${parts[@]}"
  echo "$(printf '%5d s  total' "$SECONDS")"
}
trap print_parts EXIT

bash scripts/setup-debian.sh
finish_part "setup"
jobs=$(nproc)
# The Debian interpreter, whose numpy and pytest the setup installed (a python3 earlier on PATH,
# such as pyenv's, may have neither).
python=()
if [ -x /usr/bin/python3 ]; then python=(-DPython3_EXECUTABLE=/usr/bin/python3); fi

# Test binaries compile in batches of files (TUMBLE_UNITY_TESTS, tests/CMakeLists.txt): about
# half the compile time of one file at a time, most of it in the instrumented build. The
# libraries and apps too (TUMBLE_UNITY_LIBRARIES): 248 s against 339 s for the instrumented
# libraries on 2 cores; the optimised build passes every test, golden hashes included, either way.
echo "== release build and tests =="
cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release -DTUMBLE_UNITY_TESTS=ON \
  -DTUMBLE_UNITY_LIBRARIES=ON "${python[@]}"
cmake --build build/release -j "$jobs"
finish_part "release build"
ctest --test-dir build/release --output-on-failure -j "$jobs"
finish_part "release tests (C++ and Python)"

echo "== sanitizer build (address, undefined) and tests =="
# -O1 with line tables only: the instrumented build is the longest part of the run, and at -O2
# with full debug information it took twice as long to compile (104 s against 54 s for the
# largest test file) for the same checks; stack traces still name file and line.
# Without OpenVDB: the whole suite then runs as on a machine that lacks it (its grids from
# tumble's own dense builder, its level sets refused with the reason, its own tests skipped),
# while the optimised build above runs it with OpenVDB, and the fuzzers load OpenVDB's level sets
# under the sanitizers.
cmake -S . -B build/sanitize -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" -DTUMBLE_SANITIZE=ON -DTUMBLE_WITH_OPENVDB=OFF \
  -DTUMBLE_BUILD_BENCHMARKS=OFF -DTUMBLE_UNITY_TESTS=ON -DTUMBLE_UNITY_LIBRARIES=ON "${python[@]}"
cmake --build build/sanitize -j "$jobs"
finish_part "sanitizer build"
# The broad-phase property tests run a quarter of their random steps here (see
# tests/broad_phase/broad_phase_property.hpp): every path is still exercised under the sanitizers.
TUMBLE_PROPERTY_SCALE=0.25 \
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir build/sanitize --output-on-failure -j "$jobs"
finish_part "sanitizer tests"

# The golden state hashes from clang (the core libraries and that test alone, at -O3; -O2 agrees
# too, docs/architecture.md, "Determinism").
bash scripts/clang_golden_hashes.sh O3
finish_part "clang build and golden hashes"

echo "== ThreadSanitizer build (clang) and the threaded tests =="
bash scripts/tsan.sh
finish_part "ThreadSanitizer build and threaded tests"

# Every libFuzzer target of tests/fuzz, briefly, from their seeds (the repository's scenes, meshes
# and queries, and the corpora of longer runs in tests/fuzz/seeds); a finding fails the run.
# docs/reliability.md has the longer runs. Built at -O1: the build was two thirds of this part at
# -O2 (267 of 389 s), and -O1 compiles in 29% less time. 10 s a target: libFuzzer replays every
# seed before it looks at the clock, so the slowest targets (the scene loader, the narrow phase)
# still run all of theirs.
echo "== fuzzing (clang, libFuzzer with address and undefined sanitizers) =="
FUZZ_OPT=-O1 bash scripts/fuzz.sh 10
finish_part "fuzz build and run"
