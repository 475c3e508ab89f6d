// Stanford PLY, ASCII and binary (either byte order).
// Only `x y z` of the `vertex` element and the `vertex_indices` (or `vertex_index`) list of the `face`
// element are kept; every other property and element is skipped, whatever its type.
#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>

#include <fmt/format.h>

#include "readers.hpp"

namespace spheremap::io_detail {
namespace {

enum class PlyFormat { kAscii, kBinaryLittleEndian, kBinaryBigEndian };

enum class PlyType { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };

struct PlyTypeName {
  std::string_view name;
  PlyType type;
};

// Both the original names and the sized aliases written by newer exporters.
constexpr std::array<PlyTypeName, 16> kPlyTypeNames = {{
    {"char", PlyType::kInt8},
    {"int8", PlyType::kInt8},
    {"uchar", PlyType::kUint8},
    {"uint8", PlyType::kUint8},
    {"short", PlyType::kInt16},
    {"int16", PlyType::kInt16},
    {"ushort", PlyType::kUint16},
    {"uint16", PlyType::kUint16},
    {"int", PlyType::kInt32},
    {"int32", PlyType::kInt32},
    {"uint", PlyType::kUint32},
    {"uint32", PlyType::kUint32},
    {"float", PlyType::kFloat32},
    {"float32", PlyType::kFloat32},
    {"double", PlyType::kFloat64},
    {"float64", PlyType::kFloat64},
}};

std::size_t size_of(PlyType type) {
  switch (type) {
    case PlyType::kInt8:
    case PlyType::kUint8: return 1;
    case PlyType::kInt16:
    case PlyType::kUint16: return 2;
    case PlyType::kInt32:
    case PlyType::kUint32:
    case PlyType::kFloat32: return 4;
    case PlyType::kFloat64: return 8;
  }
  return 1;
}

bool is_integer_type(PlyType type) { return type != PlyType::kFloat32 && type != PlyType::kFloat64; }

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::kUint8;  // the item type of a list
  bool is_list = false;
  PlyType count_type = PlyType::kUint8;
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

struct PlyHeader {
  PlyFormat format = PlyFormat::kAscii;
  std::vector<PlyElement> elements;
  std::size_t body_offset = 0;
};

/// Where the data the mesh needs sits in the header.
struct PlyLayout {
  std::size_t vertex_element = 0;
  std::array<std::size_t, 3> coordinate_property{};  // x, y, z
  std::optional<std::size_t> face_element;
  std::size_t index_property = 0;
};

constexpr const char* kHeaderFix = "fix the header or re-export the mesh";

PlyType parse_type(std::string_view token, std::size_t line_number, const std::string& file) {
  for (const auto& [name, type] : kPlyTypeNames) {
    if (token == name) return type;
  }
  fail(file,
       fmt::format("line {}: bad PLY header: unknown property type {}", line_number,
                   token.empty() ? std::string("(missing)") : quote(token)),
       "use char, uchar, short, ushort, int, uint, float, double or their int8..float64 names");
}

PlyHeader parse_header(std::string_view bytes, const std::string& file) {
  const auto first_line_end = bytes.find('\n');
  std::string_view first_line = bytes.substr(0, first_line_end);
  if (!first_line.empty() && first_line.back() == '\r') first_line.remove_suffix(1);
  if (first_line != "ply") {
    fail(file, "bad PLY header: the file does not start with the line 'ply'",
         "check that it really is a PLY file and not another format renamed to .ply");
  }

  PlyHeader header;
  bool has_format = false;
  std::size_t line_start = first_line_end + 1;
  std::size_t line_number = 1;
  for (;;) {
    if (line_start >= bytes.size()) {
      fail(file, "bad PLY header: no 'end_header' line (truncated?)", kHeaderFix);
    }
    std::string_view rest = take_line(bytes, line_start);
    ++line_number;

    const std::string_view keyword = take_token(rest);
    if (keyword.empty() || keyword == "comment" || keyword == "obj_info") continue;
    if (keyword == "end_header") break;
    if (keyword == "format") {
      const std::string_view format = take_token(rest);
      if (format == "ascii") {
        header.format = PlyFormat::kAscii;
      } else if (format == "binary_little_endian") {
        header.format = PlyFormat::kBinaryLittleEndian;
      } else if (format == "binary_big_endian") {
        header.format = PlyFormat::kBinaryBigEndian;
      } else {
        fail(file, fmt::format("line {}: bad PLY header: unknown format {}", line_number, quote(format)),
             "the format must be ascii, binary_little_endian or binary_big_endian");
      }
      has_format = true;
    } else if (keyword == "element") {
      PlyElement element;
      element.name = std::string(take_token(rest));
      std::int64_t count = 0;
      const std::string_view count_token = take_token(rest);
      if (element.name.empty() || !parse_integer(count_token, count) || count < 0) {
        fail(file, fmt::format("line {}: bad PLY header: expected 'element <name> <count>'", line_number), kHeaderFix);
      }
      element.count = static_cast<std::uint64_t>(count);
      header.elements.push_back(std::move(element));
    } else if (keyword == "property") {
      if (header.elements.empty()) {
        fail(file, fmt::format("line {}: bad PLY header: a property comes before any element", line_number),
             kHeaderFix);
      }
      PlyProperty property;
      std::string_view type_token = take_token(rest);
      if (type_token == "list") {
        property.is_list = true;
        property.count_type = parse_type(take_token(rest), line_number, file);
        if (!is_integer_type(property.count_type)) {
          fail(file, fmt::format("line {}: bad PLY header: a list length must have an integer type", line_number),
               kHeaderFix);
        }
        type_token = take_token(rest);
      }
      property.type = parse_type(type_token, line_number, file);
      property.name = std::string(take_token(rest));
      if (property.name.empty()) {
        fail(file, fmt::format("line {}: bad PLY header: the property has no name", line_number), kHeaderFix);
      }
      header.elements.back().properties.push_back(std::move(property));
    } else {
      fail(file, fmt::format("line {}: bad PLY header: unknown keyword {}", line_number, quote(keyword)), kHeaderFix);
    }
  }
  if (!has_format) fail(file, "bad PLY header: no 'format' line", kHeaderFix);
  header.body_offset = std::min(line_start, bytes.size());
  return header;
}

std::optional<std::size_t> find_property(const PlyElement& element, std::string_view name) {
  for (std::size_t p = 0; p < element.properties.size(); ++p) {
    if (element.properties[p].name == name) return p;
  }
  return std::nullopt;
}

PlyLayout find_layout(const PlyHeader& header, const std::string& file) {
  PlyLayout layout;
  std::optional<std::size_t> vertex_element;
  for (std::size_t e = 0; e < header.elements.size(); ++e) {
    if (header.elements[e].name == "vertex" && !vertex_element) vertex_element = e;
    if (header.elements[e].name == "face" && !layout.face_element) layout.face_element = e;
  }
  if (!vertex_element) fail(file, "bad PLY header: no 'element vertex'", kHeaderFix);
  layout.vertex_element = *vertex_element;

  const PlyElement& vertices = header.elements[layout.vertex_element];
  constexpr std::array<std::string_view, 3> kCoordinateNames = {"x", "y", "z"};
  for (std::size_t axis = 0; axis < 3; ++axis) {
    const auto property = find_property(vertices, kCoordinateNames[axis]);
    if (!property || vertices.properties[*property].is_list) {
      fail(file, fmt::format("bad PLY header: the vertex element has no '{}' property", kCoordinateNames[axis]),
           "vertices need 'property float x', 'y' and 'z' (any numeric type)");
    }
    layout.coordinate_property[axis] = *property;
  }

  if (layout.face_element) {
    const PlyElement& faces = header.elements[*layout.face_element];
    auto property = find_property(faces, "vertex_indices");
    if (!property) property = find_property(faces, "vertex_index");
    if (!property || !faces.properties[*property].is_list) {
      fail(file, "bad PLY header: the face element has no 'vertex_indices' list property",
           "faces need 'property list uchar int vertex_indices'");
    }
    if (!is_integer_type(faces.properties[*property].type)) {
      fail(file, "bad PLY header: the face vertex indices have a floating-point type",
           "vertex indices must be an integer type such as int");
    }
    layout.index_property = *property;
  }
  return layout;
}

template <typename T>
T load(const char* bytes, bool swap_bytes) {
  std::array<char, sizeof(T)> buffer;
  std::memcpy(buffer.data(), bytes, sizeof(T));
  if (swap_bytes) std::reverse(buffer.begin(), buffer.end());
  T value;
  std::memcpy(&value, buffer.data(), sizeof(T));
  return value;
}

/// Binary values in the file's byte order. Each read returns false when the data ends.
class BinaryValues {
 public:
  BinaryValues(std::string_view body, bool big_endian)
      : body_(body), swap_bytes_(big_endian != (std::endian::native == std::endian::big)) {}

