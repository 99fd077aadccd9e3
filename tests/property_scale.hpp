// TUMBLE_PROPERTY_SCALE (default 1) scales the number of random cases, steps or simulated seconds
// of the property tests. The sanitizer pass of .ci/run sets it to 0.25: there the point is memory
// and undefined-behaviour errors on every code path, which a shorter run still reaches, not more
// random cases. Values outside (0, 1] are ignored.
#pragma once

#include <algorithm>
#include <cstdlib>

namespace tumble {

inline double property_scale() {
  const char* text = std::getenv("TUMBLE_PROPERTY_SCALE");
  if (text == nullptr)
    return 1.0;
  const double scale = std::strtod(text, nullptr);
  return scale > 0 && scale <= 1 ? scale : 1.0;
}

// `count` scaled, at least 1.
inline int scaled(int count) {
  return std::max(1, static_cast<int>(count * property_scale()));
}

}  // namespace tumble
