#!/usr/bin/env bash
# Installs tumble from a build tree into a fresh prefix and builds examples/ against it twice, as a
# user would: with CMake (find_package(tumble)) and with pkg-config. Runs each program and checks
# what it prints.   Usage: install_test.sh <build dir> <source dir>
set -euo pipefail
build=$1
source=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
prefix=$work/prefix

cmake --install "$build" --prefix "$prefix" >/dev/null
for f in include/tumble/tumble.hpp lib/libtumble.so lib/cmake/tumble/tumbleConfig.cmake \
  lib/pkgconfig/tumble.pc bin/tumble; do
  [[ -e $prefix/$f ]] || { echo "not installed: $f"; exit 1; }
done
# No internal header is installed: a program sees the public API only.
if find "$prefix/include" -name '*.hpp' | grep -v '/include/tumble/'; then
  echo "internal headers were installed"; exit 1
fi

# CMake, out of tree.
cmake -S "$source/examples" -B "$work/cmake-build" -DCMAKE_PREFIX_PATH="$prefix" \
  -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$work/cmake-build" -j2 >/dev/null
"$work/cmake-build/first_program" | tee "$work/cmake.out"
grep -Eq 'box at z = 1\.0[0-9]* m after 2\.00 s, 1 contact' "$work/cmake.out"
"$work/cmake-build/kinematic_paddle" | grep -q '3 of 3 boxes in the goal'
"$work/cmake-build/ball_in_field_bowl" >/dev/null

# pkg-config, with the compiler alone.
export PKG_CONFIG_PATH=$prefix/lib/pkgconfig
# shellcheck disable=SC2046
g++ -std=c++20 -O1 "$source/examples/first_program.cpp" -o "$work/first_program_pc" \
  $(pkg-config --cflags --libs tumble)
LD_LIBRARY_PATH=$prefix/lib "$work/first_program_pc" | tee "$work/pc.out"
cmp "$work/cmake.out" "$work/pc.out"
# The installed CLI runs a scene.
"$prefix/bin/tumble" validate "$source/scenes/demo.yaml" >/dev/null
# With OpenVDB, its module is installed, and the installed CLI, started from PATH in another
# folder, loads the installed module (the dynamic loader's log names the file it opened), not the
# build tree's.
if [[ -e $build/lib/tumble/libtumble_openvdb.so ]]; then
  [[ -e $prefix/lib/tumble/libtumble_openvdb.so ]] ||
    { echo "not installed: lib/tumble/libtumble_openvdb.so"; exit 1; }
  (cd "$work" && PATH=$prefix/bin:$PATH LD_DEBUG=files tumble validate \
    "$source/scenes/sdf/things_in_level_set_bowls.yaml" >"$work/vdb.out" 2>&1) ||
    { cat "$work/vdb.out"; exit 1; }
  grep -q "file=$prefix/bin/../lib/tumble/libtumble_openvdb.so \[0\]; *dynamically loaded" \
    "$work/vdb.out" || grep -q "file=$prefix/lib/tumble/libtumble_openvdb.so \[0\]; *dynamically loaded" \
    "$work/vdb.out" || { grep libtumble_openvdb "$work/vdb.out"; echo "the installed module was not loaded"; exit 1; }
fi
# The installed Python package (when the build made one) imports from the prefix alone, with its
# compiled module and its environments, and steps a batch.
if [[ -d $build/python/tumble ]]; then
  site=$(find "$prefix" -type d -path '*/site-packages' | head -n1)
  [[ -n $site && -f $site/tumble/__init__.py && -f $site/tumble/envs.py ]] ||
    { echo "the Python package was not installed"; exit 1; }
  (cd "$work" && PYTHONPATH=$site "${PYTHON:-python3}" -c '
import tumble, tumble.envs
assert tumble.__file__.startswith("'"$site"'"), tumble.__file__
env = tumble.envs.PushBoxEnv(num_envs=2, threads=1)
obs, _ = env.reset(seed=0)
obs, *_ = env.step(env.action_space.sample())
print("python package from the prefix:", obs.shape)
')
fi
echo "install test passed"
