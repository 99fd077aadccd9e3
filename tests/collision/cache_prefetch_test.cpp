// CachePrefetch (collision/cache_prefetch.hpp): the lines it records for a batch's next world, and
// the slices issue() takes of them, checked against a line-by-line count of the same requests.
#include "collision/cache_prefetch.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <random>
#include <vector>

namespace tumble {
namespace {

constexpr std::size_t kLine = CachePrefetch::kLineBytes;

// The lines bytes [begin, begin + bytes) touch, counted one byte-address line at a time.
std::size_t lines_touched(std::uintptr_t begin, std::size_t bytes) {
  if (bytes == 0)
    return 0;
  return (begin + bytes - 1) / kLine - begin / kLine + 1;
}

TEST(CachePrefetch, RecordsEveryLineAnArrayTouchesAndIssuesThemInSlices) {
  // Arrays that begin mid-line and end mid-line: the first and last lines count.
  std::vector<unsigned char> storage(4096 + 3 * kLine);
  const auto base = reinterpret_cast<std::uintptr_t>(storage.data());
  const std::size_t offset = kLine - base % kLine + 17;  // 17 bytes into a line
  CachePrefetch requests;
  requests.record(storage.data() + offset, 100);       // 17..116: two lines
  requests.record(storage.data() + offset + 200, 64);  // 217..280: two lines
  requests.record(storage.data() + offset + 1000, 1);  // one line
  requests.record(storage.data() + offset + 2000, 0);  // none
  const std::uintptr_t start = base + offset;
  const std::size_t expected =
      lines_touched(start, 100) + lines_touched(start + 200, 64) + lines_touched(start + 1000, 1);
  ASSERT_EQ(expected, 5u);
  EXPECT_EQ(requests.pending_lines(), expected);
  requests.issue(3);  // ends inside the second array
  EXPECT_EQ(requests.pending_lines(), expected - 3);
  requests.issue(0);
  EXPECT_EQ(requests.pending_lines(), expected - 3);
  requests.issue_all();
  EXPECT_EQ(requests.pending_lines(), 0u);
  requests.issue(10);  // nothing left: no effect
  EXPECT_EQ(requests.pending_lines(), 0u);
  requests.clear();
  EXPECT_EQ(requests.pending_lines(), 0u);
  requests.record(storage.data() + offset, 100);
  EXPECT_EQ(requests.pending_lines(), 2u);
}

TEST(CachePrefetch, StopsAtItsBudgetAndRangeCount) {
  // One array that begins on a line: exactly the budget's lines.
  std::vector<unsigned char> big(3 * CachePrefetch::kBytesPerWorld + kLine);
  const auto base = reinterpret_cast<std::uintptr_t>(big.data());
  unsigned char* aligned = big.data() + (kLine - base % kLine) % kLine;
  CachePrefetch requests;
  requests.record(aligned, 2 * CachePrefetch::kBytesPerWorld);
  const std::size_t budget_lines = CachePrefetch::kBytesPerWorld / kLine;
  EXPECT_EQ(requests.pending_lines(), budget_lines);
  requests.record(aligned, kLine);  // the budget is spent
  EXPECT_EQ(requests.pending_lines(), budget_lines);

  CachePrefetch many;
  std::vector<unsigned char> small(kLine * (CachePrefetch::kMaxRanges + 9));
  unsigned char* first =
      small.data() + (kLine - reinterpret_cast<std::uintptr_t>(small.data()) % kLine) % kLine;
  for (int k = 0; k < CachePrefetch::kMaxRanges + 8; ++k)
    many.record(first + kLine * std::size_t(k), 1);
  // One line each, up to the range count: the arrays past it are not recorded.
  EXPECT_EQ(many.pending_lines(), std::size_t(CachePrefetch::kMaxRanges));
}

TEST(CachePrefetch, RandomRequestsMatchALineByLineCount) {
  std::mt19937_64 random(20261203);
  std::vector<unsigned char> storage(1 << 20);
  const auto base = reinterpret_cast<std::uintptr_t>(storage.data());
  for (int trial = 0; trial < 2000; ++trial) {
    CachePrefetch requests;
    std::size_t expected = 0;
    std::size_t budget = CachePrefetch::kBytesPerWorld;
    const int arrays = std::uniform_int_distribution<int>(0, CachePrefetch::kMaxRanges)(random);
    for (int a = 0; a < arrays; ++a) {
      const std::size_t begin = std::uniform_int_distribution<std::size_t>(0, 500000)(random);
      const std::size_t bytes = std::uniform_int_distribution<std::size_t>(0, 20000)(random);
      requests.record(storage.data() + begin, bytes);
      if (bytes == 0 || budget == 0)
        continue;
      const std::uintptr_t first = (base + begin) / kLine * kLine;
      const std::size_t span = std::min(base + begin + bytes - first, budget);
      budget -= span;
      expected += lines_touched(first, span);
    }
    ASSERT_EQ(requests.pending_lines(), expected) << "trial " << trial;
    // Independently of the budget's arithmetic: no more than the budget's lines and one partial
    // line per array.
    ASSERT_LE(expected, CachePrefetch::kBytesPerWorld / kLine + std::size_t(arrays))
        << "trial " << trial;
    std::size_t left = expected;
    while (left > 0) {
      const std::size_t slice = std::uniform_int_distribution<std::size_t>(0, 100)(random);
      requests.issue(slice);
      left -= std::min(slice, left);
      ASSERT_EQ(requests.pending_lines(), left) << "trial " << trial;
    }
  }
}

}  // namespace
}  // namespace tumble
