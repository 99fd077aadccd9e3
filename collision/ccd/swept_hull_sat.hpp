// The separating-axis theorem extended over time (docs/ccd.md) for convex polytopes: boxes and
// convex hulls, translating or turning. Our own extension of collision/ccd/swept_box_sat.hpp;
// the pieces it combines are cited in swept_hull_sat.cpp.
//
// Candidate axes (both bodies posed at one time): the face normals of A and of B, and the cross
// products of those edge pairs of A and B that form a face of the Minkowski difference (the
// Gauss-map arc test of Gregorius, "The Separating Axis Test between Convex Polyhedra", GDC
// 2013); parallel edge pairs are skipped (the face normals cover that direction). Along each
// axis the gap between the two bodies is exact: the bodies overlap exactly when no axis has a
// positive gap.
//
// Translation only: the axes keep their direction and every gap changes linearly in time, so
// each axis rules out a half-line of times and the first contact is the latest entry time,
// if it comes before the earliest exit time: exact up to rounding, no iteration.
// With rotation: the gap along a fixed axis changes by at most (rate bound) * (time); each axis
// rules out the window of times before its gap can close, the search moves to the end of the
// longest window and repeats (conservative advancement over the SAT axes). The reported time is
// never later than the true first contact.
#pragma once

#include "collision/ccd/conservative_advancement.hpp"

namespace tumble {

class ConvexHull;

// Two hulls translating by `translation_a` and `translation_b` over s in [0, 1] (no rotation):
// hit (or overlapping at s = 0) with the time and the axis (unit, from B to A) of the last axis
// to close, or separated. `target_distance` > 0 stops that far short of touching (along the
// separating axis: with the closest features vertex against vertex or edge, the SAT gap is below
// the distance, so the stop comes earlier); < 0 allows that much overlap along every axis.
ToiResult swept_hull_sat(const ConvexHull& a, const Transform& pose_a, const Vec3& translation_a,
                         const ConvexHull& b, const Transform& pose_b, const Vec3& translation_b,
                         Real target_distance = 0);

// True when time_extended_sat handles the pair: box or hull on both sides.
bool time_extended_sat_applies(const Shape& a, const Shape& b);

// Box or hull shapes under any rigid motions (linear or screw). Without rotation it is the exact
// translating test above (`settings.target_distance` as there; tolerance and the cap unused).
// With rotation it advances over time windows until the largest SAT gap is within
// `settings.tolerance` above `settings.target_distance` (hit; the time is a lower bound of the
// true time of contact), some axis stays separated to s = 1 (separated), or
// `settings.max_iterations` evaluations ran (max_iterations; no contact before the time reached).
// `distance` of the result is the largest SAT gap at the reported time, a lower bound of the
// distance. Other shape types give invalid_input, as do NaN or infinite poses or motions.
ToiResult time_extended_sat(const Shape& a, const RigidMotion& motion_a, const Shape& b,
                            const RigidMotion& motion_b, const ToiSettings& settings = {});

// The static test the time-extended one is made of: the largest gap over the candidate axes of
// two posed boxes or hulls, with its axis (from B to A). It is the exact distance when a face or
// an edge pair is closest and below it otherwise; its sign is exact (> 0 apart, <= 0 touching
// or overlapping). A lower bound of the distance for conservative advancement.
DistanceBound polytope_separation(const Shape& a, const Transform& pose_a, const Shape& b,
                                  const Transform& pose_b);

}  // namespace tumble
