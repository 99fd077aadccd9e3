// The batched sphere-sphere path against collide(), the per-pair narrow phase it stands in for:
// on tens of thousands of random pairs (fixed seed; mixed and equal radii, near and far from the
// origin, exactly touching, at the margin's edge, coincident, NaN) it must find the same pairs
// and give the same contacts bit for bit, so a simulation can use either.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "collision/narrow_phase/narrow_phase.hpp"
#include "collision/narrow_phase/sphere_batch.hpp"
#include "tests/collision/mesh_fixtures.hpp"

namespace tumble::testing {
namespace {

struct SphereSoup {
  std::vector<Real> x, y, z, radius;
  std::vector<SpherePair> pairs;

  int add(const Vec3& centre, Real r) {
    x.push_back(centre.x());
    y.push_back(centre.y());
    z.push_back(centre.z());
    radius.push_back(r);
    return int(x.size()) - 1;
  }
  Vec3 centre(int i) const { return {x[std::size_t(i)], y[std::size_t(i)], z[std::size_t(i)]}; }
  SphereArrays arrays() const { return {x.data(), y.data(), z.data(), radius.data()}; }
};

bool same_bits(Real a, Real b) {
  return std::memcmp(&a, &b, sizeof(Real)) == 0 || (std::isnan(a) && std::isnan(b));
}
bool same_bits(const Vec3& a, const Vec3& b) {
  return same_bits(a.x(), b.x()) && same_bits(a.y(), b.y()) && same_bits(a.z(), b.z());
}

// Random pairs of every kind the narrow phase meets; returns the soup.
SphereSoup random_soup(int count, Real margin) {
  std::mt19937_64 rng(20261122);
  std::uniform_real_distribution<Real> unit(-1, 1);
  std::uniform_int_distribution<int> kind(0, 7);
  const auto direction = [&] {
    Vec3 v;
    do
      v = Vec3(unit(rng), unit(rng), unit(rng));
    while (v.squaredNorm() < 1e-4 || v.squaredNorm() > 1);
    return Vec3(v.normalized());
  };
  SphereSoup soup;
  for (int i = 0; i < count; ++i) {
    const int k = kind(rng);
    const Real far = k == 1 ? 1e6 : (k == 2 ? 1e3 : 1);
    const Vec3 base = Vec3(unit(rng), unit(rng), unit(rng)) * far;
    const Real ra =
        k == 3 ? Real(1e-4) * std::abs(unit(rng)) + Real(1e-6) : Real(0.1) + std::abs(unit(rng));
    const Real rb = (k == 4 || k == 5) ? ra : Real(0.1) + std::abs(unit(rng));
    Vec3 offset;
    switch (k) {
      case 4:  // equal radii, exactly touching along an axis (the ordering rule's ties)
        offset = Vec3(ra + rb, 0, 0);
        break;
      case 5:  // equal radii, coincident centres
        offset = Vec3::Zero();
        break;
      case 6:  // at the margin's edge
        offset = direction() * (ra + rb + margin * (1 + Real(1e-12) * unit(rng)));
        break;
      default:
        offset = direction() * (ra + rb) * (1 + Real(0.6) * unit(rng));
    }
    const int a = soup.add(base, ra);
    const int b = soup.add(base + offset, rb);
    soup.pairs.push_back(k == 7 && i % 2 == 0 ? SpherePair{b, a} : SpherePair{a, b});
  }
  // A NaN centre and a zero-radius pair at the end.
  const int n1 = soup.add(Vec3(std::numeric_limits<Real>::quiet_NaN(), 0, 0), 1);
  const int n2 = soup.add(Vec3::Zero(), 1);
  soup.pairs.push_back({n1, n2});
  const int p1 = soup.add(Vec3(2, 0, 0), 0);
  const int p2 = soup.add(Vec3(2, 0, 0), 0);
  soup.pairs.push_back({p1, p2});
  return soup;
}

void expect_matches_collide(const SphereSoup& soup, Real margin) {
  std::vector<SphereContact> contacts(soup.pairs.size());
  const std::size_t written = collide_sphere_pairs(soup.arrays(), soup.pairs, margin, contacts);
  std::size_t next = 0;
  int touching = 0;
  int mismatches = 0;
  for (std::size_t i = 0; i < soup.pairs.size(); ++i) {
    const SpherePair p = soup.pairs[i];
    const Shape sa =
        Shape::sphere(soup.radius[std::size_t(p.a)] > 0 ? soup.radius[std::size_t(p.a)] : 1);
    const Shape sb =
        Shape::sphere(soup.radius[std::size_t(p.b)] > 0 ? soup.radius[std::size_t(p.b)] : 1);
    Shape a = sa;
    Shape b = sb;
    a.radius = soup.radius[std::size_t(p.a)];
    b.radius = soup.radius[std::size_t(p.b)];
    Manifold m;
    const int count = collide(a, {soup.centre(p.a), Quat::Identity()}, b,
                              {soup.centre(p.b), Quat::Identity()}, margin, m);
    ASSERT_LE(count, 1);
    if (count == 0) {
      if (next < written && contacts[next].pair == std::int32_t(i)) {
        ADD_FAILURE() << "pair " << i << ": batch found a contact collide() did not";
        ++next;
      }
      continue;
    }
    ++touching;
    ASSERT_LT(next, written) << "pair " << i << ": collide() found a contact the batch missed";
    const SphereContact& c = contacts[next++];
    ASSERT_EQ(c.pair, std::int32_t(i)) << "the batch missed pair " << i;
    if (!same_bits(c.depth, m.points[0].depth) || !same_bits(c.normal, m.normal) ||
        !same_bits(c.position, m.points[0].position))
      ++mismatches;
  }
  EXPECT_EQ(next, written);
  EXPECT_EQ(mismatches, 0) << "contacts that differ from collide() in some bit";

  // The dense form: the same pairs touch, with the same bits; the others are apart.
  const std::size_t n = soup.pairs.size();
  std::vector<Real> depth(n), nx(n), ny(n), nz(n), px(n), py(n), pz(n);
  const std::size_t touching_dense = collide_sphere_pairs_dense(
      soup.arrays(), soup.pairs, margin,
      {depth.data(), nx.data(), ny.data(), nz.data(), px.data(), py.data(), pz.data()});
  EXPECT_EQ(touching_dense, written);
  for (std::size_t k = 0; k < written; ++k) {
    const SphereContact& c = contacts[k];
    const std::size_t i = std::size_t(c.pair);
    EXPECT_TRUE(same_bits(depth[i], c.depth) && same_bits(Vec3(nx[i], ny[i], nz[i]), c.normal) &&
                same_bits(Vec3(px[i], py[i], pz[i]), c.position))
        << "dense result of pair " << i << " differs";
  }
  // The soup is built so that both outcomes are common.
  EXPECT_GT(touching, int(soup.pairs.size()) / 4);
  EXPECT_LT(touching, int(soup.pairs.size()) * 9 / 10);
}

TEST(SphereBatch, MatchesCollideBitForBit) {
  constexpr Real kMargin = 0.01;
  expect_matches_collide(random_soup(scaled(40000), kMargin), kMargin);
}

TEST(SphereBatch, MatchesCollideWithoutMargin) {
  expect_matches_collide(random_soup(scaled(20000), 0), 0);
}

TEST(SphereBatch, ContactGeometryIsRight) {
  // Two unit spheres 1.5 apart along x: depth 0.5, normal from B to A, point midway.
  SphereSoup soup;
  soup.add(Vec3(1e6, 0, 0), 1);
  soup.add(Vec3(1e6 + 1.5, 0, 0), 1);
  soup.pairs.push_back({0, 1});
  soup.pairs.push_back({1, 0});
  std::vector<SphereContact> contacts(2);
  ASSERT_EQ(collide_sphere_pairs(soup.arrays(), soup.pairs, 0, contacts), 2u);
  EXPECT_DOUBLE_EQ(contacts[0].depth, 0.5);
  EXPECT_EQ(contacts[0].normal, Vec3(-1, 0, 0));
  EXPECT_EQ(contacts[1].normal, Vec3(1, 0, 0));
  EXPECT_NEAR(contacts[0].position.x(), 1e6 + 0.75, 1e-9);
  EXPECT_EQ(contacts[0].position, contacts[1].position);
}

TEST(SphereBatch, TooSmallBuffersAreAnError) {
  SphereSoup soup;
  soup.add(Vec3::Zero(), 1);
  soup.add(Vec3::Zero(), 1);
  soup.pairs.push_back({0, 1});
  std::vector<SphereContact> contacts;
  EXPECT_THROW(collide_sphere_pairs(soup.arrays(), soup.pairs, 0, contacts), std::invalid_argument);
}

}  // namespace
}  // namespace tumble::testing
