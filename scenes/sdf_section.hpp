// Signed distance fields written in YAML (docs/scene-format.md, "sdf"): a node is a map with one
// kind and, optionally, where it sits,
//   {torus: {major_radius: 1, minor_radius: 0.25}, position: [0, 0, 1], orientation: [w, x, y, z]}
//   {difference: [{box: {half_extents: [1, 1, 0.5]}}, {sphere: {radius: 0.9}, position: [0, 0,
//   0.6]}]} {smooth_union: {k: 8, of: [{sphere: {radius: 0.5}}, {capsule: {radius: 0.2,
//   half_length: 0.6}}]}}
// Kinds: sphere, box, capsule, cylinder, torus, plane, union, intersection, difference,
// smooth_union. Errors are SceneError with the file, line, column and field.
#pragma once

#include <string_view>

#include "collision/sdf/sdf_tree.hpp"
#include "tumble/load_scene.hpp"

namespace tumble {

// The node of the YAML text `yaml` (one document: a node as above); `source_name` names it in
// messages.
SdfNode load_sdf_string(std::string_view yaml, std::string_view source_name,
                        const SceneLoadOptions& options = {});

}  // namespace tumble
