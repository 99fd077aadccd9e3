#include "dynamics/contact_solver.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <new>
#include <numbers>

#include "dynamics/contact_rows.hpp"
#include "dynamics/contact_solver_wide.hpp"

namespace tumble {

namespace {

// Soft spring of angular frequency w and damping ratio z, discretised implicitly over the
// substep h (Catto, Solver2D): a1 = 2 z + h w, a2 = h w a1. The bias velocity is (w / a1) *
// separation, and each row's compliance is J M^-1 J^T / a2, so the response does not depend on
// mass: one row alone gets the impulse -m_eff a2 / (1 + a2) (v + bias) - lambda / (1 + a2).
ContactSolver::Coefficients coefficients_of(const ContactSolverSettings& settings) {
  ContactSolver::Coefficients k;
  const Real h = settings.substep;
  k.h = h;
  k.inv_h = Real(1) / h;
  const Real hertz[2] = {settings.contact_hertz, settings.static_contact_hertz};
  for (int i = 0; i < 2; ++i) {
    const Real omega = 2 * std::numbers::pi_v<Real> * hertz[i];
    const Real a1 = 2 * settings.contact_damping_ratio + h * omega;
    const Real a2 = h * omega * a1;
    k.bias_rate[i] = a1 > 0 ? omega / a1 : Real(0);
    k.soft_compliance[i] = a2 > 0 ? Real(1) / a2 : std::numeric_limits<Real>::max();
  }
  k.slop = settings.penetration_slop;
  k.max_push = settings.max_push_velocity;
  k.restitution_threshold = settings.restitution_threshold;
  return k;
}

// The curvature of a curved contact's separation along the direction the pair slides (the
// tangential part of `relative_velocity`, the centres' relative velocity), or the mean of the
// tangent plane's when it does not slide: the one number the passes need to follow the surface
// through the step (docs/architecture.md, "Curved contacts").
Real sliding_curvature(const Manifold& manifold, const Vec3& relative_velocity) {
  if (manifold.separation_curvature == PackedSymmetric{})
    return 0;
  const Mat3 h = unpacked_symmetric(manifold.separation_curvature);
  const Vec3& n = manifold.normal;
  const Vec3 sliding = relative_velocity - relative_velocity.dot(n) * n;
  const Real speed_squared = sliding.squaredNorm();
  if (speed_squared > Real(1e-24))
    return sliding.dot(h * sliding) / speed_squared;
  return (h.trace() - n.dot(h * n)) / 2;
}

// Work per chunk: enough that a chunk outweighs handing it to a thread (about a microsecond).
constexpr std::int32_t kRecordsPerChunk = 64;
constexpr std::int32_t kBundlesPerChunk = 16;
constexpr std::int32_t kSlotsPerChunk = 512;

}  // namespace

template <class Body>
void ContactSolver::for_chunks(std::int32_t count, std::int32_t grain, Body&& body) const {
  if (runner_ != nullptr)
    runner_->for_chunks(count, grain, body);
  else if (count > 0)
    body(std::int32_t(0), count);
}

void ContactSolver::AlignedFree::operator()(std::byte* p) const {
  ::operator delete[](p, std::align_val_t(64));
}

ContactSolver::ContactSolver() : ContactSolver(detail::wide_kernels()) {}

ContactSolver::ContactSolver(const detail::WideKernels& kernels) : kernels_(&kernels) {
  velocities_.resize(1);
  motions_.resize(1);
  groups_.reserve(16);  // a world has at most 11 (one per doubling of the substeps)
}
ContactSolver::~ContactSolver() = default;
ContactSolver::ContactSolver(ContactSolver&&) noexcept = default;
ContactSolver& ContactSolver::operator=(ContactSolver&&) noexcept = default;

std::size_t ContactSolver::bytes_reserved() const {
  return bundle_capacity_ + records_.capacity() * sizeof(ManifoldRecord) +
         velocities_.capacity() * sizeof(Velocity) + motions_.capacity() * sizeof(Motion) +
         (lane_records_.capacity() + group_records_.capacity() + pair_slot_a_.capacity() +
          pair_slot_b_.capacity() + slot_of_body_.capacity() + body_of_slot_.capacity()) *
             sizeof(std::int32_t);
}

void ContactSolver::build(std::span<const PairContact> contacts,
                          std::span<const CachedManifold> previous,
                          std::span<const BodyState> bodies, std::span<const BodyMass> masses,
                          Real dt, const Vec3& gravity) {
  records_.resize(contacts.size());
  loads_.resize(contacts.size());
  start_position_.resize(bodies.size());
  start_orientation_.resize(bodies.size());
  inverse_inertia_world_.resize(bodies.size());
  // Each body's world inverse inertia once (a body is in several pairs).
  for_chunks(static_cast<std::int32_t>(bodies.size()), kRecordsPerChunk,
             [&](std::int32_t begin, std::int32_t end) {
               for (std::size_t i = std::size_t(begin); i < std::size_t(end); ++i) {
                 start_position_[i] = bodies[i].position;
                 start_orientation_[i] = bodies[i].orientation;
                 const Mat3 r = bodies[i].orientation.toRotationMatrix();
                 inverse_inertia_world_[i] = r * masses[i].inverse_inertia * r.transpose();
               }
             });
  // Each contact's cached manifold from the last step: both lists are sorted by pair, so one walk
  // finds them all (a binary search per contact missed the cache at every probe: half of the
  // build's time on 10,000 pairs).
  cached_of_contact_.resize(contacts.size());
  std::size_t cursor = 0;
  for (std::size_t c = 0; c < contacts.size(); ++c) {
    const std::pair key{contacts[c].body_a, contacts[c].body_b};
    while (cursor < previous.size() &&
           std::pair{previous[cursor].body_a, previous[cursor].body_b} < key)
      ++cursor;
    cached_of_contact_[c] = cursor < previous.size() && std::pair{previous[cursor].body_a,
                                                                  previous[cursor].body_b} == key
                                ? &previous[cursor]
                                : nullptr;
  }
  Gravity g;
  g.present = gravity.squaredNorm() > 0;
  g.down = g.present ? Vec3(gravity.normalized()) : Vec3::Zero();
  g.magnitude = gravity.norm();
  for_chunks(static_cast<std::int32_t>(contacts.size()), kRecordsPerChunk,
             [&](std::int32_t begin, std::int32_t end) {
               for (std::int32_t c = begin; c < end; ++c)
                 build_record(contacts[std::size_t(c)], cached_of_contact_[std::size_t(c)], bodies,
                              masses, inverse_inertia_world_, dt, g, records_[std::size_t(c)],
                              loads_[std::size_t(c)]);
             });
}

void ContactSolver::build_record(const PairContact& pc, const CachedManifold* cached,
                                 std::span<const BodyState> bodies,
                                 std::span<const BodyMass> masses,
                                 std::span<const Mat3> inverse_inertia_world, Real dt,
                                 const Gravity& gravity, ManifoldRecord& m, ContactLoad& load) {
  // Every field the later stages read is written here, once: the record is not first reset to
  // its defaults (that reset, stored in small pieces and read back whole, stalled store
  // forwarding and was a quarter of the build). Points past `count`, the slots (pack) and the
  // Delassus entries past the count's triangle are never read.
  const std::int32_t a = pc.body_a;
  const std::int32_t b = pc.body_b;
  m.body_a = a;
  m.body_b = b;
  m.slot_a = 0;
  m.slot_b = 0;
  m.count = pc.manifold.count;
  m.normal = pc.manifold.normal;
  orthonormal_basis(m.normal, m.tangent1, m.tangent2);
  m.inv_mass_a = masses[std::size_t(a)].inverse_mass;
  m.inv_mass_b = masses[std::size_t(b)].inverse_mass;
  m.friction = pc.friction;
  m.restitution = pc.restitution;
  const BodyState& sa = bodies[std::size_t(a)];
  const BodyState& sb = bodies[std::size_t(b)];
  m.curvature = sliding_curvature(pc.manifold, sa.velocity - sb.velocity);
  const Mat3& ia = inverse_inertia_world[std::size_t(a)];
  const Mat3& ib = inverse_inertia_world[std::size_t(b)];
  const Real inv_mass_sum = m.inv_mass_a + m.inv_mass_b;
  // The points in the order of their feature keys, not the narrow phase's: the rows of a face
  // contact are solved one by one where the block would pull (docs/architecture.md), and their
  // order then shares out the impulse. A manifold found along another path (GJK from last step's
  // axis or from scratch) lists the same points in another order, and must give the same step.
  std::array<int, kMaxManifoldPoints> order{};
  for (int k = 0; k < m.count; ++k) {
    int j = k;
    const std::uint32_t key = pc.manifold.points[std::size_t(k)].feature.key();
    for (; j > 0 && pc.manifold.points[std::size_t(order[std::size_t(j - 1)])].feature.key() > key;
         --j)
      order[std::size_t(j)] = order[std::size_t(j - 1)];
    order[std::size_t(j)] = k;
  }
  for (int k = 0; k < m.count; ++k) {
    const ContactPoint& cp = pc.manifold.points[std::size_t(order[std::size_t(k)])];
    PointRecord& p = m.points[std::size_t(k)];
    // Worked in locals and stored once: read back from the record, the lever arms' stores
    // stalled the loads that followed them (a load spanning two stores is not forwarded).
    const Vec3 r_a = cp.position - sa.position;
    const Vec3 r_b = cp.position - sb.position;
    p.r_a = r_a;
    p.r_b = r_b;
    // A body of infinite mass has a zero inverse inertia, so its term is a +-0 added to a sum that
    // starts at the inverse masses' sum (positive, or +0), which it leaves unchanged: left out,
    // with the same bits (most contacts of a world of small bodies are against the ground).
    Real diagonal = inv_mass_sum;
    if (m.inv_mass_a != 0) {
      const Vec3 rn_a = r_a.cross(m.normal);
      diagonal = diagonal + rn_a.dot(ia * rn_a);
    }
    if (m.inv_mass_b != 0) {
      const Vec3 rn_b = r_b.cross(m.normal);
      diagonal = diagonal + rn_b.dot(ib * rn_b);
    }
    p.normal_diagonal = diagonal;
    p.base_separation = -cp.depth;
    p.normal_impulse = 0;
    p.tangent_impulse1 = 0;
    p.tangent_impulse2 = 0;
    p.feature = cp.feature.key();
    p.local_a = rotate_vector(sa.orientation.conjugate(), r_a);
  }
  // The load: what the warm start says the points carried, and at least the weight of the
  // body on top (the one the normal points up into) shared by the points, so that a heavy body
  // on a light one is known from the first step it touches (before a soft contact has sunk
  // under it). A light body on a heavy one loads the contact with its own weight only.
  const Real up = gravity.present ? -m.normal.dot(gravity.down) : Real(0);
  const Real upper_inverse_mass = up >= 0 ? m.inv_mass_a : m.inv_mass_b;  // n from B to A
  const Real upper = upper_inverse_mass == 0 ? Real(0) : 1 / upper_inverse_mass;
  const Real weight_share =
      m.count > 0 ? gravity.magnitude * std::abs(up) * upper / m.count : Real(0);
  if (cached != nullptr)
    warm_start_from(*cached, pc.match_distance, m);
  load = ContactLoad{};
  for (int k = 0; k < m.count; ++k) {
    const Real diagonal = m.points[std::size_t(k)].normal_diagonal;
    load.inverse_effective_mass = std::max(load.inverse_effective_mass, diagonal);
    load.warm = std::max(load.warm, m.points[std::size_t(k)].normal_impulse / dt * diagonal);
    load.weight = std::max(load.weight, weight_share * diagonal);
  }
}

void ContactSolver::pack(std::span<const std::int32_t> group_of_contact,
                         std::span<const ContactSolverSettings> group_settings,
                         std::span<const std::uint8_t> kinematic) {
  const std::size_t group_count = group_settings.size();
  const auto moving = [&](std::int32_t body) {
    return std::size_t(body) < kinematic.size() && kinematic[std::size_t(body)] != 0;
  };
  groups_.assign(group_count, Group{});
  pending_separations_group_ = -1;
  runs_.clear();
  lane_records_.clear();
  point_count_ = 0;
  color_count_ = 0;
  overflow_count_ = 0;
  const int lanes = kernels_->lanes;
  slot_of_body_.assign(start_position_.size(), -1);
  body_of_slot_.assign(1, -1);
  for (std::size_t g = 0; g < group_count; ++g) {
    Group& group = groups_[g];
    group.settings = group_settings[g];
    group.coefficients = coefficients_of(group.settings);
    const Real per_substep = Real(1) / Real(std::max(1, group.settings.substeps));
    // Slots of the group's moving bodies, in order of first appearance in its pairs.
    group_records_.clear();
    group.slot_begin = static_cast<std::int32_t>(body_of_slot_.size());
    const auto slot_of = [&](std::int32_t body, Real inverse_mass, bool moves) {
      if (inverse_mass == 0 && !moves)
        return std::int32_t(0);
      // A slot from an earlier group belongs to a body of infinite mass that moves (kinematic):
      // each group tracks that body's motion through its own substeps, in a slot of its own.
      std::int32_t& slot = slot_of_body_[std::size_t(body)];
      if (slot < group.slot_begin) {
        slot = static_cast<std::int32_t>(body_of_slot_.size());
        body_of_slot_.push_back(body);
      }
      return slot;
    };
    for (std::size_t c = 0; c < records_.size(); ++c) {
      if (group_of_contact[c] != std::int32_t(g))
        continue;
      ManifoldRecord& m = records_[c];
      m.slot_a = slot_of(m.body_a, m.inv_mass_a, moving(m.body_a));
      m.slot_b = slot_of(m.body_b, m.inv_mass_b, moving(m.body_b));
      for (int k = 0; k < m.count; ++k) {
        PointRecord& p = m.points[std::size_t(k)];
        p.normal_impulse *= per_substep;
        p.tangent_impulse1 *= per_substep;
        p.tangent_impulse2 *= per_substep;
      }
      group.point_count += m.count;
      group.has_restitution = group.has_restitution || (m.restitution != 0 && m.count > 0);
      group_records_.push_back(static_cast<std::int32_t>(c));
    }
    group.slot_end = static_cast<std::int32_t>(body_of_slot_.size());
    point_count_ += group.point_count;

    // Colours, then within a colour the manifolds with more points first, so that a bundle's
    // lanes carry similar counts. A colour fills bundles of `lanes`; the overflow is solved one
    // manifold per bundle, in sequence.
    pair_slot_a_.resize(group_records_.size());
    pair_slot_b_.resize(group_records_.size());
    for (std::size_t i = 0; i < group_records_.size(); ++i) {
      pair_slot_a_[i] = records_[std::size_t(group_records_[i])].slot_a;
      pair_slot_b_[i] = records_[std::size_t(group_records_[i])].slot_b;
    }
    graph_.build(pair_slot_a_, pair_slot_b_, static_cast<std::int32_t>(body_of_slot_.size()));
    color_count_ += graph_.color_count();
    overflow_count_ += graph_.overflow_pairs();
    group.bundle_begin = static_cast<std::int32_t>(lane_records_.size()) / lanes;
    group.run_begin = static_cast<std::int32_t>(runs_.size());
    for (const ContactGraph::Group& run : graph_.groups()) {
      const std::size_t first = lane_records_.size();
      if (!run.sequential) {
        // Most points first: one pass per count, in the colour's order (stable, no buffer).
        for (int points = kMaxManifoldPoints; points >= 0; --points) {
          for (std::int32_t k = run.begin; k < run.end; ++k) {
            const std::int32_t record = group_records_[std::size_t(graph_.order()[std::size_t(k)])];
            if (records_[std::size_t(record)].count == points)
              lane_records_.push_back(record);
          }
        }
        while (lane_records_.size() % std::size_t(lanes) != 0)
          lane_records_.push_back(-1);
      } else {
        // One manifold per bundle, in lane 0, solved in sequence.
        for (std::int32_t k = run.begin; k < run.end; ++k) {
          lane_records_.push_back(group_records_[std::size_t(graph_.order()[std::size_t(k)])]);
          for (int l = 1; l < lanes; ++l)
            lane_records_.push_back(-1);
        }
      }
      runs_.push_back({static_cast<std::int32_t>(first) / lanes,
                       static_cast<std::int32_t>(lane_records_.size()) / lanes, run.sequential});
    }
    group.run_end = static_cast<std::int32_t>(runs_.size());
    group.bundle_end = static_cast<std::int32_t>(lane_records_.size()) / lanes;
  }
  bundle_count_ = static_cast<int>(lane_records_.size()) / lanes;
  group_of_record_.assign(group_of_contact.begin(), group_of_contact.end());

  velocities_.resize(body_of_slot_.size());
  velocities_[0] = Velocity{};
  motions_.assign(body_of_slot_.size(), Motion{});
  const std::size_t bytes = std::size_t(bundle_count_) * kernels_->bundle_bytes;
  if (bytes > bundle_capacity_) {
    const std::size_t capacity = std::max(bytes, 2 * bundle_capacity_);
    bundles_.reset(static_cast<std::byte*>(::operator new[](capacity, std::align_val_t(64))));
    bundle_capacity_ = capacity;
  }
  // Each bundle is filled from its own lanes' records.
  for_chunks(bundle_count_, kBundlesPerChunk, [&](std::int32_t begin, std::int32_t end) {
    kernels_->pack(records_.data(), lane_records_.data() + std::size_t(begin) * std::size_t(lanes),
                   end - begin, inverse_inertia_world_.data(),
                   bundles_.get() + std::size_t(begin) * kernels_->bundle_bytes);
  });
}

void ContactSolver::prepare(std::span<const PairContact> contacts,
                            std::span<const CachedManifold> previous,
                            std::span<const BodyState> bodies, std::span<const BodyMass> masses,
                            const ContactSolverSettings& settings) {
  build(contacts, previous, bodies, masses, settings.substep * Real(std::max(1, settings.substeps)),
        Vec3::Zero());
  single_group_.assign(contacts.size(), 0);
  pack(single_group_, std::span(&settings, 1));
}

// Each cached point lends its impulses to at most one new point: first to the point with the
// same feature id, then, for points still unmatched, to the nearest within `match_distance`.
void ContactSolver::warm_start_from(const CachedManifold& cached, Real match_distance,
                                    ManifoldRecord& m) {
  std::array<bool, kMaxManifoldPoints> used{};
  std::array<int, kMaxManifoldPoints> source;
  source.fill(-1);
  for (int k = 0; k < m.count; ++k) {
    for (int c = 0; c < cached.count; ++c) {
      if (!used[std::size_t(c)] &&
          cached.points[std::size_t(c)].feature == m.points[std::size_t(k)].feature) {
        used[std::size_t(c)] = true;
        source[std::size_t(k)] = c;
        break;
      }
    }
  }
  for (int k = 0; k < m.count; ++k) {
    if (source[std::size_t(k)] >= 0)
      continue;
    Real best = match_distance;
    for (int c = 0; c < cached.count; ++c) {
      const Real distance =
          (cached.points[std::size_t(c)].local_point - m.points[std::size_t(k)].local_a).norm();
      if (!used[std::size_t(c)] && distance < best) {
        best = distance;
        source[std::size_t(k)] = c;
      }
    }
    if (source[std::size_t(k)] >= 0)
      used[std::size_t(source[std::size_t(k)])] = true;
  }
  for (int k = 0; k < m.count; ++k) {
    if (source[std::size_t(k)] < 0)
      continue;
    const CachedContactPoint& match = cached.points[std::size_t(source[std::size_t(k)])];
    PointRecord& p = m.points[std::size_t(k)];
    p.normal_impulse = match.normal_impulse;
    p.tangent_impulse1 = match.friction_impulse.dot(m.tangent1);
    p.tangent_impulse2 = match.friction_impulse.dot(m.tangent2);
  }
}

// The three loops over a group's slots below run every substep; each slot is its own (a body
// has one slot per group), so they split over the threads.
void ContactSolver::load_velocities(int group, std::span<const BodyState> bodies) {
  const Group& g = groups_[std::size_t(group)];
  for_chunks(g.slot_end - g.slot_begin, kSlotsPerChunk, [&](std::int32_t begin, std::int32_t end) {
    kernels_->load_velocities(bodies.data(), body_of_slot_.data(), g.slot_begin + begin,
                              g.slot_begin + end, velocities_.data());
  });
}

void ContactSolver::store_velocities(int group, std::span<BodyState> bodies) const {
  const Group& g = groups_[std::size_t(group)];
  for_chunks(g.slot_end - g.slot_begin, kSlotsPerChunk, [&](std::int32_t begin, std::int32_t end) {
    for (std::int32_t s = g.slot_begin + begin; s < g.slot_begin + end; ++s) {
      BodyState& b = bodies[std::size_t(body_of_slot_[std::size_t(s)])];
      const Velocity& v = velocities_[std::size_t(s)];
      b.velocity = Vec3(v.v[0], v.v[1], v.v[2]);
      b.angular_velocity = Vec3(v.w[0], v.w[1], v.w[2]);
    }
  });
}

void ContactSolver::update_separations(int group, std::span<const BodyState> bodies) {
  const Group& g = groups_[std::size_t(group)];
  for_chunks(g.slot_end - g.slot_begin, kSlotsPerChunk, [&](std::int32_t begin, std::int32_t end) {
    update_motions(g.slot_begin + begin, g.slot_begin + end, bodies);
  });
  // The bundles' separations follow in the next pass over them (solve), or on their own when
  // something else reads them first (apply_pending_separations).
  pending_separations_group_ = group;
}

void ContactSolver::update_motions(std::int32_t begin, std::int32_t end,
                                   std::span<const BodyState> bodies) {
  for (std::int32_t s = begin; s < end; ++s) {
    const std::size_t body = std::size_t(body_of_slot_[std::size_t(s)]);
    const BodyState& b = bodies[body];
    Motion& m = motions_[std::size_t(s)];
    const Vec3 dp = b.position - start_position_[body];
    // The rotation since the start of the step, less the identity, written so that a small
    // rotation loses no digits to 1 - 1.
    const Quat q = b.orientation * start_orientation_[body].conjugate();
    const Real x = q.x(), y = q.y(), z = q.z(), w = q.w();
    m.dp[0] = dp.x();
    m.dp[1] = dp.y();
    m.dp[2] = dp.z();
    Real* r = m.rotation_less_identity;
    r[0] = -2 * (y * y + z * z);
    r[1] = 2 * (x * y - w * z);
    r[2] = 2 * (x * z + w * y);
    r[3] = 2 * (x * y + w * z);
    r[4] = -2 * (x * x + z * z);
    r[5] = 2 * (y * z - w * x);
    r[6] = 2 * (x * z - w * y);
    r[7] = 2 * (y * z + w * x);
    r[8] = -2 * (x * x + y * y);
  }
}

void ContactSolver::apply_pending_separations(int group) {
  if (pending_separations_group_ != group)
    return;
  pending_separations_group_ = -1;
  const Group& g = groups_[std::size_t(group)];
  // Each bundle's separations are its own.
  for_chunks(g.bundle_end - g.bundle_begin, kBundlesPerChunk,
             [&](std::int32_t begin, std::int32_t end) {
               kernels_->update_separations(bundles_.get(), g.bundle_begin + begin,
                                            g.bundle_begin + end, motions_.data());
             });
}

// Runs `kernel` over the group's bundles a colour at a time, in colour order: the bundles of a
// colour share no moving body, so they may run at once; the overflow's one after another. A
// body's velocity then gathers its pairs' changes in the same order on any number of threads.
template <class Kernel>
void ContactSolver::for_each_colour(const Group& g, const Kernel& kernel) {
  for (std::int32_t r = g.run_begin; r < g.run_end; ++r) {
    const Run& run = runs_[std::size_t(r)];
    if (run.sequential) {
      kernel(run.begin, run.end);
      continue;
    }
    for_chunks(run.end - run.begin, kBundlesPerChunk, [&](std::int32_t begin, std::int32_t end) {
      kernel(run.begin + begin, run.begin + end);
    });
  }
}

void ContactSolver::warm_start(int group) {
  for_each_colour(groups_[std::size_t(group)], [&](std::int32_t begin, std::int32_t end) {
    kernels_->warm_start(bundles_.get(), begin, end, velocities_.data());
  });
}

void ContactSolver::solve(int group, bool use_bias) {
  const Group& g = groups_[std::size_t(group)];
  // Separations waiting since the bodies moved are brought up to date by this pass, bundle by
  // bundle just before each is solved.
  const Motion* motions = pending_separations_group_ == group ? motions_.data() : nullptr;
  pending_separations_group_ = -1;
  for_each_colour(g, [&](std::int32_t begin, std::int32_t end) {
    kernels_->solve(bundles_.get(), begin, end, velocities_.data(), g.coefficients, use_bias,
                    motions);
  });
}

int ContactSolver::resolve_impacts(int group) {
  apply_pending_separations(group);
  const Group& g = groups_[std::size_t(group)];
  if (!g.has_restitution)
    return 0;
  return kernels_->resolve_impacts(bundles_.get(), g.bundle_begin, g.bundle_end, velocities_.data(),
                                   g.coefficients, g.point_count);
}

void ContactSolver::apply_restitution(int group) {
  const Group& g = groups_[std::size_t(group)];
  if (g.has_restitution) {
    kernels_->apply_restitution(bundles_.get(), g.bundle_begin, g.bundle_end, velocities_.data(),
                                g.coefficients);
  }
}

void ContactSolver::store(std::vector<CachedManifold>& cache) {
  const std::size_t lanes = std::size_t(kernels_->lanes);
  for_chunks(bundle_count_, kBundlesPerChunk, [&](std::int32_t begin, std::int32_t end) {
    kernels_->unpack(bundles_.get() + std::size_t(begin) * kernels_->bundle_bytes,
                     lane_records_.data() + std::size_t(begin) * lanes, end - begin,
                     records_.data());
  });
  cache.resize(records_.size());
  for_chunks(static_cast<std::int32_t>(records_.size()), kRecordsPerChunk,
             [&](std::int32_t begin, std::int32_t end) { store_records(begin, end, cache); });
}

void ContactSolver::store_records(std::int32_t begin, std::int32_t end,
                                  std::vector<CachedManifold>& cache) const {
  for (std::size_t i = std::size_t(begin); i < std::size_t(end); ++i) {
    const ManifoldRecord& r = records_[i];
    const Real steps =
        Real(std::max(1, groups_[std::size_t(group_of_record_[i])].settings.substeps));
    CachedManifold& m = cache[i];
    m = CachedManifold{};
    m.body_a = r.body_a;
    m.body_b = r.body_b;
    m.count = r.count;
    for (int k = 0; k < r.count; ++k) {
      const PointRecord& p = r.points[std::size_t(k)];
      CachedContactPoint& out = m.points[std::size_t(k)];
      out.feature = p.feature;
      out.local_point = p.local_a;
      out.normal_impulse = p.normal_impulse * steps;
      out.friction_impulse =
          (r.tangent1 * p.tangent_impulse1 + r.tangent2 * p.tangent_impulse2) * steps;
    }
  }
}

void ContactSolver::warm_start(std::span<BodyState> bodies) {
  load_velocities(0, bodies);
  warm_start(0);
  store_velocities(0, bodies);
}

void ContactSolver::solve(std::span<BodyState> bodies, bool use_bias) {
  load_velocities(0, bodies);
  update_separations(0, bodies);
  solve(0, use_bias);
  store_velocities(0, bodies);
}

int ContactSolver::resolve_impacts(std::span<BodyState> bodies) {
  load_velocities(0, bodies);
  const int bounces = resolve_impacts(0);
  store_velocities(0, bodies);
  return bounces;
}

void ContactSolver::apply_restitution(std::span<BodyState> bodies) {
  load_velocities(0, bodies);
  apply_restitution(0);
  store_velocities(0, bodies);
}

}  // namespace tumble
