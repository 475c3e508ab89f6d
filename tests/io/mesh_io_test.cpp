// Tests of read_polygon_soup, write_ply and write_file_atomically.
#include "spheremap/io/mesh_io.hpp"
#include "spheremap/attributes.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "../test_support.hpp"
#include "spheremap/error.hpp"
#include "spheremap/io/atomic_file.hpp"
#include "spheremap/io/ply.hpp"

namespace spheremap {
namespace {

namespace fs = std::filesystem;

using Faces = std::vector<std::vector<std::int32_t>>;
using testing_support::slurp;

/// A fresh folder per test, removed afterwards.
class MeshIoTest : public testing_support::FolderTest {
 protected:
  /// Expects read_polygon_soup to throw InputError whose message names the file and contains `fragment`.
  static void expect_input_error(const fs::path& path, const std::string& fragment) {
    try {
      read_polygon_soup(path);
      ADD_FAILURE() << path << ": expected InputError containing \"" << fragment << "\"";
    } catch (const InputError& error) {
      const std::string message = error.what();
      EXPECT_NE(message.find(path.filename().string()), std::string::npos) << message;
      EXPECT_NE(message.find(fragment), std::string::npos) << "expected \"" << fragment << "\" in: " << message;
    }
  }
};

class ObjReader : public MeshIoTest {};
class OffReader : public MeshIoTest {};
class PlyReader : public MeshIoTest {};
class StlReader : public MeshIoTest {};
class PlyWriter : public MeshIoTest {};
class MeshIoErrors : public MeshIoTest {};

// Builders for binary test files.
template <typename T>
void append(std::string& out, T value, std::endian order) {
  std::array<char, sizeof(T)> bytes;
  std::memcpy(bytes.data(), &value, sizeof(T));
  if (order != std::endian::native) std::reverse(bytes.begin(), bytes.end());
  out.append(bytes.data(), bytes.size());
}

std::string binary_stl(const std::string& header_start, const std::vector<std::array<float, 9>>& triangles) {
  std::string bytes = header_start;
  bytes.resize(80, ' ');
  append(bytes, static_cast<std::uint32_t>(triangles.size()), std::endian::little);
  for (const auto& corners : triangles) {
    for (int i = 0; i < 3; ++i) append(bytes, 0.0F, std::endian::little);  // normal
    for (const float value : corners) append(bytes, value, std::endian::little);
    append(bytes, std::uint16_t{0}, std::endian::little);
  }
  return bytes;
}

Mesh tetrahedron_with_attributes() {
  Mesh mesh;
  // Values that a lossy writer would change: thirds, tiny, huge, subnormal, negative zero.
  mesh.positions = {{1.0 / 3.0, -0.0, 1e-300},
                    {0.1, 2.0 / 3.0, std::numeric_limits<double>::max()},
                    {std::numeric_limits<double>::denorm_min(), -1.0 / 7.0, 12345.678901234567},
                    {-std::numeric_limits<double>::min(), std::nextafter(1.0, 2.0), -2.5}};
  mesh.triangles = {{0, 1, 2}, {0, 3, 1}, {1, 3, 2}, {2, 3, 0}};
  mesh.real_attributes["u"] = {0.1, 0.2, 0.3, 0.4};
  mesh.real_attributes["distortion"] = {1.0 / 3.0, 1e-310, -0.0, 1e308};
  mesh.integer_attributes["label"] = {-1, 0, 2147483647, -2147483647 - 1};
  return mesh;
}

void expect_positions_bit_exact(const std::vector<Vec3>& actual, const std::vector<Vec3>& expected) {
  ASSERT_EQ(actual.size(), expected.size());
  for (std::size_t v = 0; v < actual.size(); ++v) {
    for (std::size_t axis = 0; axis < 3; ++axis) {
      EXPECT_EQ(std::bit_cast<std::uint64_t>(actual[v][axis]), std::bit_cast<std::uint64_t>(expected[v][axis]))
          << "vertex " << v << " axis " << axis << ": " << actual[v][axis] << " vs " << expected[v][axis];
    }
  }
}

Faces faces_of(const Mesh& mesh) {
  Faces faces;
  for (const Triangle& t : mesh.triangles) faces.push_back({t[0], t[1], t[2]});
  return faces;
}

// ---------------------------------------------------------------------------------------------
// Writing PLY and reading it back.

TEST_F(PlyWriter, BinaryRoundTripIsBitExact) {
  const Mesh mesh = tetrahedron_with_attributes();
  const fs::path path = folder_ / "round.ply";
  write_ply(path, mesh);
  const PolygonSoup soup = read_polygon_soup(path);
  expect_positions_bit_exact(soup.positions, mesh.positions);
  EXPECT_EQ(soup.faces, faces_of(mesh));
}

TEST_F(PlyWriter, AsciiRoundTripIsBitExact) {
  const Mesh mesh = tetrahedron_with_attributes();
  const fs::path path = folder_ / "round.ply";
  write_ply(path, mesh, {.ascii = true});
  const PolygonSoup soup = read_polygon_soup(path);
  expect_positions_bit_exact(soup.positions, mesh.positions);
  EXPECT_EQ(soup.faces, faces_of(mesh));
}

TEST_F(PlyWriter, HeaderListsRealAttributesThenIntegerAttributesInNameOrder) {
  const fs::path path = folder_ / "header.ply";
  write_ply(path, tetrahedron_with_attributes());
  const std::string expected_header =
      "ply\n"
      "format binary_little_endian 1.0\n"
      "comment written by spheremap\n"
      "element vertex 4\n"
      "property double x\n"
      "property double y\n"
      "property double z\n"
      "property double distortion\n"
      "property double u\n"
      "property int label\n"
      "element face 4\n"
      "property list uchar int vertex_indices\n"
      "end_header\n";
  const std::string bytes = slurp(path);
  EXPECT_EQ(bytes.substr(0, expected_header.size()), expected_header);
  const std::size_t vertex_bytes = 4 * (5 * 8 + 4);
  const std::size_t face_bytes = 4 * (1 + 3 * 4);
  EXPECT_EQ(bytes.size(), expected_header.size() + vertex_bytes + face_bytes);
}

TEST_F(PlyWriter, TextAttributesAreByteListsThatReadersSkip) {
  Mesh mesh = tetrahedron_with_attributes();
  mesh.text_attributes[attributes::kAtomName] = TextAttribute{{"CA", "", "OXT"}, {0, 2, 1, 0}};
  const std::string header_line = std::string("property list uchar uchar ") + attributes::kAtomName + "\n";
  for (const bool ascii : {false, true}) {
    const fs::path path = folder_ / (ascii ? "text-ascii.ply" : "text.ply");
    write_ply(path, mesh, {.ascii = ascii});
    const std::string bytes = slurp(path);
    EXPECT_NE(bytes.find("property int label\n" + header_line + "element face 4\n"), std::string::npos);
    if (ascii) {
      EXPECT_NE(bytes.find(" 2 67 65\n"), std::string::npos);     // "CA"
      EXPECT_NE(bytes.find(" 3 79 88 84\n"), std::string::npos);  // "OXT"
      EXPECT_NE(bytes.find(" 0\n"), std::string::npos);           // ""
    } else {
      EXPECT_NE(bytes.find(std::string("\x03OXT", 4)), std::string::npos);
      const std::size_t header_end = bytes.find("end_header\n") + 11;
      const std::size_t vertex_bytes = 4 * (5 * 8 + 4) + (1 + 2) * 2 + (1 + 3) + 1;
      EXPECT_EQ(bytes.size(), header_end + vertex_bytes + 4 * (1 + 3 * 4));
    }
    // Our reader (and any PLY reader) steps over list properties of vertices.
    const PolygonSoup soup = read_polygon_soup(path);
    expect_positions_bit_exact(soup.positions, mesh.positions);
    EXPECT_EQ(soup.faces, faces_of(mesh));
  }
  mesh.text_attributes[attributes::kAtomName].codes[0] = 7;
  EXPECT_THROW(write_ply(folder_ / "bad.ply", mesh), std::invalid_argument);
}

TEST_F(PlyWriter, AsciiWritesSeventeenDigitsAndPlainIntegers) {
  Mesh mesh;
  mesh.positions = {{0.1, 1.0, -0.0}, {0, 1, 0}, {0, 0, 1}};
  mesh.triangles = {{0, 1, 2}};
  mesh.integer_attributes["label"] = {7, -3, 0};
  const fs::path path = folder_ / "ascii.ply";
  write_ply(path, mesh, {.ascii = true});
  const std::string bytes = slurp(path);
  const std::string body = bytes.substr(bytes.find("end_header\n") + 11);
  EXPECT_EQ(body, "0.10000000000000001 1 -0 7\n0 1 0 -3\n0 0 1 0\n3 0 1 2\n");
}

TEST_F(PlyWriter, OutputIsDeterministic) {
  const Mesh mesh = tetrahedron_with_attributes();
  for (const bool ascii : {false, true}) {
    write_ply(folder_ / "a.ply", mesh, {.ascii = ascii});
    write_ply(folder_ / "b.ply", mesh, {.ascii = ascii});
    EXPECT_EQ(slurp(folder_ / "a.ply"), slurp(folder_ / "b.ply"));
  }
}

TEST_F(PlyWriter, AtomicWriteLeavesOnlyTheTargetFile) {
  write(std::string("old.ply"), "previous contents");
  write_ply(folder_ / "old.ply", tetrahedron_with_attributes());
  write_file_atomically(folder_ / "notes.txt", "hello\n");
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(folder_)) names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"notes.txt", "old.ply"}));
  EXPECT_EQ(slurp(folder_ / "notes.txt"), "hello\n");
  EXPECT_EQ(read_polygon_soup(folder_ / "old.ply").positions.size(), 4U);
}

