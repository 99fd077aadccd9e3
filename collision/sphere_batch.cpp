// Sphere-sphere over many pairs (see sphere_batch.hpp), in the data-oriented style: test
// everything in a tight loop, then work only on what passed.
// pairs go in blocks of 64; one straight-line loop computes every contact of a block (the
// ordering rule and the zero-length fallback as selects, not branches, so the compiler
// vectorises the gathers, square roots and divisions), a second writes out those within the
// margin without a branch. (A square-root-free prefilter pass was tried first: it costs more
// than it saves when most broad-phase pairs touch.)
// The contact itself is Ericson, Real-Time Collision Detection (2005) 4.3.1.
#include "collision/sphere_batch.hpp"

#include <algorithm>
#include <array>
#include <limits>
#include <stdexcept>

namespace tumble {
namespace {

constexpr std::size_t kBlock = 64;

// One block of pairs' results: contact position, normal (from B to A), depth, and whether the
// pair is within the margin (as a Real, so the loop that fills it has one lane width).
struct Block {
  std::array<Real, kBlock> px, py, pz, nx, ny, nz, depth, keep;
};

// sphere_pairs.cpp's sphere_sphere (what collide() runs for two spheres) for each pair of the
// block, operation for operation, so the results match it bit for bit; written without branches
// so that it vectorises, centres and radii fetched by gathers. Compiled for AVX-512, AVX2 and the
// baseline, picked at load time by the CPU (GCC function multi-versioning): wider lanes, the
// same IEEE operations in the same order, so the same bits on every machine.
__attribute__((target_clones("avx512f", "avx2", "default"))) void contacts_of_block(
    const Real* __restrict x, const Real* __restrict y, const Real* __restrict z,
    const Real* __restrict r, const SpherePair* __restrict pairs, std::size_t count, Real margin,
    Block& __restrict k) {
  int degenerate = 0;
  constexpr Real kLargest = std::numeric_limits<Real>::max();
  for (std::size_t j = 0; j < count; ++j) {
    const std::int32_t ia = pairs[j].a;
    const std::int32_t ib = pairs[j].b;
    const Real ax = x[ia], ay = y[ia], az = z[ia], ar = r[ia];
    const Real bx = x[ib], by = y[ib], bz = z[ib], br = r[ib];
    const Real dx = ax - bx, dy = ay - by, dz = az - bz;
    const Real length = std::sqrt(dx * dx + dy * dy + dz * dz);
    const bool has_direction = (length > 0) & (length <= kLargest);
    // Divide in every lane, select after (a lane without direction divides by 0 or inf, and
    // its quotient is thrown away). Such a lane gets its normal from the rare fix-up below.
    const Real qx = dx / length, qy = dy / length, qz = dz / length;
    const Real nx = has_direction ? qx : Real(0);
    const Real ny = has_direction ? qy : Real(0);
    const Real nz = has_direction ? qz : Real(1);
    degenerate += has_direction ? 0 : 1;
    const Real depth = ar + br - length;
    k.px[j] = ((ax - nx * ar) + (bx + nx * br)) * Real(0.5);
    k.py[j] = ((ay - ny * ar) + (by + ny * br)) * Real(0.5);
    k.pz[j] = ((az - nz * ar) + (bz + nz * br)) * Real(0.5);
    k.nx[j] = nx;
    k.ny[j] = ny;
    k.nz[j] = nz;
    k.depth[j] = depth;
    // NaN fails the comparison: no contact, as in collide().
    k.keep[j] = depth >= -margin ? Real(1) : Real(0);
  }
  if (degenerate == 0)
    return;
  // Coincident centres (or a NaN/inf offset): the smaller sphere (of equal ones the
  // lexicographically lower centre) is pushed up the z axis, down otherwise.
  for (std::size_t j = 0; j < count; ++j) {
    const std::int32_t ia = pairs[j].a;
    const std::int32_t ib = pairs[j].b;
    const Real dx = x[ia] - x[ib], dy = y[ia] - y[ib], dz = z[ia] - z[ib];
    const Real length = std::sqrt(dx * dx + dy * dy + dz * dz);
    if (length > 0 && length <= kLargest)
      continue;
    const bool lower =
        x[ia] < x[ib] || (x[ia] == x[ib] && (y[ia] < y[ib] || (y[ia] == y[ib] && z[ia] <= z[ib])));
    const bool goes_up = r[ia] != r[ib] ? r[ia] < r[ib] : lower;
    const Real nz = goes_up ? Real(1) : Real(-1);
    k.nz[j] = nz;
    k.pz[j] = ((z[ia] - nz * r[ia]) + (z[ib] + nz * r[ib])) * Real(0.5);
  }
}

}  // namespace

std::size_t collide_sphere_pairs(const SphereArrays& spheres, std::span<const SpherePair> pairs,
                                 Real margin, std::span<SphereContact> out) {
  if (out.size() < pairs.size())
    throw std::invalid_argument("collide_sphere_pairs: `out` needs one entry per pair");
  Block block;
  std::size_t written = 0;
  for (std::size_t start = 0; start < pairs.size(); start += kBlock) {
    const std::size_t count = std::min(kBlock, pairs.size() - start);
    contacts_of_block(spheres.x, spheres.y, spheres.z, spheres.radius, pairs.data() + start, count,
                      margin, block);
    // Write every pair to the next free slot and advance only past those within the margin: no
    // branch to mispredict (out has room for all pairs).
    for (std::size_t j = 0; j < count; ++j) {
      SphereContact& c = out[written];
      c.pair = static_cast<std::int32_t>(start + j);
      c.depth = block.depth[j];
      c.normal = Vec3(block.nx[j], block.ny[j], block.nz[j]);
      c.position = Vec3(block.px[j], block.py[j], block.pz[j]);
      written += block.keep[j] != 0 ? 1 : 0;
    }
  }
  return written;
}

}  // namespace tumble
