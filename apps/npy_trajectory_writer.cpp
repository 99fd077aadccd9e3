#include "apps/npy_trajectory_writer.hpp"

#include <bit>
#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <string>

namespace tumble::app {

static_assert(std::endian::native == std::endian::little, "the .npy data is written as '<f8'");

std::string NpyTrajectoryWriter::header(std::int64_t records, std::size_t bodies,
                                        std::size_t size) {
  std::string dict = "{'descr': '<f8', 'fortran_order': False, 'shape': (" +
                     std::to_string(records) + ", " + std::to_string(bodies) + ", 13), }";
  // magic (6) + version (2) + length (2) + dict + spaces + '\n' = size.
  const std::size_t prefix = 10;
  if (prefix + dict.size() + 1 > size)
    throw std::runtime_error("trajectory.npy: the header does not fit");
  dict.append(size - prefix - dict.size() - 1, ' ');
  dict.push_back('\n');
  const std::uint16_t length = static_cast<std::uint16_t>(dict.size());
  std::string out("\x93NUMPY\x01\x00", 8);
  out.push_back(static_cast<char>(length & 0xff));
  out.push_back(static_cast<char>(length >> 8));
  return out + dict;
}

NpyTrajectoryWriter::NpyTrajectoryWriter(const std::filesystem::path& path, std::vector<int> bodies)
    : file_(path), bodies_(std::move(bodies)) {
  // A placeholder of the final header's size; finish() writes the real shape over it.
  file_.stream() << header(0, bodies_.size(), kHeaderSize);
}

void NpyTrajectoryWriter::record(const State& state) {
  errno = 0;  // so that a failed write's reason is the one file_.check() reports
  std::ostream& out = file_.stream();
  for (const int index : bodies_) {
    const BodyState& b = state.bodies[std::size_t(index)];
    const double values[13] = {
        b.position.x(),        b.position.y(),    b.position.z(),         b.orientation.w(),
        b.orientation.x(),     b.orientation.y(), b.orientation.z(),      b.velocity.x(),
        b.velocity.y(),        b.velocity.z(),    b.angular_velocity.x(), b.angular_velocity.y(),
        b.angular_velocity.z()};
    out.write(reinterpret_cast<const char*>(values), sizeof values);
  }
  ++records_;
  file_.check();
}

void NpyTrajectoryWriter::finish() {
  std::ostream& out = file_.stream();
  out.seekp(0);
  out << header(records_, bodies_.size(), kHeaderSize);
  out.seekp(0, std::ios::end);
  file_.commit();
}

}  // namespace tumble::app