TEST_F(PlyWriter, FilesOfManyMegabytesAreWrittenInPiecesWithNothingLostOrRepeated) {
  // 200,000 vertices with varying text lengths: several megabytes, binary and ASCII, so that pieces end
  // mid-vertex, mid-text and mid-face.
  Mesh mesh;
  const std::int32_t n = 200'000;
  for (std::int32_t v = 0; v < n; ++v) mesh.positions.push_back({v / 3.0, -v / 7.0, std::sqrt(static_cast<double>(v))});
  for (std::int32_t v = 0; v + 2 < n; v += 3) mesh.triangles.push_back({v, v + 1, v + 2});
  mesh.integer_attributes["label"].resize(static_cast<std::size_t>(n));
  mesh.text_attributes["name"] = TextAttribute{{"", "N", "CA", "OXT", "HE21"}, {}};
  for (std::int32_t v = 0; v < n; ++v) {
    mesh.integer_attributes["label"][static_cast<std::size_t>(v)] = v * 7 - 5;
    mesh.text_attributes["name"].codes.push_back(v % 5);
  }
  for (const bool ascii : {false, true}) {
    const fs::path path = folder_ / (ascii ? "large-ascii.ply" : "large.ply");
    write_ply(path, mesh, {.ascii = ascii});
    const std::string bytes = slurp(path);
    EXPECT_GT(bytes.size(), std::size_t{3} << 20);
    const std::size_t body = bytes.find("end_header\n") + 11;
    if (!ascii) {
      // Per vertex: x y z, the label, a length byte and the text (0 to 4 bytes, 2 on average); per face 13.
      EXPECT_EQ(bytes.size(), body + static_cast<std::size_t>(n) * (3 * 8 + 4 + 1 + 2) + mesh.triangles.size() * 13);
    } else {
      EXPECT_EQ(
          static_cast<std::size_t>(std::count(bytes.begin() + static_cast<std::ptrdiff_t>(body), bytes.end(), '\n')),
          static_cast<std::size_t>(n) + mesh.triangles.size());
    }
    const PolygonSoup soup = read_polygon_soup(path);
    expect_positions_bit_exact(soup.positions, mesh.positions);
    EXPECT_EQ(soup.faces, faces_of(mesh));
  }
}

