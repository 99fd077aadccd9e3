#include "dynamics/rigid_body.hpp"

namespace tumble {

BodyMass BodyMass::make(Real mass, const Mat3& inertia, bool is_static) {
  BodyMass m;
  if (is_static || mass <= 0)
    return m;
  m.inverse_mass = Real(1) / mass;
  m.inertia = inertia;
  m.inverse_inertia = inertia.inverse();
  const Real trace = inertia.trace() / 3;
  m.is_isotropic = inertia == Mat3::Identity() * trace;
  return m;
}

Real kinetic_energy(const BodyState& s, const BodyMass& m) {
  if (m.inverse_mass == 0)
    return 0;
  const Vec3 w_body = s.orientation.conjugate() * s.angular_velocity;
  return Real(0.5) * s.velocity.squaredNorm() / m.inverse_mass +
         Real(0.5) * w_body.dot(m.inertia * w_body);
}

Vec3 angular_momentum(const BodyState& s, const BodyMass& m) {
  const Vec3 w_body = s.orientation.conjugate() * s.angular_velocity;
  return s.orientation * (m.inertia * w_body);
}

}  // namespace tumble
