// read_polygon_soup (format dispatch and the checks common to all formats) and the helpers shared by
// the readers.
#include "spheremap/io/mesh_io.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <stdexcept>
#include <system_error>

#include <fmt/format.h>

#include "../util/read_all.hpp"
#include "readers.hpp"
#include "spheremap/error.hpp"

namespace spheremap {
namespace io_detail {

void fail(const std::string& file, const std::string& problem, const std::string& fix) {
  throw InputError(fmt::format("{}: {}; {}", file, problem, fix));
}

std::size_t line_number_at(std::string_view text, std::size_t offset) {
  offset = std::min(offset, text.size());
  return 1 +
         static_cast<std::size_t>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(offset), '\n'));
}

void require_text(std::string_view text, const std::string& file, std::string_view format_name,
                  std::string_view whole_file, std::size_t base_offset) {
  // Tab, newline, vertical tab, form feed, carriage return and DOS end-of-file (0x1A) occur in text
  // files; the other control characters only in binary data. Bytes >= 0x80 may be UTF-8 comments.
  const auto is_binary_byte = [](char c) {
    const auto byte = static_cast<unsigned char>(c);
    return byte < 0x09 || (byte > 0x0D && byte < 0x20 && byte != 0x1A) || byte == 0x7F;
  };
  const auto it = std::find_if(text.begin(), text.end(), is_binary_byte);
  if (it == text.end()) return;
  const std::size_t offset = base_offset + static_cast<std::size_t>(it - text.begin());
  fail(file,
       fmt::format("byte {} (line {}) is binary data (0x{:02X}), which a text {} file cannot contain", offset,
                   line_number_at(whole_file, offset), static_cast<unsigned char>(*it), format_name),
       fmt::format("check that the file really is a text {} file and was not truncated or corrupted", format_name));
}

std::string quote(std::string_view token) {
  constexpr std::size_t kMaxQuoted = 40;
  std::string shown(token.substr(0, kMaxQuoted));
  for (char& c : shown) {
    if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7F) c = '?';
  }
  return "'" + shown + (token.size() > kMaxQuoted ? "...'" : "'");
}

}  // namespace io_detail

namespace {

using io_detail::fail;

std::string lowercase(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

std::string read_whole_file(const std::filesystem::path& path, const std::string& file) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (!std::filesystem::exists(status)) fail(file, "the file does not exist", "check the path");
  if (std::filesystem::is_directory(status))
    fail(file, "this is a folder, not a mesh file", "give the path of a mesh file");

  const auto close_file = [](std::FILE* stream) { std::fclose(stream); };
  std::unique_ptr<std::FILE, decltype(close_file)> stream(std::fopen(path.c_str(), "rb"), close_file);
  if (!stream) {
    fail(file, fmt::format("the file cannot be opened ({})", std::strerror(errno)),
         "check that it is readable (permissions)");
  }
  const auto size_hint = std::filesystem::file_size(path, ec);
  std::string bytes = detail::read_all(stream.get(), ec ? 0 : static_cast<std::size_t>(size_hint));
  if (std::ferror(stream.get())) {
    fail(file, fmt::format("the file cannot be read ({})", std::strerror(errno)), "check the disk and the file");
  }
  return bytes;
}

// The checks every format needs once parsed. `first_index` is 1 for OBJ (which counts vertices from
// 1) and 0 otherwise: messages number vertices and faces the way the format does.
void check_soup(const PolygonSoup& soup, const std::string& file, int first_index) {
  const auto vertex_count = soup.positions.size();
  if (vertex_count > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max())) {
    fail(file, fmt::format("the mesh has {} vertices, more than the 2^31 - 1 supported", vertex_count),
         "simplify the mesh first");
  }
  for (std::size_t v = 0; v < vertex_count; ++v) {
    const Vec3& p = soup.positions[v];
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
      fail(file,
           fmt::format("vertex {} has a non-finite coordinate ({} {} {})", v + static_cast<std::size_t>(first_index),
                       p[0], p[1], p[2]),
           "fix or remove that vertex in the mesh editor that wrote the file");
    }
  }
  if (soup.faces.empty()) {
    fail(file, "the file has no faces (a point cloud?)", "give a surface mesh with triangles or polygons");
  }
  for (std::size_t f = 0; f < soup.faces.size(); ++f) {
    const auto& face = soup.faces[f];
    if (face.size() < 3) {
      fail(
          file,
          fmt::format("face {} has {} corner(s), fewer than 3", f + static_cast<std::size_t>(first_index), face.size()),
          "remove degenerate faces (points and edges) from the mesh");
    }
    for (const std::int32_t index : face) {
      if (index < 0 || static_cast<std::size_t>(index) >= vertex_count) {
        const std::string valid_range = vertex_count == 0
                                            ? std::string("the file has no vertices")
                                            : fmt::format("the vertices are numbered {} to {}", first_index,
                                                          static_cast<std::int64_t>(vertex_count) - 1 + first_index);
        fail(file,
             fmt::format("face {} refers to vertex {}, but {}", f + static_cast<std::size_t>(first_index),
                         static_cast<std::int64_t>(index) + first_index, valid_range),
             "the file is corrupt or truncated; re-export the mesh");
      }
    }
  }
}

}  // namespace

PolygonSoup read_polygon_soup(const std::filesystem::path& path) {
  const std::string file = path.string();
  const std::string extension = lowercase(path.extension().string());
  using Reader = PolygonSoup (*)(std::string_view, const std::string&);
  Reader reader = nullptr;
  int first_index = 0;
  if (extension == ".obj") {
    reader = io_detail::read_obj;
    first_index = 1;
  } else if (extension == ".off") {
    reader = io_detail::read_off;
  } else if (extension == ".ply") {
    reader = io_detail::read_ply;
  } else if (extension == ".stl") {
    reader = io_detail::read_stl;
  } else {
    fail(file,
         extension.empty() ? std::string("the file name has no extension")
                           : fmt::format("unknown mesh file extension '{}'", path.extension().string()),
         "give a .obj, .off, .ply or .stl file (any letter case)");
  }
  const std::string bytes = read_whole_file(path, file);
  if (bytes.empty()) fail(file, "the file is empty", "re-export the mesh");
  PolygonSoup soup = reader(bytes, file);
  check_soup(soup, file, first_index);
  return soup;
}

Mesh read_ply_mesh(const std::filesystem::path& path) {
  const std::string file = path.string();
  const std::string bytes = read_whole_file(path, file);
  if (bytes.empty()) fail(file, "the file is empty", "write it again");
  io_detail::PlyVertexAttributes attributes;
  PolygonSoup soup = io_detail::read_ply(bytes, file, &attributes);
  check_soup(soup, file, 0);
  Mesh mesh;
  mesh.positions = std::move(soup.positions);
  mesh.triangles.reserve(soup.faces.size());
  for (std::size_t f = 0; f < soup.faces.size(); ++f) {
    if (soup.faces[f].size() != 3)
      fail(file, fmt::format("face {} has {} corners, not 3", f, soup.faces[f].size()),
           "give a PLY file that spheremap wrote (surface.ply or sphere.ply)");
    mesh.triangles.push_back({soup.faces[f][0], soup.faces[f][1], soup.faces[f][2]});
  }
  mesh.real_attributes = std::move(attributes.real);
  mesh.integer_attributes = std::move(attributes.integer);
  mesh.text_attributes = std::move(attributes.text);
  return mesh;
}

}  // namespace spheremap