TEST_F(PlyWriter, AnAtomicFileLeftUncommittedLeavesTheTargetAsItWas) {
  write(std::string("kept.txt"), "previous contents");
  {
    AtomicFile file(folder_ / "kept.txt");
    file.append("new contents, not committed");
  }
  {
    AtomicFile file(folder_ / "new.txt");
    file.append("half");
  }
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(folder_)) names.push_back(entry.path().filename().string());
  EXPECT_EQ(names, (std::vector<std::string>{"kept.txt"}));
  EXPECT_EQ(slurp(folder_ / "kept.txt"), "previous contents");
  AtomicFile file(folder_ / "kept.txt");
  file.append("new ");
  file.append("contents");
  file.commit();
  EXPECT_EQ(slurp(folder_ / "kept.txt"), "new contents");
}

TEST_F(PlyWriter, UnwritableTargetThrowsInputErrorAndLeavesNoTemporaryFile) {
  const fs::path path = folder_ / "missing_folder" / "out.ply";
  EXPECT_THROW(write_ply(path, tetrahedron_with_attributes()), InputError);
  // A folder where the file should go: the temporary file is written, the rename fails.
  fs::create_directories(folder_ / "taken.ply" / "child");
  try {
    write_file_atomically(folder_ / "taken.ply", "text");
    ADD_FAILURE() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("taken.ply"), std::string::npos) << error.what();
  }
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(folder_)) names.push_back(entry.path().filename().string());
  EXPECT_EQ(names, (std::vector<std::string>{"taken.ply"}));
}

// ---------------------------------------------------------------------------------------------
// OBJ

