// The OBJ reader (scenes/obj_reader.hpp): a mesh whose every vertex is finite and every index in
// range, or an ObjError. The mesh read is then built into a triangle mesh, which either holds or
// is refused with tumble::Error.
#include <cstdint>
#include <cstdlib>
#include <string>

#include "scenes/obj_reader.hpp"
#include "tumble/error.hpp"
#include "tumble/shape.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  tumble::ObjMesh mesh;
  try {
    mesh = tumble::read_obj_string(text, "fuzz.obj");
  } catch (const tumble::ObjError&) {
    return 0;
  }
  for (const tumble::Vec3& v : mesh.vertices) {
    if (!v.allFinite())
      std::abort();  // the reader promises finite vertices
  }
  for (const auto& t : mesh.triangles) {
    for (const std::int32_t i : t) {
      if (i < 0 || static_cast<std::size_t>(i) >= mesh.vertices.size())
        std::abort();  // and indices in range
    }
  }
  try {
    tumble::mesh_from_triangles(std::move(mesh.vertices), std::move(mesh.triangles));
  } catch (const tumble::Error&) {
  }
  return 0;
}