  bool read_real(PlyType type, double& value) {
    if (remaining() < size_of(type)) return false;
    const char* at = body_.data() + position_;
    switch (type) {
      case PlyType::kFloat32: value = load<float>(at, swap_bytes_); break;
      case PlyType::kFloat64: value = load<double>(at, swap_bytes_); break;
      default: value = static_cast<double>(integer_at(type, at)); break;
    }
    position_ += size_of(type);
    return true;
  }

  /// `type` must be an integer type (the header parser guarantees it for list lengths and indices).
  bool read_integer(PlyType type, std::int64_t& value) {
    if (remaining() < size_of(type)) return false;
    value = integer_at(type, body_.data() + position_);
    position_ += size_of(type);
    return true;
  }

  bool skip(PlyType type, std::uint64_t count) {
    if (count > remaining() / size_of(type)) return false;
    position_ += static_cast<std::size_t>(count) * size_of(type);
    return true;
  }

  [[nodiscard]] std::size_t remaining() const { return body_.size() - position_; }

  static constexpr bool kSizesAreExact = true;
  [[nodiscard]] static std::size_t minimum_bytes(PlyType type) { return size_of(type); }

 private:
  [[nodiscard]] std::int64_t integer_at(PlyType type, const char* at) const {
    switch (type) {
      case PlyType::kInt8: return load<std::int8_t>(at, swap_bytes_);
      case PlyType::kUint8: return load<std::uint8_t>(at, swap_bytes_);
      case PlyType::kInt16: return load<std::int16_t>(at, swap_bytes_);
      case PlyType::kUint16: return load<std::uint16_t>(at, swap_bytes_);
      case PlyType::kInt32: return load<std::int32_t>(at, swap_bytes_);
      case PlyType::kUint32: return load<std::uint32_t>(at, swap_bytes_);
      default: return 0;  // unreachable: floating-point types are rejected for integers in the header
    }
  }