TEST_F(ObjReader, ReadsPolygonsAllCornerFormsAndSkipsOtherLines) {
  const fs::path path = write("mixed.obj",
                              "# comment\n"
                              "mtllib x.mtl\n"
                              "o thing\n"
                              "v 0 0 0\n"
                              "v 1 0 0 1.0\n"  // optional w
                              "v +1 1 0\n"
                              "v 0 1.5e0 -0\n"
                              "vt 0.5 0.5\n"
                              "vn 0 0 1\n"
                              "usemtl m\n"
                              "s off\n"
                              "f 1 2 3 4\n"
                              "f 1/1 2/1 3/1\n"
                              "f 1//1 3//1 4//1\n"
                              "\tf   2/1/1 3/1/1   4/1/1  \n"
                              "l 1 2\n");
  const PolygonSoup soup = read_polygon_soup(path);
  ASSERT_EQ(soup.positions.size(), 4U);
  EXPECT_EQ(soup.positions[2], (Vec3{1, 1, 0}));
  EXPECT_EQ(soup.positions[3], (Vec3{0, 1.5, 0}));
  EXPECT_EQ(soup.faces, (Faces{{0, 1, 2, 3}, {0, 1, 2}, {0, 2, 3}, {1, 2, 3}}));
}

TEST_F(ObjReader, ResolvesNegativeIndicesRelativeToTheVerticesReadSoFar) {
  const fs::path path = write("relative.obj",
                              "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
                              "f -3 -2 -1\n"
                              "v 0 0 1\n"
                              "f -4/-1/-1 -1/-1/-1 -3/-1/-1\n");
  const PolygonSoup soup = read_polygon_soup(path);
  EXPECT_EQ(soup.faces, (Faces{{0, 1, 2}, {0, 3, 1}}));
}

TEST_F(ObjReader, ReadsCrlfFilesAndUppercaseExtensions) {
  const fs::path path = write("WINDOWS.OBJ", "v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 3\r\n");
  const PolygonSoup soup = read_polygon_soup(path);
  EXPECT_EQ(soup.positions.size(), 3U);
  EXPECT_EQ(soup.faces, (Faces{{0, 1, 2}}));
}

TEST_F(ObjReader, RejectsMalformedLines) {
  expect_input_error(write("short.obj", "v 0 0\nf 1 1 1\n"), "line 1: a vertex needs 3 coordinates");
  expect_input_error(write("word.obj", "v 0 0 zero\n"), "line 1: expected a coordinate but found 'zero'");
  expect_input_error(write("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n"), "refers to vertex 0");
  expect_input_error(write("behind.obj", "v 0 0 0\nf -1 -2 -3\n"), "face 1 refers to vertex -2");
  expect_input_error(write("corner.obj", "v 0 0 0\nf 1 a 1\n"), "face 1 has the corner 'a'");
  expect_input_error(write("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 9\n"),
                     "face 2 refers to vertex 9, but the vertices are numbered 1 to 3");
  expect_input_error(write("edge.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n"), "face 1 has 2 corner(s)");
}

// ---------------------------------------------------------------------------------------------
// OFF

TEST_F(OffReader, ReadsCommentsQuadsAndFaceColours) {
  const fs::path path = write("cube_part.off",
                              "OFF # keyword\n"
                              "# a comment line\n"
                              "\n"
                              "5 2 0\n"
                              "0 0 0\n"
                              "1 0 0 # trailing comment\n"
                              "1 1 0\n"
                              "0 1 0\n"
                              "0.5 0.5 1\n"
                              "4 0 1 2 3 255 0 0\n"
                              "3 0 1 4 0.5 0.5 0.5 1.0\n");
  const PolygonSoup soup = read_polygon_soup(path);
  EXPECT_EQ(soup.positions.size(), 5U);
  EXPECT_EQ(soup.positions[4], (Vec3{0.5, 0.5, 1}));
  EXPECT_EQ(soup.faces, (Faces{{0, 1, 2, 3}, {0, 1, 4}}));
}

TEST_F(OffReader, AcceptsHeaderVariants) {
  const std::string body = "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  for (const std::string header : {"OFF 3 1 0\n", "OFF\n3 1\n", "3 1 0\n", "COFF\n3 1 3\n", "OFF\r\n3 1 0\r\n"}) {
    std::string bytes = header + body;
    if (header == "COFF\n3 1 3\n") bytes = header + "0 0 0 1 1 1 1\n1 0 0 1 1 1 1\n0 1 0 1 1 1 1\n3 0 1 2\n";
    const PolygonSoup soup = read_polygon_soup(write("variant.off", bytes));
    EXPECT_EQ(soup.faces, (Faces{{0, 1, 2}})) << header;
    EXPECT_EQ(soup.positions.size(), 3U) << header;
  }
}

