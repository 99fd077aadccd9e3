#!/usr/bin/env bash
# Installs everything, builds tumble twice (optimised with GCC, and with clang's AddressSanitizer +
# UndefinedBehaviorSanitizer and the fuzzers' coverage) and runs the whole test suite under each,
# then checks the golden state hashes from a clang build (scripts/clang_golden_hashes.sh), runs the
# threaded tests under ThreadSanitizer and runs each fuzz target briefly from the sanitizer build
# (scripts/fuzz.sh). `.ci/run` calls this.
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

echo "== sanitizer build (clang: address, undefined, and the fuzzers' coverage) and tests =="
# One clang build serves the sanitized test suite and the fuzzers below (TUMBLE_SANITIZE and
# TUMBLE_FUZZ): the fuzzers' libraries are the tests', so the libraries compile once for both,
# about 300 s less than a GCC build for the tests and a clang build for the fuzzers
# (docs/reliability.md, "CI time"); TUMBLE_FUZZ's sanitizers include TUMBLE_SANITIZE's, which
# clang takes twice without harm. -O1 with line tables only: stack traces still name file and
# line. Eigen is left out of the coverage instrumentation (tests/fuzz/coverage_ignorelist.txt).
# Without OpenVDB: the whole suite then runs as on a machine that lacks it (its grids from
# tumble's own dense builder, its level sets refused with the reason, its own tests skipped),
# while the optimised build above runs it with OpenVDB; the long fuzz runs (scripts/fuzz.sh
# alone) load OpenVDB's level sets.
clang=$(command -v clang++-14 || command -v clang++)
cmake -S . -B build/check -G Ninja -DCMAKE_CXX_COMPILER="$clang" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -fsanitize-coverage-ignorelist=$PWD/tests/fuzz/coverage_ignorelist.txt" \
  -DTUMBLE_SANITIZE=ON -DTUMBLE_FUZZ=ON -DTUMBLE_WITH_OPENVDB=OFF -DTUMBLE_BUILD_BENCHMARKS=OFF \
  -DTUMBLE_UNITY_TESTS=ON -DTUMBLE_UNITY_LIBRARIES=ON "${python[@]}"
cmake --build build/check -j "$jobs"
finish_part "sanitizer build (with the fuzzers)"
# The broad-phase property tests run a quarter of their random steps here (see
# tests/broad_phase/broad_phase_property.hpp): every path is still exercised under the sanitizers.
# OSMesa keeps allocations for the life of the process, which LeakSanitizer reports at exit under
# clang's runtime: tests/sanitizers/lsan_suppressions.txt names that library alone.
TUMBLE_PROPERTY_SCALE=0.25 \
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
LSAN_OPTIONS=suppressions=$PWD/tests/sanitizers/lsan_suppressions.txt:print_suppressions=0 \
  ctest --test-dir build/check --output-on-failure -j "$jobs"
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
# docs/reliability.md has the longer runs. From the sanitizer build above, which built them. 10 s
# a target: libFuzzer replays every seed before it looks at the clock, so the slowest targets
# (the scene loader, the narrow phase) still run all of theirs.
echo "== fuzzing (clang, libFuzzer with address and undefined sanitizers) =="
FUZZ_CONFIGURED=1 TUMBLE_FUZZ_BUILD=build/check bash scripts/fuzz.sh 10
finish_part "fuzz run"
