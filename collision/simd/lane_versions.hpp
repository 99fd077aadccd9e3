// Picking among the versions of a lanes file (collision/simd/lane_versions.inc) at run time: the
// widest this CPU runs. Each user keeps its versions' functions in a table of its own type.
#pragma once

namespace tumble::simd {

// The tables this CPU can run, widest first (AVX-512, AVX2, the SSE2 baseline), at most
// `capacity` of them; the count written.
template <class Table>
int available_versions(const Table& lanes8, const Table& lanes4, const Table& lanes2,
                       const Table** out, int capacity) {
  __builtin_cpu_init();
  int n = 0;
  if (n < capacity && __builtin_cpu_supports("avx512f"))
    out[n++] = &lanes8;
  if (n < capacity && __builtin_cpu_supports("avx2"))
    out[n++] = &lanes4;
  if (n < capacity)
    out[n++] = &lanes2;
  return n;
}

// The widest table this CPU runs.
template <class Table>
const Table& widest_version(const Table& lanes8, const Table& lanes4, const Table& lanes2) {
  const Table* best[1] = {nullptr};
  available_versions(lanes8, lanes4, lanes2, best, 1);
  return *best[0];
}

}  // namespace tumble::simd
