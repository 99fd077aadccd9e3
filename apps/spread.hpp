// The min, median, max and mean of a list of timings: what every benchmark table reports, since
// the machines are shared and one number would hide their noise.
#pragma once

#include <algorithm>
#include <vector>

namespace tumble::app {

struct Spread {
  double min = 0, median = 0, max = 0, mean = 0;
};

inline Spread spread_of(std::vector<double> v) {
  Spread s;
  if (v.empty())
    return s;
  std::sort(v.begin(), v.end());
  s.min = v.front();
  s.max = v.back();
  const std::size_t n = v.size();
  s.median = n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
  double total = 0;
  for (const double x : v)
    total += x;
  s.mean = total / static_cast<double>(n);
  return s;
}

// The value below which a fraction q of the samples lie (nearest rank).
inline double quantile(std::vector<double> v, double q) {
  if (v.empty())
    return 0;
  std::sort(v.begin(), v.end());
  const auto rank = static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5);
  return v[std::min(rank, v.size() - 1)];
}

}  // namespace tumble::app
