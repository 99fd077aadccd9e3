#include "apps/trajectory_writer.hpp"

#include <cerrno>

#include "apps/csv_field.hpp"
#include "apps/number_format.hpp"

namespace tumble::app {

std::vector<int> trajectory_bodies(const Scene& scene, bool with_static) {
  std::vector<int> bodies;
  for (std::size_t i = 0; i < scene.bodies.size(); ++i)
    if (with_static || !scene.bodies[i].is_static)
      bodies.push_back(static_cast<int>(i));
  return bodies;
}

TrajectoryWriter::TrajectoryWriter(const std::filesystem::path& path, const Scene& scene,
                                   std::vector<int> bodies)
    : file_(path), scene_(scene), bodies_(std::move(bodies)) {
  file_.stream() << kTrajectoryHeader << '\n';
}

void TrajectoryWriter::record(const State& state) {
  errno = 0;  // so that a failed write's reason is the one file_.check() reports
  std::ostream& out = file_.stream();
  for (const int index : bodies_) {
    const auto i = std::size_t(index);
    const BodyState& b = state.bodies[i];
    write_number(out, state.time);
    out << ',';
    write_csv_field(out, scene_.bodies[i].name);
    const Real values[] = {b.position.x(),        b.position.y(),         b.position.z(),
                           b.orientation.w(),     b.orientation.x(),      b.orientation.y(),
                           b.orientation.z(),     b.velocity.x(),         b.velocity.y(),
                           b.velocity.z(),        b.angular_velocity.x(), b.angular_velocity.y(),
                           b.angular_velocity.z()};
    for (Real v : values) {
      out << ',';
      write_number(out, v);
    }
    out << '\n';
  }
  file_.check();
}

}  // namespace tumble::app
