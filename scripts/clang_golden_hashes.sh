#!/usr/bin/env bash
# Builds the core libraries and the golden-hash test (tests/golden) with clang, once per
# optimisation level given (default: -O2 and -O3), and runs it: every scene must end in the same
# state hash as the g++ build recorded in tests/data/golden_hashes.json (docs/architecture.md,
# "Determinism").
#
#   scripts/clang_golden_hashes.sh [LEVEL...]      e.g. scripts/clang_golden_hashes.sh O3
set -euo pipefail
cd "$(dirname "$0")/.."
levels=("$@")
if [ ${#levels[@]} -eq 0 ]; then levels=(O2 O3); fi
clang=$(command -v clang++-14 || command -v clang++ || true)
if [ -z "$clang" ]; then
  echo "clang golden hashes: no clang++ (scripts/setup-debian.sh installs clang-14)" >&2
  exit 2
fi
python=()
if [ -x /usr/bin/python3 ]; then python=(-DPython3_EXECUTABLE=/usr/bin/python3); fi
for level in "${levels[@]}"; do
  build="build/clang-$level"
  echo "== clang -$level: core libraries and the golden-hash test =="
  cmake -S . -B "$build" -G Ninja -DCMAKE_CXX_COMPILER="$clang" -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_CXX_FLAGS_RELEASE="-$level -DNDEBUG" -DTUMBLE_UNITY_LIBRARIES=ON \
    -DTUMBLE_UNITY_TESTS=ON -DTUMBLE_WITH_RENDER=OFF -DTUMBLE_WITH_BULLET=OFF \
    -DTUMBLE_WITH_MUJOCO=OFF -DTUMBLE_WITH_MPI=OFF "${python[@]}" >/dev/null
  cmake --build "$build" --target test_golden -j "$(nproc)"
  "$build/tests/test_golden"
done
