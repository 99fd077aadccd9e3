// Contacts CSV (`tumble run --contacts`): one row per contact point per recorded step, with the
// two bodies by name, the point, the normal (from B to A), the depth and the impulses the solver
// applied in that step (docs/api.md, "Contact reports"). Written atomically on finish().
#pragma once

#include <filesystem>

#include "apps/atomic_file.hpp"
#include "tumble/world.hpp"

namespace tumble::app {

inline constexpr const char* kContactsHeader =
    "time,body_a,body_b,px,py,pz,nx,ny,nz,depth,normal_impulse,fx,fy,fz";

class ContactsWriter {
 public:
  explicit ContactsWriter(const std::filesystem::path& path);
  void record(const World& world);
  void finish() { file_.commit(); }

 private:
  AtomicFile file_;
};

}  // namespace tumble::app
