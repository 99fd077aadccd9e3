#include "engine/islands.hpp"

#include <numeric>
#include <utility>

namespace tumble {

void Islands::reset(std::size_t body_count) {
  parent_.resize(body_count);
  std::iota(parent_.begin(), parent_.end(), 0);
}

std::int32_t Islands::root(std::int32_t body) {
  while (parent_[body] != body) {
    parent_[body] = parent_[parent_[body]];  // path halving
    body = parent_[body];
  }
  return body;
}

void Islands::join(std::int32_t a, std::int32_t b) {
  std::int32_t ra = root(a);
  std::int32_t rb = root(b);
  if (ra == rb)
    return;
  if (rb < ra)
    std::swap(ra, rb);
  parent_[rb] = ra;
}

}  // namespace tumble
