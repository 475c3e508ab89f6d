// write_ply: the file is built in pieces of about a megabyte (the bytes do not depend on the pieces),
// each appended to a temporary file that is renamed over the target when complete (AtomicFile).
#include "spheremap/io/ply.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <stdexcept>

#include <fmt/format.h>

#include "spheremap/io/atomic_file.hpp"

namespace spheremap {
namespace {

// Attribute names become PLY tokens, and x, y, z are taken by the positions.
void check_writable(const Mesh& mesh, const PlyWriteOptions& options) {
  const auto check_name = [](const std::string& name) {
    const bool has_space = std::any_of(name.begin(), name.end(), [](unsigned char c) { return c <= ' ' || c >= 0x7F; });
    if (name.empty() || has_space || name == "x" || name == "y" || name == "z") {
      throw std::invalid_argument(fmt::format("write_ply: attribute name '{}' cannot be a PLY property name", name));
    }
  };
  const auto check_size = [&](const std::string& name, std::size_t size) {
    if (size != mesh.positions.size()) {
      throw std::invalid_argument(
          fmt::format("write_ply: attribute '{}' has {} values for {} vertices", name, size, mesh.positions.size()));
    }
  };
  for (const auto& [name, values] : mesh.real_attributes) {
    check_name(name);
    check_size(name, values.size());
  }
  for (const auto& [name, values] : mesh.integer_attributes) {
    check_name(name);
    check_size(name, values.size());
    if (options.uchar_attributes.count(name) != 0 &&
        std::any_of(values.begin(), values.end(), [](std::int32_t v) { return v < 0 || v > 255; })) {
      throw std::invalid_argument(fmt::format("write_ply: uchar attribute '{}' has a value outside [0, 255]", name));
    }
    if (mesh.real_attributes.count(name) != 0) {
      throw std::invalid_argument(fmt::format("write_ply: attribute '{}' is both real and integer", name));
    }
  }
  for (const auto& [name, text] : mesh.text_attributes) {
    check_name(name);
    check_size(name, text.codes.size());
    if (mesh.real_attributes.count(name) != 0 || mesh.integer_attributes.count(name) != 0) {
      throw std::invalid_argument(fmt::format("write_ply: attribute '{}' is both text and numeric", name));
    }
    for (const auto& entry : text.dictionary) {
      if (entry.size() > 255) {
        throw std::invalid_argument(
            fmt::format("write_ply: text attribute '{}' has a value longer than 255 bytes", name));
      }
    }
    for (const auto code : text.codes) {
      if (code < 0 || static_cast<std::size_t>(code) >= text.dictionary.size()) {
        throw std::invalid_argument(
            fmt::format("write_ply: text attribute '{}' has a code outside its dictionary", name));
      }
    }
  }
}

// The numeric vertex columns in the order they are written: real attributes, then integer ones, each in name
// order, except that red, green, blue go last in that order (Open3D's reader counts a vertex's colour done at
// blue); each with whether it is written narrow (float, uchar).
struct Columns {
  struct Real {
    const std::string* name;
    const std::vector<double>* values;
    bool as_float;
  };
  struct Integer {
    const std::string* name;
    const std::vector<std::int32_t>* values;
    bool as_uchar;
  };
  std::vector<Real> reals;
  std::vector<Integer> integers;

