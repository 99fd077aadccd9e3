#!/usr/bin/env bash
# Installs every Debian package tumble needs to build, test, render and compare against Bullet.
# Idempotent; run as root (or through sudo) on Debian 12.
set -euo pipefail

packages=(
  # toolchain
  build-essential g++ cmake ninja-build pkg-config clang-format
  # the layout check (tests/layout/check_dependencies.py) and the Python module (python/)
  python3 python3-dev pybind11-dev python3-numpy python3-pytest python3-matplotlib
  # core and scene loading
  libeigen3-dev libyaml-cpp-dev libcli11-dev nlohmann-json3-dev
  # threads (dynamics/parallel_runner.hpp)
  libtbb-dev
  # convex hulls (collision/shapes/convex_hull.cpp) and OBJ meshes (scenes/)
  libqhull-dev libtinyobjloader-dev
  # tests and benchmarks
  libgtest-dev libgmock-dev libbenchmark-dev
  # optional parts: off-screen renderer, video, Bullet oracle, plots
  libosmesa6-dev libpng-dev ffmpeg libbullet-dev gnuplot-nox
  # the MuJoCo peer of the batch benchmark (apps/mujoco_bridge.cpp)
  libmujoco-dev
  # sweeps, reports and RL batches over MPI ranks (apps/mpi_work_pool.cpp, docs/scale-out.md)
  openmpi-bin libopenmpi-dev python3-mpi4py
  # OpenVDB level sets as SDF shapes (collision/sdf/vdb_level_set.hpp; optional in the build)
  libopenvdb-dev
  # fuzzing and ThreadSanitizer (scripts/fuzz.sh, tests/fuzz, scripts/tsan.sh): clang with libFuzzer and its sanitizer runtimes; xxd
  # for the seeds kept in hex
  clang-14 libclang-rt-14-dev xxd
  # the PyTorch example around tumble.distance (examples/python/torch_distance.py)
  python3-torch
)

as_root=()
if [ "$(id -u)" -ne 0 ]; then as_root=(sudo); fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} packages already installed"
  exit 0
fi
echo "setup: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
"${as_root[@]}" apt-get update
"${as_root[@]}" apt-get install -y --no-install-recommends "${missing[@]}"
