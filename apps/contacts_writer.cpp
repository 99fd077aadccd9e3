#include "apps/contacts_writer.hpp"

#include <cerrno>

#include "apps/csv_field.hpp"
#include "apps/number_format.hpp"

namespace tumble::app {

ContactsWriter::ContactsWriter(const std::filesystem::path& path) : file_(path) {
  file_.stream() << kContactsHeader << '\n';
}

void ContactsWriter::record(const World& world) {
  errno = 0;  // so that a failed write's reason is the one file_.check() reports
  std::ostream& out = file_.stream();
  for (const ContactReport& r : world.contact_reports()) {
    const std::string a = world.name(r.body_a);
    const std::string b = world.name(r.body_b);
    for (int k = 0; k < r.point_count; ++k) {
      const ContactPointReport& p = r.points[std::size_t(k)];
      write_number(out, world.time());
      out << ',';
      write_csv_field(out, a);
      out << ',';
      write_csv_field(out, b);
      const Real values[] = {p.position.x(),
                             p.position.y(),
                             p.position.z(),
                             r.normal.x(),
                             r.normal.y(),
                             r.normal.z(),
                             p.depth,
                             p.normal_impulse,
                             p.friction_impulse.x(),
                             p.friction_impulse.y(),
                             p.friction_impulse.z()};
      for (const Real v : values) {
        out << ',';
        write_number(out, v);
      }
      out << '\n';
    }
  }
  file_.check();
}

}  // namespace tumble::app
