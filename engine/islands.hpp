// Islands: the bodies connected through touching contacts, static bodies excluded (a floor
// does not join everything resting on it into one island). Union-find with path halving and
// union by index (the smaller index becomes the root), so the islands, their roots and their
// order depend only on the pairs given, never on memory layout: deterministic.
// Reference: Tarjan, "Efficiency of a Good But Not Linear Set Union Algorithm", JACM 1975.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace tumble {

class Islands {
 public:
  // Starts with every body alone. Keeps capacity: no allocation once `body_count` settles.
  void reset(std::size_t body_count);
  void join(std::int32_t a, std::int32_t b);
  // The island's root body: the smallest index in it.
  std::int32_t root(std::int32_t body);
  // Heap bytes held (capacity).
  std::size_t bytes_reserved() const { return parent_.capacity() * sizeof(std::int32_t); }

 private:
  std::vector<std::int32_t> parent_;
};

}  // namespace tumble