TEST_F(OffReader, ReportsTruncationAndBadData) {
  expect_input_error(write("short.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n"),
                     "the file ends after 2 of 4 vertices (truncated?); re-export the mesh");
  expect_input_error(write("fewfaces.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
                     "the file ends after 1 of 2 faces");
  expect_input_error(write("corners.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2\n"), "index 4 is missing");
  expect_input_error(write("range.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"),
                     "face 0 refers to vertex 3, but the vertices are numbered 0 to 2");
  expect_input_error(write("header.off", "OFF\nthree 1 0\n"), "bad OFF header");
  expect_input_error(write("notoff.off", "PLY\n3 1 0\n"), "not 'OFF'");
  expect_input_error(write("four.off", "4OFF\n3 1 0\n"), "not supported");
}

// ---------------------------------------------------------------------------------------------
// PLY

TEST_F(PlyReader, ReadsAsciiWithExtraPropertiesAndElements) {
  const fs::path path = write("extra.ply",
                              "ply\r\n"
                              "format ascii 1.0\r\n"
                              "comment made by hand\r\n"
                              "obj_info nothing\r\n"
                              "element vertex 4\r\n"
                              "property uchar red\r\n"
                              "property float32 x\r\n"
                              "property list uchar float texcoords\r\n"
                              "property double y\r\n"
                              "property int z\r\n"
                              "element face 2\r\n"
                              "property uchar flags\r\n"
                              "property list int uint vertex_index\r\n"
                              "element edge 1\r\n"
                              "property list uchar int vertex_indices\r\n"
                              "end_header\r\n"
                              "255 0 2 0.5 0.5 0 0\r\n"
                              "255 1 0 0 0\r\n"
                              "255 1 3 1 2 3 1 0\r\n"
                              "0 0 0 1 1\r\n"
                              "7 4 0 1 2 3\r\n"
                              "7 3 0 2 3\r\n"
                              "2 0 1\r\n");
  const PolygonSoup soup = read_polygon_soup(path);
  EXPECT_EQ(soup.positions, (std::vector<Vec3>{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 1}}));
  EXPECT_EQ(soup.faces, (Faces{{0, 1, 2, 3}, {0, 2, 3}}));
}

TEST_F(PlyReader, ReadsBigEndianWithExtraPropertiesAndAnExtraElement) {
  constexpr auto big = std::endian::big;
  std::string bytes =
      "ply\n"
      "format binary_big_endian 1.0\n"
      "element material 2\n"
      "property list ushort double coefficients\n"
      "property short id\n"
      "element vertex 3\n"
      "property double x\n"
      "property list uint8 int16 neighbours\n"
      "property float y\n"
      "property char flag\n"
      "property ushort z\n"
      "property float64 confidence\n"
      "element face 1\n"
      "property list uchar uint vertex_indices\n"
      "property list uint char extra\n"
      "end_header\n";
  // material: lists of 2 and 0 coefficients
  append(bytes, std::uint16_t{2}, big);
  append(bytes, 1.5, big);
  append(bytes, 2.5, big);
  append(bytes, std::int16_t{-4}, big);
  append(bytes, std::uint16_t{0}, big);
  append(bytes, std::int16_t{9}, big);
  const std::array<Vec3, 3> positions = {{{0.25, -1.0, 3}, {1e10, 0.5, 65535}, {-7.0, 2.0, 0}}};
  for (const Vec3& p : positions) {
    append(bytes, p[0], big);
    append(bytes, std::uint8_t{2}, big);
    append(bytes, std::int16_t{-1}, big);
    append(bytes, std::int16_t{300}, big);
    append(bytes, static_cast<float>(p[1]), big);
    append(bytes, std::int8_t{-5}, big);
    append(bytes, static_cast<std::uint16_t>(p[2]), big);
    append(bytes, 0.99, big);
  }
  append(bytes, std::uint8_t{3}, big);
  for (const std::uint32_t index : {2U, 0U, 1U}) append(bytes, index, big);
  append(bytes, std::uint32_t{1}, big);
  append(bytes, std::int8_t{42}, big);

  const PolygonSoup soup = read_polygon_soup(write("big.ply", bytes));
  EXPECT_EQ(soup.positions, (std::vector<Vec3>{positions.begin(), positions.end()}));
  EXPECT_EQ(soup.faces, (Faces{{2, 0, 1}}));
}

