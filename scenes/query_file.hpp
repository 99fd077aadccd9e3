// The input of `tumble query` (docs/scene-format.md): a YAML file with a list of shape pairs,
//   queries: [{name, kind, margin, duration, method, a: {shape, position, orientation, velocity,
//              angular_velocity}, b: {...}}]
// Shapes are written exactly as in scene files (the same parser reads them). Errors are the
// loader's SceneError, with file, line, column and field.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "collision/shapes/shape.hpp"
#include "tumble/load_scene.hpp"

namespace tumble {

// What a query asks: `contact` (distance, witnesses, manifold at the given poses) or `toi`
// (time of impact of the two shapes moving with constant velocities over `duration`).
enum class QueryKind { contact, toi };

// kind toi: how the time of impact is found: conservative advancement (any shapes; the
// default) or the time-extended SAT (a box or hull on both sides; collision/ccd/swept_hull_sat).
enum class ToiMethod { advancement, sat };

struct ShapeQuery {
  std::string name;
  QueryKind kind = QueryKind::contact;
  Real margin = 10;  // m: contacts are reported while the shapes are closer than this
  Shape a;
  Transform pose_a;
  Shape b;
  Transform pose_b;
  // kind toi only: constant velocities (world frame) and the time span searched.
  Vec3 velocity_a = Vec3::Zero();          // m/s
  Vec3 angular_velocity_a = Vec3::Zero();  // rad/s
  Vec3 velocity_b = Vec3::Zero();
  Vec3 angular_velocity_b = Vec3::Zero();
  Real duration = 1;  // s
  ToiMethod method = ToiMethod::advancement;
};

std::vector<ShapeQuery> load_query_file(const std::filesystem::path& path,
                                        const SceneLoadOptions& options = {});
std::vector<ShapeQuery> load_query_string(std::string_view yaml, std::string_view source_name,
                                          const SceneLoadOptions& options = {});

}  // namespace tumble
