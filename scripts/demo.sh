#!/usr/bin/env bash
# Installs everything, builds tumble, runs the demo scene and renders it to a video.
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/setup-debian.sh
cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build/release -j "$(nproc)" --target tumble
build/release/apps/tumble run scenes/demo.yaml -o out/demo
# 6 s of simulation at 30 frames per second, 1280x720, H.264 (about 10-20 s on two cores).
build/release/apps/tumble render scenes/demo.yaml -o out/demo/demo.mp4 --fps 30