  std::string_view body_;
  std::size_t position_ = 0;
  bool swap_bytes_;
};

/// Whitespace-separated ASCII values. Each read returns false when the data ends, and throws on a
/// token that is not a number.
class AsciiValues {
 public:
  AsciiValues(std::string_view whole_file, std::size_t body_offset, const std::string& file)
      : whole_file_(whole_file), rest_(whole_file.substr(body_offset)), file_(file) {}

  bool read_real(PlyType /*type*/, double& value) {
    const std::string_view token = take_token(rest_);
    if (token.empty()) return false;
    if (!parse_double(token, value)) bad_token(token, "a number");
    return true;
  }

  bool read_integer(PlyType /*type*/, std::int64_t& value) {
    const std::string_view token = take_token(rest_);
    if (token.empty()) return false;
    if (!parse_integer(token, value)) bad_token(token, "an integer");
    return true;
  }

  bool skip(PlyType /*type*/, std::uint64_t count) {
    for (std::uint64_t i = 0; i < count; ++i) {
      if (take_token(rest_).empty()) return false;
    }
    return true;
  }

  [[nodiscard]] std::size_t remaining() const { return rest_.size(); }

  static constexpr bool kSizesAreExact = false;
  /// A digit and a separator.
  [[nodiscard]] static std::size_t minimum_bytes(PlyType /*type*/) { return 2; }

