#!/usr/bin/env bash
# Runs the tests that step on several threads under ThreadSanitizer (clang): the step's split loops
# (dynamics/parallel_runner.hpp) on 1, 2 and 4 threads, and batches of worlds on several threads.
#
#   scripts/tsan.sh
#
# Debian's oneTBB is not instrumented, so ThreadSanitizer cannot see its hand-overs of work between
# threads; this build runs the same loops on plain std::threads instead (TUMBLE_TSAN,
# dynamics/parallel_runner_std_threads.cpp), with the same chunks. Builds the core libraries and the
# two test binaries only, and exits non-zero on any report. It builds without OpenVDB, which its
# tests do not use: the one build of the suite that compiles the core as a machine without
# libopenvdb-dev would (collision/sdf/vdb_level_set_unavailable.cpp).
set -euo pipefail
cd "$(dirname "$0")/.."
clang=$(command -v clang++-14 || command -v clang++ || true)
if [ -z "$clang" ]; then
  echo "tsan: no clang++ (scripts/setup-debian.sh installs clang-14)" >&2
  exit 2
fi
python=()
if [ -x /usr/bin/python3 ]; then python=(-DPython3_EXECUTABLE=/usr/bin/python3); fi
build=${TUMBLE_TSAN_BUILD:-build/tsan}
cmake -S . -B "$build" -G Ninja -DCMAKE_CXX_COMPILER="$clang" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" -DTUMBLE_TSAN=ON -DTUMBLE_UNITY_LIBRARIES=ON \
  -DTUMBLE_UNITY_TESTS=ON -DTUMBLE_WITH_RENDER=OFF -DTUMBLE_WITH_BULLET=OFF \
  -DTUMBLE_WITH_MUJOCO=OFF -DTUMBLE_WITH_MPI=OFF -DTUMBLE_WITH_OPENVDB=OFF \
  -DTUMBLE_BUILD_BENCHMARKS=OFF "${python[@]}" \
  >/dev/null
cmake --build "$build" --target test_physics test_api -j "$(nproc)"
export TSAN_OPTIONS="halt_on_error=1 second_deadlock_stack=1"
"$build/tests/test_physics" --gtest_filter='ThreadCount.*'
"$build/tests/test_api" --gtest_filter='BatchWorld.*:Randomization.*:StepWorkspace.*'