TEST_F(PlyReader, ReadsLittleEndianFloatVerticesAndSizedTypeNames) {
  constexpr auto little = std::endian::little;
  std::string bytes =
      "ply\nformat binary_little_endian 1.0\n"
      "element vertex 3\nproperty float32 x\nproperty int8 y\nproperty uint32 z\n"
      "element face 1\nproperty list int32 int32 vertex_indices\nend_header\n";
  const std::array<Vec3, 3> positions = {{{0.5, -128, 4000000000.0}, {1, 127, 0}, {-2, 0, 1}}};
  for (const Vec3& p : positions) {
    append(bytes, static_cast<float>(p[0]), little);
    append(bytes, static_cast<std::int8_t>(p[1]), little);
    append(bytes, static_cast<std::uint32_t>(p[2]), little);
  }
  append(bytes, std::int32_t{3}, little);
  for (const std::int32_t index : {0, 1, 2}) append(bytes, index, little);
  const PolygonSoup soup = read_polygon_soup(write("little.ply", bytes));
  EXPECT_EQ(soup.positions, (std::vector<Vec3>{positions.begin(), positions.end()}));
  EXPECT_EQ(soup.faces, (Faces{{0, 1, 2}}));
}

TEST_F(PlyReader, ReportsTruncatedBinaryFiles) {
  Mesh mesh = tetrahedron_with_attributes();
  write_ply(folder_ / "whole.ply", mesh);
  const std::string bytes = slurp(folder_ / "whole.ply");
  const std::size_t header_size = bytes.find("end_header\n") + 11;
  const std::size_t vertex_bytes = 5 * 8 + 4;
  expect_input_error(write("cut_vertices.ply", bytes.substr(0, header_size + 2 * vertex_bytes + 5)),
                     "the file ends after 2 of 4 vertices (truncated?); re-export the mesh");
  expect_input_error(write("cut_faces.ply", bytes.substr(0, bytes.size() - 1)), "the file ends after 3 of 4 faces");
  expect_input_error(write("cut_header.ply", bytes.substr(0, header_size - 11)), "no 'end_header'");
}

TEST_F(PlyReader, SurvivesHeadersThatClaimHugeCounts) {
  expect_input_error(write("huge.ply",
                           "ply\nformat binary_little_endian 1.0\nelement vertex 2000000000\nproperty float x\n"
                           "property float y\nproperty float z\nelement face 1\n"
                           "property list uchar int vertex_indices\nend_header\n0123456789"),
                     "the file ends after 0 of 2000000000 vertices");
  expect_input_error(write("hugelist.ply",
                           "ply\nformat binary_little_endian 1.0\nelement vertex 0\nproperty float x\n"
                           "property float y\nproperty float z\nelement face 1\n"
                           "property list uint int vertex_indices\nend_header\n\xff\xff\xff\xff"),
                     "the file ends after 0 of 1 faces");
  expect_input_error(write("toomany.ply",
                           "ply\nformat ascii 1.0\nelement vertex 99999999999\nproperty float x\n"
                           "property float y\nproperty float z\nend_header\n"),
                     "more than the 2^31 - 1 supported");
}

TEST_F(PlyReader, ReportsIndexOutOfRangeWithFaceAndIndex) {
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  expect_input_error(write("range.ply", header + "3 0 1 3\n"),
                     "face 1 refers to vertex 3, but the file has 3 vertices");
  expect_input_error(write("negative.ply", header + "3 0 -1 2\n"), "face 1 refers to vertex -1");
  expect_input_error(write("text.ply", header + "3 0 one 2\n"), "line 14: expected an integer but found 'one'");
}