 private:
  [[noreturn]] void bad_token(std::string_view token, std::string_view expected) const {
    const auto offset = static_cast<std::size_t>(token.data() - whole_file_.data());
    fail(file_,
         fmt::format("line {}: expected {} but found {}", line_number_at(whole_file_, offset), expected, quote(token)),
         "fix the line or re-export the mesh");
  }

  std::string_view whole_file_;
  std::string_view rest_;
  const std::string& file_;
};

std::string plural_name(const PlyElement& element) {
  if (element.name == "vertex") return "vertices";
  if (element.name == "face") return "faces";
  return fmt::format("'{}' elements", element.name);
}

[[noreturn]] void fail_truncated(const std::string& file, const PlyElement& element, std::uint64_t complete) {
  fail(file, fmt::format("the file ends after {} of {} {} (truncated?)", complete, element.count, plural_name(element)),
       "re-export the mesh");
}

/// Reads the body element by element; `Values` is BinaryValues or AsciiValues. With `attributes`, the vertex
/// element's other scalar properties and its lists of uchar (text) are kept there too.
template <typename Values>
PolygonSoup read_body(const PlyHeader& header, const PlyLayout& layout, Values& values, const std::string& file,
                      PlyVertexAttributes* attributes = nullptr) {
  PolygonSoup soup;
  if (attributes != nullptr) {
    const PlyElement& vertices = header.elements[layout.vertex_element];
    for (std::size_t p = 0; p < vertices.properties.size(); ++p) {
      const PlyProperty& property = vertices.properties[p];
      if (p == layout.coordinate_property[0] || p == layout.coordinate_property[1] ||
          p == layout.coordinate_property[2])
        continue;
      if (property.is_list && property.type == PlyType::kUint8)
        attributes->text[property.name];
      else if (!property.is_list && is_integer_type(property.type))
        attributes->integer[property.name];
      else if (!property.is_list)
        attributes->real[property.name];
    }
  }
  const std::uint64_t vertex_count = header.elements[layout.vertex_element].count;
  for (std::size_t e = 0; e < header.elements.size(); ++e) {
    const PlyElement& element = header.elements[e];
    if (element.properties.empty()) continue;  // nothing to read, however large the count
    const bool is_vertex = e == layout.vertex_element;
    const bool is_face = layout.face_element && e == *layout.face_element;

    // What the rest of the file can hold bounds the reservation, so a lying header cannot exhaust
    // memory; without lists the bound is exact and a truncated file is reported before reading.
    std::uint64_t minimum_instance_bytes = 0;
    bool has_list = false;
    for (const PlyProperty& property : element.properties) {
      minimum_instance_bytes += values.minimum_bytes(property.is_list ? property.count_type : property.type);
      has_list = has_list || property.is_list;
    }
    const std::uint64_t capacity = values.remaining() / minimum_instance_bytes;
    if (Values::kSizesAreExact && !has_list && element.count > capacity) fail_truncated(file, element, capacity);
    if (is_vertex) soup.positions.reserve(static_cast<std::size_t>(std::min(element.count, capacity)));
    if (is_face) soup.faces.reserve(static_cast<std::size_t>(std::min(element.count, capacity)));

    for (std::uint64_t i = 0; i < element.count; ++i) {
      Vec3 position{};
      for (std::size_t p = 0; p < element.properties.size(); ++p) {
        const PlyProperty& property = element.properties[p];
        if (property.is_list) {
          std::int64_t length = 0;
          if (!values.read_integer(property.count_type, length)) fail_truncated(file, element, i);
          if (length < 0) {
            fail(file,
                 fmt::format("{} {} has a list '{}' of negative length {}", element.name, i, property.name, length),
                 "the file is corrupt; re-export the mesh");
          }
          if (is_vertex && attributes != nullptr && property.type == PlyType::kUint8) {
            std::string text;
            for (std::int64_t c = 0; c < length; ++c) {
              std::int64_t byte = 0;
              if (!values.read_integer(property.type, byte)) fail_truncated(file, element, i);
              text.push_back(static_cast<char>(byte));
            }
            TextAttribute& attribute = attributes->text[property.name];
            auto [found, inserted] = attributes->text_codes[property.name].try_emplace(
                text, static_cast<std::int32_t>(attribute.dictionary.size()));
            if (inserted) attribute.dictionary.push_back(text);
            attribute.codes.push_back(found->second);
          } else if (is_face && p == layout.index_property) {
            std::vector<std::int32_t> corners;
            corners.reserve(static_cast<std::size_t>(std::min<std::uint64_t>(
                static_cast<std::uint64_t>(length), values.remaining() / size_of(property.type))));
            for (std::int64_t c = 0; c < length; ++c) {
              std::int64_t index = 0;
              if (!values.read_integer(property.type, index)) fail_truncated(file, element, i);
              if (index < 0 || static_cast<std::uint64_t>(index) >= vertex_count) {
                fail(file,
                     fmt::format("face {} refers to vertex {}, but the file has {} vertices (numbered from 0)", i,
                                 index, vertex_count),
                     "the file is corrupt or truncated; re-export the mesh");
              }
              corners.push_back(static_cast<std::int32_t>(index));
            }
            soup.faces.push_back(std::move(corners));
          } else if (!values.skip(property.type, static_cast<std::uint64_t>(length))) {
            fail_truncated(file, element, i);
          }
        } else if (is_vertex && (p == layout.coordinate_property[0] || p == layout.coordinate_property[1] ||
                                 p == layout.coordinate_property[2])) {
          const std::size_t axis = p == layout.coordinate_property[0] ? 0 : p == layout.coordinate_property[1] ? 1 : 2;
          if (!values.read_real(property.type, position[axis])) fail_truncated(file, element, i);
        } else if (is_vertex && attributes != nullptr && is_integer_type(property.type)) {
          std::int64_t value = 0;
          if (!values.read_integer(property.type, value)) fail_truncated(file, element, i);
          attributes->integer[property.name].push_back(static_cast<std::int32_t>(value));
        } else if (is_vertex && attributes != nullptr) {
          double value = 0;
          if (!values.read_real(property.type, value)) fail_truncated(file, element, i);
          attributes->real[property.name].push_back(value);
        } else if (!values.skip(property.type, 1)) {
          fail_truncated(file, element, i);
        }
      }
      if (is_vertex) soup.positions.push_back(position);
    }
  }
  return soup;
}

}  // namespace

PolygonSoup read_ply(std::string_view bytes, const std::string& file, PlyVertexAttributes* attributes) {
  const PlyHeader header = parse_header(bytes, file);
  const PlyLayout layout = find_layout(header, file);
  if (header.elements[layout.vertex_element].count >
      static_cast<std::uint64_t>(std::numeric_limits<std::int32_t>::max())) {
    fail(file,
         fmt::format("the header declares {} vertices, more than the 2^31 - 1 supported",
                     header.elements[layout.vertex_element].count),
         "simplify the mesh first");
  }
  if (header.format == PlyFormat::kAscii) {
    require_text(bytes.substr(header.body_offset), file, "PLY (format ascii)", bytes, header.body_offset);
    AsciiValues values(bytes, header.body_offset, file);
    return read_body(header, layout, values, file, attributes);
  }
  BinaryValues values(bytes.substr(header.body_offset), header.format == PlyFormat::kBinaryBigEndian);
  return read_body(header, layout, values, file, attributes);
}

PolygonSoup read_ply(std::string_view bytes, const std::string& file) { return read_ply(bytes, file, nullptr); }

}  // namespace spheremap::io_detail
