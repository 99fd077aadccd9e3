// Sphere-sphere over many pairs (see sphere_batch.hpp), in the data-oriented style: test
// everything in a tight loop, then work only on what passed.
// pairs go in blocks of 64; one straight-line loop computes every contact of a block (the
// ordering rule and the zero-length fallback as selects, not branches, so the compiler
// vectorises the gathers, square roots and divisions), a second writes out those within the
// margin without a branch. (A square-root-free prefilter pass was tried first: it costs more
// than it saves when most broad-phase pairs touch.)
// The contact itself is Ericson, Real-Time Collision Detection (2005) 4.3.1.
#include "collision/narrow_phase/sphere_batch.hpp"

#include <algorithm>
#include <array>
#include <limits>
#include <stdexcept>

namespace tumble {
namespace {

constexpr std::size_t kBlock = 64;

// One block of pairs' results, for the compact form.
struct Block {
  std::array<Real, kBlock> px, py, pz, nx, ny, nz, depth;
};

// sphere_pairs.cpp's sphere_sphere (what collide() runs for two spheres) for each of `count`
// pairs, operation for operation, so the results match it bit for bit; written without branches
// so that it vectorises, centres and radii fetched by gathers. Compiled for AVX-512, AVX2 and the
// baseline, picked at load time by the CPU (GCC function multi-versioning): wider lanes, the
// same IEEE operations in the same order, so the same bits on every machine. Counts the pairs
// within the margin, and returns the number whose centres coincide (or are NaN/inf apart):
// their normal is set by fix_degenerate.
struct KernelCounts {
  std::int64_t touching = 0;
  std::int64_t degenerate = 0;
};

__attribute__((target_clones("avx512f", "avx2", "default"))) KernelCounts contacts_of_pairs(
    const Real* __restrict x, const Real* __restrict y, const Real* __restrict z,
    const Real* __restrict r, const SpherePair* __restrict pairs, std::size_t count,
    Real* __restrict out_depth, Real* __restrict out_nx, Real* __restrict out_ny,
    Real* __restrict out_nz, Real* __restrict out_px, Real* __restrict out_py,
    Real* __restrict out_pz, Real margin) {
  std::int64_t degenerate = 0;
  std::int64_t touching = 0;
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
    // its quotient is thrown away).
    const Real inv = Real(1) / length;
    const Real qx = dx * inv, qy = dy * inv, qz = dz * inv;
    const Real nx = has_direction ? qx : Real(0);
    const Real ny = has_direction ? qy : Real(0);
    const Real nz = has_direction ? qz : Real(1);
    degenerate += has_direction ? 0 : 1;
    const Real depth = ar + br - length;
    const Real shift = (br - ar) * Real(0.5);
    out_px[j] = (ax + bx) * Real(0.5) + nx * shift;
    out_py[j] = (ay + by) * Real(0.5) + ny * shift;
    out_pz[j] = (az + bz) * Real(0.5) + nz * shift;
    out_nx[j] = nx;
    out_ny[j] = ny;
    out_nz[j] = nz;
    out_depth[j] = depth;
    touching += depth >= -margin ? 1 : 0;  // NaN fails, as in collide()
  }
  return {touching, degenerate};
}

// Coincident centres (or a NaN/inf offset): the smaller sphere (of equal ones the
// lexicographically lower centre) is pushed up the z axis, down otherwise. Rare, so scalar.
void fix_degenerate(const SphereArrays& s, const SpherePair* pairs, std::size_t count, Real* nz,
                    Real* pz) {
  constexpr Real kLargest = std::numeric_limits<Real>::max();
  const Real* x = s.x;
  const Real* y = s.y;
  const Real* z = s.z;
  const Real* r = s.radius;
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
    nz[j] = goes_up ? Real(1) : Real(-1);
    pz[j] = (z[ia] + z[ib]) * Real(0.5) + nz[j] * ((r[ib] - r[ia]) * Real(0.5));
  }
}

}  // namespace

std::size_t collide_sphere_pairs_dense(const SphereArrays& spheres,
                                       std::span<const SpherePair> pairs, Real margin,
                                       const SphereContactArrays& out) {
  const std::size_t n = pairs.size();
  const KernelCounts counts =
      contacts_of_pairs(spheres.x, spheres.y, spheres.z, spheres.radius, pairs.data(), n, out.depth,
                        out.normal_x, out.normal_y, out.normal_z, out.x, out.y, out.z, margin);
  if (counts.degenerate > 0)
    fix_degenerate(spheres, pairs.data(), n, out.normal_z, out.z);
  return static_cast<std::size_t>(counts.touching);
}

std::size_t collide_sphere_pairs(const SphereArrays& spheres, std::span<const SpherePair> pairs,
                                 Real margin, std::span<SphereContact> out) {
  if (out.size() < pairs.size())
    throw std::invalid_argument("collide_sphere_pairs: `out` needs one entry per pair");
  Block block;
  std::size_t written = 0;
  for (std::size_t start = 0; start < pairs.size(); start += kBlock) {
    const std::size_t count = std::min(kBlock, pairs.size() - start);
    const SpherePair* block_pairs = pairs.data() + start;
    if (contacts_of_pairs(spheres.x, spheres.y, spheres.z, spheres.radius, block_pairs, count,
                          block.depth.data(), block.nx.data(), block.ny.data(), block.nz.data(),
                          block.px.data(), block.py.data(), block.pz.data(), margin)
            .degenerate > 0)
      fix_degenerate(spheres, block_pairs, count, block.nz.data(), block.pz.data());
    // Write every pair to the next free slot and advance only past those within the margin: no
    // branch to mispredict (out has room for all pairs). NaN fails, as in collide().
    for (std::size_t j = 0; j < count; ++j) {
      SphereContact& c = out[written];
      c.pair = static_cast<std::int32_t>(start + j);
      c.depth = block.depth[j];
      c.normal = Vec3(block.nx[j], block.ny[j], block.nz[j]);
      c.position = Vec3(block.px[j], block.py[j], block.pz[j]);
      written += block.depth[j] >= -margin ? 1 : 0;
    }
  }
  return written;
}

}  // namespace tumble
