// The OBJ reader refuses what its library would misread: a coordinate that is not a finite number
// (read as 0), a face index beyond an int (wrapped to a valid vertex), and a path that is not a
// regular file (a FIFO blocks for ever, /dev/zero never ends).
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>

#include "scenes/obj_reader.hpp"

namespace tumble {
namespace {

std::string obj_error(const std::string& text) {
  try {
    read_obj_string(text, "test.obj");
  } catch (const ObjError& e) {
    return e.what();
  }
  return "";
}

TEST(ObjReader, RefusesRecordsTheLibraryWouldMisread) {
  EXPECT_NE(obj_error("v nan 4 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").find("line 1: vertex coordinate 1"),
            std::string::npos);
  EXPECT_NE(obj_error("v 0 0 0\nv 1 abc 0\nv 0 1 0\nf 1 2 3\n").find("line 2: vertex coordinate 2"),
            std::string::npos);
  EXPECT_NE(obj_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999999999\n")
                .find("line 4: face vertex '99999999999999999999'"),
            std::string::npos);
  EXPECT_NE(obj_error("v 0 0\nf 1 1 1\n").find("three coordinates"), std::string::npos);
  // A good file still reads, with texture and normal indices and negative (relative) indices.
  const ObjMesh mesh =
      read_obj_string("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 -1//1\n", "good.obj");
  ASSERT_EQ(mesh.triangles.size(), 1u);
  EXPECT_EQ(mesh.triangles[0][2], 2);
}

// Found by tests/fuzz/fuzz_obj_reader: tinyobjloader converted a vertex weight's joint id
// (`vw`) to int without a range check, undefined behaviour for 4.5e10. The reader now gives the
// library only the records it checked (v and f): the others are ignored, whatever they hold.
TEST(ObjReader, RecordsTumbleDoesNotUseAreNotParsed) {
  const ObjMesh mesh = read_obj_string(
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nvw 45555555555 1e300 x\nvt 1e999 nan\nvn q r s\n"
      "usemtl nowhere\nmtllib /etc/passwd\nl 1 99999999999\nf 1/1e99/zz 2 3\n",
      "others.obj");
  ASSERT_EQ(mesh.vertices.size(), 3u);
  ASSERT_EQ(mesh.triangles.size(), 1u);
  EXPECT_EQ(mesh.triangles[0][0], 0);
  EXPECT_EQ(mesh.triangles[0][2], 2);
}

// Found by tests/fuzz/fuzz_obj_reader: tinyobjloader reads 0000000e01001 (zero, written with an
// exponent past the double range) as NaN, where std::from_chars, which checked it, reads 0. The
// mesh takes the vertices tumble read, not the library's.
TEST(ObjReader, VerticesAreTheValuesTheCheckRead) {
  const ObjMesh mesh =
      read_obj_string("v 0000000e01001 1101 3\nv 1 0 0\nv 0 1 0.1\nf 1 2 3\n", "exponent.obj");
  ASSERT_EQ(mesh.vertices.size(), 3u);
  EXPECT_EQ(mesh.vertices[0], Vec3(0, 1101, 3));
  EXPECT_EQ(mesh.vertices[2], Vec3(0, 1, 0.1));
}

// The triangle limit (10,000,000 per mesh) counts a face of n corners as n - 2 triangles and
// stops at the line that passes it, before the mesh is built: 2,500,001 quads of four corners
// (two triangles each) pass it on their last line.
TEST(ObjReader, AMeshPastTheTriangleLimitIsRefusedAtTheLineThatPassesIt) {
  std::string text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n";
  const std::string hexagon = "f 1 2 4 3 1 2\n";  // six corners: four triangles
  text.reserve(text.size() + 2500001 * hexagon.size());
  for (int i = 0; i < 2500001; ++i)
    text += hexagon;
  try {
    (void)read_obj_string(text, "many.obj");
    FAIL() << "a mesh of 10,000,004 triangles was read";
  } catch (const ObjError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("line 2500005"), std::string::npos) << message;
    EXPECT_NE(message.find("more than 10,000,000 triangles"), std::string::npos) << message;
  }
}

TEST(ObjReader, RefusesPathsThatAreNotRegularFiles) {
  const std::filesystem::path fifo =
      std::filesystem::temp_directory_path() / ("tumble_obj_fifo_" + std::to_string(::getpid()));
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_THROW(read_obj_file(fifo), ObjError);
  std::filesystem::remove(fifo);
  EXPECT_THROW(read_obj_file("/dev/zero"), ObjError);
}

}  // namespace
}  // namespace tumble
