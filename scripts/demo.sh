#!/usr/bin/env bash
# Installs everything, builds tumble and runs the demo scene.
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/setup-debian.sh
cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build/release -j "$(nproc)" --target tumble
build/release/apps/tumble run scenes/demo.yaml -o out/demo