  Columns(const Mesh& mesh, const PlyWriteOptions& options) {
    for (const auto& [name, values] : mesh.real_attributes)
      reals.push_back({&name, &values, options.float_attributes.count(name) != 0});
    for (const auto& [name, values] : mesh.integer_attributes)
      integers.push_back({&name, &values, options.uchar_attributes.count(name) != 0});
    const auto rank = [](const Integer& c) {
      const std::string& n = *c.name;
      return n == "red" ? 1 : n == "green" ? 2 : n == "blue" ? 3 : 0;
    };
    std::stable_sort(integers.begin(), integers.end(),
                     [&](const Integer& a, const Integer& b) { return rank(a) < rank(b); });
  }
};

std::string header(const Mesh& mesh, const Columns& columns, bool ascii) {
  std::string text = "ply\n";
  text += ascii ? "format ascii 1.0\n" : "format binary_little_endian 1.0\n";
  text += "comment written by spheremap\n";
  text += fmt::format("element vertex {}\n", mesh.positions.size());
  text += "property double x\nproperty double y\nproperty double z\n";
  for (const auto& c : columns.reals) text += fmt::format("property {} {}\n", c.as_float ? "float" : "double", *c.name);
  for (const auto& c : columns.integers) text += fmt::format("property {} {}\n", c.as_uchar ? "uchar" : "int", *c.name);
  for (const auto& [name, values] : mesh.text_attributes) text += fmt::format("property list uchar uchar {}\n", name);
  text += fmt::format("element face {}\n", mesh.triangles.size());
  text += "property list uchar int vertex_indices\n";
  text += "end_header\n";
  return text;
}

template <typename T>
void append_little_endian(std::string& out, T value) {
  std::array<char, sizeof(T)> bytes;
  std::memcpy(bytes.data(), &value, sizeof(T));
  if constexpr (std::endian::native == std::endian::big) std::reverse(bytes.begin(), bytes.end());
  out.append(bytes.data(), bytes.size());
}

// Bytes are gathered in `out` and handed to `spill` whenever they pass a megabyte: a 0.25 Å surface of
// GroEL is a 1.8 GB file, which would otherwise stand in memory beside the mesh.
constexpr std::size_t kSpillBytes = std::size_t{1} << 20;

template <typename Spill>
void append_binary_body(std::string& out, const Mesh& mesh, const Columns& columns, Spill&& spill) {
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    for (const double coordinate : mesh.positions[v]) append_little_endian(out, coordinate);
    for (const auto& c : columns.reals) {
      if (c.as_float) {
        append_little_endian(out, static_cast<float>((*c.values)[v]));
      } else {
        append_little_endian(out, (*c.values)[v]);
      }
    }
    for (const auto& c : columns.integers) {
      if (c.as_uchar) {
        out.push_back(static_cast<char>(static_cast<std::uint8_t>((*c.values)[v])));
      } else {
        append_little_endian(out, (*c.values)[v]);
      }
    }
    for (const auto& [name, text] : mesh.text_attributes) {
      const std::string& value = text.at(v);
      out.push_back(static_cast<char>(value.size()));
      out += value;
    }
    if (out.size() >= kSpillBytes) spill();
  }
  for (const Triangle& triangle : mesh.triangles) {
    out.push_back(static_cast<char>(3));
    for (const std::int32_t index : triangle) append_little_endian(out, index);
    if (out.size() >= kSpillBytes) spill();
  }
}

template <typename Spill>
void append_ascii_body(std::string& out, const Mesh& mesh, const Columns& columns, Spill&& spill) {
  auto sink = std::back_inserter(out);
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    const Vec3& p = mesh.positions[v];
    // 17 significant digits make every double read back bit-exact.
    fmt::format_to(sink, "{:.17g} {:.17g} {:.17g}", p[0], p[1], p[2]);
    for (const auto& c : columns.reals) {
      if (c.as_float) {
        fmt::format_to(sink, " {:.9g}", static_cast<float>((*c.values)[v]));  // 9 digits: every float reads back
      } else {
        fmt::format_to(sink, " {:.17g}", (*c.values)[v]);
      }
    }
    for (const auto& c : columns.integers) fmt::format_to(sink, " {}", (*c.values)[v]);
    for (const auto& [name, text] : mesh.text_attributes) {
      const std::string& value = text.at(v);
      fmt::format_to(sink, " {}", value.size());
      for (const unsigned char c : value) fmt::format_to(sink, " {}", static_cast<unsigned>(c));
    }
    out.push_back('\n');
    if (out.size() >= kSpillBytes) spill();
  }
  for (const Triangle& t : mesh.triangles) {
    fmt::format_to(sink, "3 {} {} {}\n", t[0], t[1], t[2]);
    if (out.size() >= kSpillBytes) spill();
  }
}

}  // namespace

void write_ply(const std::filesystem::path& path, const Mesh& mesh, const PlyWriteOptions& options) {
  check_writable(mesh, options);
  const Columns columns(mesh, options);
  AtomicFile file(path);
  std::string buffer = header(mesh, columns, options.ascii);
  buffer.reserve(kSpillBytes + 4096);
  auto spill = [&] {
    file.append(buffer);
    buffer.clear();
  };
  if (options.ascii) {
    append_ascii_body(buffer, mesh, columns, spill);
  } else {
    append_binary_body(buffer, mesh, columns, spill);
  }
  spill();
  file.commit();
}

}  // namespace spheremap
