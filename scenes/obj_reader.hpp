// Reads triangle meshes from Wavefront OBJ files for `mesh {file: X.obj}` scenes, through
// tinyobjloader (Debian libtinyobjloader-dev; header-only use here, double precision). Faces
// with more than three corners are fan-triangulated by the library; materials, normals and
// texture coordinates are ignored. The only code that includes tinyobjloader.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <vector>

#include "collision/math.hpp"
#include "collision/shapes/triangle_mesh.hpp"

namespace tumble {

struct ObjError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct ObjMesh {
  std::vector<Vec3> vertices;
  std::vector<TriangleMesh::Triangle> triangles;
};

// Throws ObjError with a message naming the file (and the library's line-level reason).
ObjMesh read_obj_file(const std::filesystem::path& path);
ObjMesh read_obj_string(const std::string& text, const std::string& name);
// The vertices ('v' lines) alone, for a hull: faces may be there or not.
std::vector<Vec3> read_obj_points_file(const std::filesystem::path& path);

}  // namespace tumble