TEST_F(PlyReader, ReportsBadHeaders) {
  expect_input_error(write("notply.ply", "solid cube\nendsolid\n"), "does not start with the line 'ply'");
  expect_input_error(write("format.ply", "ply\nformat binary_middle_endian 1.0\nend_header\n"), "unknown format");
  expect_input_error(write("noformat.ply", "ply\nelement vertex 0\nend_header\n"), "no 'format' line");
  expect_input_error(write("novertex.ply", "ply\nformat ascii 1.0\nelement face 0\nend_header\n"),
                     "no 'element vertex'");
  expect_input_error(write("noz.ply",
                           "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n"
                           "end_header\n"),
                     "no 'z' property");
  expect_input_error(write("type.ply", "ply\nformat ascii 1.0\nelement vertex 0\nproperty float128 x\nend_header\n"),
                     "unknown property type 'float128'");
  expect_input_error(write("noindices.ply",
                           "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\n"
                           "property float y\nproperty float z\nelement face 0\nproperty int a\n"
                           "end_header\n"),
                     "no 'vertex_indices' list property");
  expect_input_error(write("pointcloud.ply",
                           "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                           "property float y\nproperty float z\nend_header\n0 0 0\n"),
                     "no faces");
}

// ---------------------------------------------------------------------------------------------
// STL

TEST_F(StlReader, ReadsAsciiFacetsWithoutSharingVertices) {
  const fs::path path = write("two.stl",
                              "solid two facets\n"
                              "  facet normal 0 0 1\n"
                              "    outer loop\n"
                              "      vertex 0 0 0\n"
                              "      vertex 1 0 0\n"
                              "      vertex 0 1 0\n"
                              "    endloop\n"
                              "  endfacet\n"
                              "  facet normal 0 0 -1\n"
                              "    outer loop\n"
                              "      vertex 0 0 0\n"
                              "      vertex 0 1 0\n"
                              "      vertex 1e0 1 -2.5E-1\n"
                              "    endloop\n"
                              "  endfacet\n"
                              "endsolid two facets\n");
  const PolygonSoup soup = read_polygon_soup(path);
  ASSERT_EQ(soup.positions.size(), 6U);
  EXPECT_EQ(soup.positions[5], (Vec3{1, 1, -0.25}));
  EXPECT_EQ(soup.faces, (Faces{{0, 1, 2}, {3, 4, 5}}));
}

TEST_F(StlReader, ReadsBinaryFilesEvenWhenTheHeaderStartsWithSolid) {
  const std::vector<std::array<float, 9>> triangles = {{0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 0, 0, 0, 1, 0, 0.5F, 0.5F, 1}};
  for (const std::string header : {"solid exported by a careless tool", "binary"}) {
    const PolygonSoup soup = read_polygon_soup(write("binary.STL", binary_stl(header, triangles)));
    ASSERT_EQ(soup.positions.size(), 6U) << header;
    EXPECT_EQ(soup.positions[5], (Vec3{0.5, 0.5, 1})) << header;
    EXPECT_EQ(soup.faces, (Faces{{0, 1, 2}, {3, 4, 5}})) << header;
  }
}

TEST_F(StlReader, ReportsTruncatedAndMalformedFiles) {
  const std::vector<std::array<float, 9>> triangles(3, {0, 0, 0, 1, 0, 0, 0, 1, 0});
  const std::string binary = binary_stl("binary", triangles);
  expect_input_error(write("cut.stl", binary.substr(0, binary.size() - 10)),
                     "the file ends after 2 of 3 triangles (truncated?)");
  const std::string solid_binary = binary_stl("solid", triangles);
  expect_input_error(write("cut_solid.stl", solid_binary.substr(0, solid_binary.size() - 10)), "binary data");
  expect_input_error(write("tiny.stl", "abc"), "too short");
  expect_input_error(write("open.stl", "solid a\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"),
                     "ends inside facet 0");
  expect_input_error(write("word.stl", "solid a\nfacet normal 0 0 1\nouter loop\nvertex 0 0 zero\n"),
                     "line 4: 'vertex' needs 3 numbers");
  expect_input_error(write("empty.stl", binary_stl("binary", {})), "no faces");
}

// ---------------------------------------------------------------------------------------------
// Errors common to all formats

TEST_F(MeshIoErrors, MissingFileUnknownExtensionFolderAndEmptyFile) {
  expect_input_error(folder_ / "absent.obj", "does not exist");
  expect_input_error(write("mesh.3ds", "data"), "unknown mesh file extension '.3ds'; give a .obj, .off, .ply or .stl");
  expect_input_error(write("mesh", "data"), "no extension");
  fs::create_directories(folder_ / "folder.obj");
  expect_input_error(folder_ / "folder.obj", "folder");
  expect_input_error(write("empty.off", ""), "empty");
}

TEST_F(MeshIoErrors, UnreadableFile) {
  const fs::path path = write("locked.obj", "v 0 0 0\n");
  fs::permissions(path, fs::perms::none);
  if (std::ifstream(path).good()) GTEST_SKIP() << "running as root: permissions are not enforced";
  expect_input_error(path, "cannot be opened");
}

TEST_F(MeshIoErrors, NonFiniteCoordinates) {
  expect_input_error(write("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"),
                     "vertex 2 has a non-finite coordinate (nan 0 0)");
  expect_input_error(write("inf.off", "OFF\n3 1 0\n0 0 0\n1 0 inf\n0 1 0\n3 0 1 2\n"),
                     "vertex 1 has a non-finite coordinate");
  std::string ply =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
      "property double z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  for (int v = 0; v < 3; ++v) {
    for (int axis = 0; axis < 3; ++axis) {
      append(ply, v == 2 && axis == 1 ? -std::numeric_limits<double>::infinity() : 0.0, std::endian::little);
    }
  }
  append(ply, std::uint8_t{3}, std::endian::little);
  for (const std::int32_t index : {0, 1, 2}) append(ply, index, std::endian::little);
  expect_input_error(write("inf.ply", ply), "vertex 2 has a non-finite coordinate (0 -inf 0)");
}

