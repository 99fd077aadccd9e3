// After its first steps, a step allocates nothing on the heap: every scratch buffer of the world
// keeps its capacity from step to step. This binary replaces the global operator new to count
// allocations, so it holds this one test alone.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>
#include <string>

#include "engine/simulation.hpp"
#include "scenes/scene_loader.hpp"

// These replacements take memory from malloc and give it back to free, which GCC cannot see
// through (it warns that free() meets memory from operator new).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif

namespace {
std::atomic<long> g_allocations{0};
}  // namespace

void* operator new(std::size_t size) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size == 0 ? 1 : size))
    return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) {
  return operator new(size);
}
void* operator new(std::size_t size, std::align_val_t alignment) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  const std::size_t a = static_cast<std::size_t>(alignment);
  if (void* p = std::aligned_alloc(a, (size + a - 1) / a * a))
    return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size, std::align_val_t alignment) {
  return operator new(size, alignment);
}
// The nothrow forms too (std::stable_partition's buffer uses them): every new here must pair
// with the delete below, or ASan reports a mismatch between its allocator and free().
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  return std::malloc(size == 0 ? 1 : size);
}
void* operator new[](std::size_t size, const std::nothrow_t& tag) noexcept {
  return operator new(size, tag);
}
void* operator new(std::size_t size, std::align_val_t alignment, const std::nothrow_t&) noexcept {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  const std::size_t a = static_cast<std::size_t>(alignment);
  return std::aligned_alloc(a, (size + a - 1) / a * a);
}
void* operator new[](std::size_t size, std::align_val_t alignment,
                     const std::nothrow_t& tag) noexcept {
  return operator new(size, alignment, tag);
}
void operator delete(void* p, const std::nothrow_t&) noexcept {
  std::free(p);
}
void operator delete[](void* p, const std::nothrow_t&) noexcept {
  std::free(p);
}
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept {
  std::free(p);
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete[](void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete(void* p, std::align_val_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::align_val_t) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t, std::align_val_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept {
  std::free(p);
}

namespace tumble::test {
namespace {

// Steps `warm_up` steps, then counts the allocations of `measured` more.
long allocations_after_warm_up(const std::string& scene_file, int warm_up, int measured) {
  auto scene = std::make_shared<const Scene>(
      load_scene_file(std::string(TUMBLE_SOURCE_DIR) + "/scenes/" + scene_file));
  Simulation world(scene);
  for (int k = 0; k < warm_up; ++k)
    world.step();
  const long before = g_allocations.load();
  for (int k = 0; k < measured; ++k)
    world.step();
  return g_allocations.load() - before;
}

TEST(StepAllocation, AfterTheFirstStepsAStepAllocatesNothing) {
  // The counter sees allocations: a vector that grows is counted.
  {
    const long before = g_allocations.load();
    std::vector<int> grows;
    grows.push_back(1);
    ASSERT_GT(g_allocations.load(), before);
  }
  // Resting and settling scenes of every kind: boxes in a tall pyramid (the box batch, colours,
  // substeps per island), mixed shapes (every pair path), a box on a mesh, a heavy body on a
  // light one (the most substeps), and a scene with sleeping. Each is measured once it has
  // settled (the demo runs at 240 Hz: 1200 steps are 5 s), since a pile still falling together
  // meets more pairs than ever before, and the buffers grow to hold them.
  struct Case {
    const char* scene;
    int warm_up;
    int measured;
  };
  for (const Case& c :
       {Case{"bench/pyramid_20.yaml", 120, 120}, Case{"demo.yaml", 1200, 240},
        Case{"mesh_slide.yaml", 60, 60}, Case{"stability/defaults_heavy_on_light.yaml", 60, 60},
        Case{"stability/sleeping_drop.yaml", 120, 120}, Case{"shapes_drop.yaml", 240, 120}}) {
    EXPECT_EQ(allocations_after_warm_up(c.scene, c.warm_up, c.measured), 0) << c.scene;
  }
}

}  // namespace
}  // namespace tumble::test
