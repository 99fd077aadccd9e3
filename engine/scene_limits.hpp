// The ranges every scene field must lie in: one table for the YAML loader
// (scenes/scene_loader.cpp) and the check of scenes built in code (engine/scene_check.cpp), so a
// bad value gets the same message either way.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <string_view>

#include "tumble/math.hpp"

namespace tumble::scene_limits {

// Limits. They are sanity bounds, not physics: they catch a typo (a missing minus in an
// exponent, a value in millimetres) before it becomes an overflow or a step count that never
// ends. docs/scene-format.md states each one.

inline constexpr Real kMaxLength = 1e9;        // m, |coordinate| and any size
inline constexpr Real kMinSize = 1e-9;         // m, smallest radius or half extent
inline constexpr Real kMaxSpeed = 1e6;         // m/s
inline constexpr Real kMaxAngularSpeed = 1e6;  // rad/s
inline constexpr Real kMaxAcceleration = 1e6;  // m/s^2, per gravity component
inline constexpr Real kMinMass = 1e-12;        // kg, a picogram
inline constexpr Real kMaxMass = 1e15;         // kg
inline constexpr Real kMaxDensity = 1e6;       // kg/m^3
// Moments of inertia: the extreme masses times the extreme sizes squared, with room to spare.
inline constexpr Real kMinMoment = 1e-40;      // kg m^2
inline constexpr Real kMaxMoment = 1e40;       // kg m^2
inline constexpr Real kMinTimeStep = 1e-9;     // s
inline constexpr Real kMaxDuration = 1e9;      // s
inline constexpr Real kMaxFriction = 100;      // [1]
inline constexpr Real kQuatTolerance = 1e-6;   // allowed | |q| - 1 |
inline constexpr Real kDefaultDensity = 1000;  // kg/m^3, water
inline constexpr std::int64_t kMaxSteps = 1000000000;
inline constexpr std::size_t kMaxBodies = 1000000;
inline constexpr std::size_t kMaxNameLength = 256;
// Sizes that cost memory, refused before anything that large is allocated.
inline constexpr std::uintmax_t kMaxFileBytes = std::uintmax_t(1) << 30;  // a file a scene reads
inline constexpr std::size_t kMaxTriangles = 10000000;     // per mesh (about 1.5 GB in tumble)
inline constexpr std::size_t kMaxMeshVertices = 10000000;  // per mesh
inline constexpr std::size_t kMaxHullPoints = 1000000;     // the points a hull is built from
// Rows of a trajectory (records times bodies listed): about 30 GB of CSV.
inline constexpr std::int64_t kMaxTrajectoryRows = 100000000;
// Candidate pairs in one step: the larger of a fixed floor and a number per body. A resting pile
// has about 10 per body; this many means bodies overlap en masse, and the narrow phase would
// exhaust the memory before it finished.
inline constexpr std::int64_t kMinCandidatePairLimit = 1000000;
inline constexpr std::int64_t kMaxCandidatePairsPerBody = 64;

inline constexpr Real kInf = std::numeric_limits<Real>::infinity();

// A numeric field: what it is (with its unit) and its closed range, optionally open at `lo`.
// `range` is the human text of [lo, hi] so that messages read naturally ("1e-9 to 1e9").
struct RealSpec {
  std::string_view what;
  std::string_view range;
  Real lo = -kInf;
  Real hi = kInf;
  bool lo_open = false;
};

struct IntSpec {
  std::string_view what;
  std::string_view range;
  std::int64_t lo;
  std::int64_t hi;
};

inline constexpr RealSpec kCoordinate{"a coordinate in metres", "-1e9 to 1e9", -kMaxLength,
                                      kMaxLength};
inline constexpr RealSpec kSize{"a positive number in metres", "1e-9 to 1e9", kMinSize, kMaxLength};
inline constexpr RealSpec kHalfLength{"a non-negative number in metres", "0 to 1e9", 0, kMaxLength};
inline constexpr RealSpec kDistance{"a non-negative distance in metres", "0 to 1e9", 0, kMaxLength};
inline constexpr RealSpec kVelocity{"a velocity in m/s", "-1e6 to 1e6", -kMaxSpeed, kMaxSpeed};
inline constexpr RealSpec kAngularVelocity{"an angular velocity in rad/s", "-1e6 to 1e6",
                                           -kMaxAngularSpeed, kMaxAngularSpeed};
inline constexpr RealSpec kAcceleration{"an acceleration in m/s^2", "-1e6 to 1e6",
                                        -kMaxAcceleration, kMaxAcceleration};
inline constexpr RealSpec kQuatComponent{"a finite number", "", -kInf, kInf};
inline constexpr RealSpec kTimeStep{"a time step in seconds", "1e-9 to 1", kMinTimeStep, 1};
inline constexpr RealSpec kDuration{"a duration in seconds", "greater than 0, at most 1e9", 0,
                                    kMaxDuration, true};
inline constexpr RealSpec kFrequency{"a frequency in Hz or auto", "greater than 0, at most 1e6", 0,
                                     1e6, true};
inline constexpr RealSpec kSagTolerance{"a fraction of the body's bounding radius",
                                        "greater than 0, at most 1", 0, 1, true};
inline constexpr RealSpec kDampingRatio{"a damping ratio", "0 to 1e6", 0, 1e6};
inline constexpr RealSpec kPushSpeed{"a speed in m/s", "greater than 0, at most 1e6", 0, kMaxSpeed,
                                     true};
inline constexpr RealSpec kSpeedThreshold{"a speed in m/s", "0 to 1e6", 0, kMaxSpeed};
inline constexpr RealSpec kFriction{"a friction coefficient", "0 to 100", 0, kMaxFriction};
inline constexpr RealSpec kRestitution{"a coefficient of restitution", "0 to 1", 0, 1};
inline constexpr RealSpec kStiffness{"a contact stiffness in N/m", "greater than 0, at most 1e12",
                                     0, 1e12, true};
inline constexpr RealSpec kDamping{"a contact damping in N s/m", "0 to 1e12", 0, 1e12};
inline constexpr RealSpec kMass{"a positive mass in kilograms", "1e-12 to 1e15", kMinMass,
                                kMaxMass};
inline constexpr RealSpec kDensity{"a positive density in kg/m^3", "greater than 0, at most 1e6", 0,
                                   kMaxDensity, true};
inline constexpr RealSpec kMoment{"a positive principal moment of inertia in kg m^2",
                                  "1e-40 to 1e40", kMinMoment, kMaxMoment};
inline constexpr RealSpec kMassScale{"a positive factor", "greater than 0, at most 1e3", 0, 1e3,
                                     true};
inline constexpr RealSpec kSizeNoise{"a relative standard deviation", "0 to 0.2", 0, 0.2};
inline constexpr RealSpec kAngleNoise{"a standard deviation in radians", "0 to 3.14", 0, 3.14};
inline constexpr RealSpec kFov{"a vertical field of view in degrees", "1 to 179", 1, 179};
inline constexpr Real kMinCameraDistance = 1e-6;  // m, camera.target from camera.position

inline constexpr IntSpec kSteps{"a whole number of steps", "1 to 1e9", 1, kMaxSteps};
inline constexpr IntSpec kThreads{"a whole number of threads, or auto", "1 to 1024", 1, 1024};
inline constexpr IntSpec kSubsteps{"a whole number of substeps", "1 to 1000", 1, 1000};
inline constexpr IntSpec kIterations{"a whole number of velocity iterations", "1 to 10000", 1,
                                     10000};
inline constexpr IntSpec kRelaxIterations{"a whole number of relax iterations", "0 to 10000", 0,
                                          10000};

}  // namespace tumble::scene_limits