TEST_F(MeshIoErrors, ZeroFaces) {
  expect_input_error(write("points.obj", "v 0 0 0\nv 1 0 0\n"), "no faces");
  expect_input_error(write("points.off", "OFF\n1 0 0\n0 0 0\n"), "no faces");
}

TEST_F(MeshIoErrors, BinaryDataInTextFormats) {
  std::string garbage = "v 0 0 0\nv 1 0 0\n";
  garbage += std::string("\x00\x01\x02\xff", 4);
  expect_input_error(write("binary.obj", garbage), "byte 16 (line 3) is binary data (0x00)");
  expect_input_error(write("binary.off", "OFF\n3 1 0\n" + garbage), "binary data");
  expect_input_error(write("binary.ply",
                           "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                           "property float y\nproperty float z\nend_header\n" +
                               garbage),
                     "binary data");
}

// Cutting and corrupting valid files anywhere must give a soup or an InputError, never a crash
// (run under -fsanitize=address,undefined to catch out-of-bounds reads).
TEST_F(MeshIoErrors, CorruptedFilesNeverCrash) {
  Mesh mesh = tetrahedron_with_attributes();
  write_ply(folder_ / "binary.ply", mesh);
  write_ply(folder_ / "ascii.ply", mesh, {.ascii = true});
  const std::map<std::string, std::string> originals = {
      {"binary.ply", slurp(folder_ / "binary.ply")},
      {"ascii.ply", slurp(folder_ / "ascii.ply")},
      {"mesh.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf -1/2/3 -2//1 -3\nf 1 2 3 4\n"},
      {"mesh.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n4 0 1 2 3 255 0 0\n"},
      {"mesh.stl", binary_stl("solid", {{0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 0, 0, 1, 0, 0, 0, 0, 1}})},
      {"text.stl",
       "solid a\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\n"
       "endfacet\nendsolid a\n"},
  };
  std::mt19937 random(12345);
  for (const auto& [name, original] : originals) {
    for (int trial = 0; trial < 120; ++trial) {
      std::string bytes = original;
      if (trial % 3 == 0) {
        bytes.resize(random() % bytes.size());
      } else {
        const int flips = 1 + static_cast<int>(random() % 4);
        for (int i = 0; i < flips; ++i) bytes[random() % bytes.size()] = static_cast<char>(random());
      }
      try {
        const PolygonSoup soup = read_polygon_soup(write(name, bytes));
        for (const auto& face : soup.faces) {
          for (const std::int32_t index : face) {
            ASSERT_GE(index, 0);
            ASSERT_LT(static_cast<std::size_t>(index), soup.positions.size());
          }
        }
      } catch (const InputError& error) {
        EXPECT_NE(std::string(error.what()).find(name), std::string::npos) << error.what();
      }
    }
  }
}

// ---------------------------------------------------------------------------------------------
// The shared data set (../shared/data/meshes).

struct KnownCounts {
  std::size_t vertices;
  std::size_t faces;
};

TEST(DataMeshIo, ReadsEveryMeshOfTheSharedDataSet) {
  const fs::path folder = fs::path(SPHEREMAP_SHARED_DATA_DIR) / "meshes";
  if (!fs::is_directory(folder)) GTEST_SKIP() << "../shared/data not found: " << folder;
  const std::map<std::string, KnownCounts> known = {
      {"ajc_horse.ply", {48485, 96966}},
      {"gc_spot.ply", {2930, 5856}},
      {"libigl_horse_quad.obj", {2400, 2398}},
      {"bff_box.obj", {26, 36}},
      {"libigl_decimated-knight.off", {502, 1000}},
  };
  std::size_t meshes_read = 0;
  std::size_t known_checked = 0;
  for (const auto& entry : fs::directory_iterator(folder)) {
    std::string extension = entry.path().extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (extension != ".obj" && extension != ".off" && extension != ".ply" && extension != ".stl") continue;
    const std::string name = entry.path().filename().string();
    PolygonSoup soup;
    ASSERT_NO_THROW(soup = read_polygon_soup(entry.path())) << name;
    EXPECT_FALSE(soup.positions.empty()) << name;
    EXPECT_FALSE(soup.faces.empty()) << name;
    ++meshes_read;
    if (const auto it = known.find(name); it != known.end()) {
      EXPECT_EQ(soup.positions.size(), it->second.vertices) << name;
      EXPECT_EQ(soup.faces.size(), it->second.faces) << name;
      ++known_checked;
    }
  }
  EXPECT_GT(meshes_read, 0U);
  EXPECT_EQ(known_checked, known.size()) << "some known meshes are missing from " << folder;
}

}  // namespace
}  // namespace spheremap
