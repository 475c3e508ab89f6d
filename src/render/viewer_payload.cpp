// Packing the viewer's data: typed arrays in one blob, texts in a JSON manifest (see viewer_payload.hpp).
#include "viewer_payload.hpp"

#include <libdeflate.h>

#include <array>
#include <bit>
#include <cstring>
#include <map>
#include <memory>
#include <stdexcept>

#include <nlohmann/json.hpp>

namespace spheremap::detail {
namespace {

using Json = nlohmann::ordered_json;

// Appends typed arrays to the blob, little-endian whatever the host, and records them in the manifest.
class BlobWriter {
 public:
  explicit BlobWriter(Json& arrays) : arrays_(arrays) {}

  void begin(const std::string& name, const char* type, std::size_t count) {
    arrays_[name] = Json{{"type", type}, {"offset", blob_.size()}, {"count", count}};
  }
  void u32(std::uint32_t v) {
    for (int shift = 0; shift < 32; shift += 8) blob_.push_back(static_cast<char>((v >> shift) & 0xffu));
  }
  void i32(std::int32_t v) { u32(static_cast<std::uint32_t>(v)); }
  void u8(std::uint8_t v) { blob_.push_back(static_cast<char>(v)); }
  /// `count` words as u32 writes them, word(k) the k-th, stored with one resize for the whole array (the
  /// arrays of a large surface hold millions of words).
  template <typename Word>
  void u32s(std::size_t count, Word&& word) {
    static_assert(std::endian::native == std::endian::little, "u32 writes little-endian words");
    const std::size_t at = blob_.size();
    blob_.resize(at + 4 * count);
    char* out = blob_.data() + at;
    for (std::size_t k = 0; k < count; ++k) {
      const std::uint32_t v = word(k);
      std::memcpy(out + 4 * k, &v, 4);
    }
  }
  // Keeps every array 4-byte aligned, as Float32Array / Int32Array views require.
  void align() {
    while (blob_.size() % 4 != 0) blob_.push_back('\0');
  }
  std::string take() { return std::move(blob_); }

 private:
  Json& arrays_;
  std::string blob_;
};

// Interns texts: each distinct string once, in order of first use, repaired to valid UTF-8.
class StringTable {
 public:
  std::uint32_t id(const std::string& text) {
    const auto [it, inserted] = ids_.try_emplace(text, static_cast<std::uint32_t>(strings_.size()));
    if (inserted) strings_.push_back(valid_utf8(text));
    return it->second;
  }
  [[nodiscard]] const std::vector<std::string>& strings() const { return strings_; }

 private:
  std::map<std::string, std::uint32_t> ids_;
  std::vector<std::string> strings_;
};

void pack_positions(BlobWriter& out, const std::string& name, const std::vector<Vec3>& positions) {
  out.begin(name, "float32", positions.size() * 3);
  out.u32s(positions.size() * 3,
           [&](std::size_t k) { return std::bit_cast<std::uint32_t>(static_cast<float>(positions[k / 3][k % 3])); });
}

void pack_atoms(BlobWriter& out, StringTable& strings, const std::vector<ViewerAtom>& atoms) {
  // One column per field: a column of one kind of value compresses far better than interleaved records.
  const auto text_column = [&](const char* name, std::string ViewerAtom::*field) {
    out.begin(name, "uint32", atoms.size());
    for (const ViewerAtom& a : atoms) out.u32(strings.id(a.*field));
  };
  text_column("atom_chain", &ViewerAtom::chain);
  text_column("atom_residue_name", &ViewerAtom::residue_name);
  out.begin("atom_residue_number", "int32", atoms.size());
  for (const ViewerAtom& a : atoms) out.i32(a.residue_number);
  text_column("atom_insertion_code", &ViewerAtom::insertion_code);
  text_column("atom_name", &ViewerAtom::atom_name);
}

Json pack_property(BlobWriter& out, const ViewerProperty& property, std::size_t index) {
  const std::string values = "property" + std::to_string(index) + "_values";
  const std::string table = "property" + std::to_string(index) + "_colours";
  out.begin(values, "float32", property.values.size());
  out.u32s(property.values.size(), [&](std::size_t k) { return std::bit_cast<std::uint32_t>(property.values[k]); });
  out.begin(table, "uint8", 3 * kColourTableSize);
  for (const Rgb8& c : colour_table(property.scale)) out.u8(c.r), out.u8(c.g), out.u8(c.b);
  out.align();
  Json categories = Json::array();
  for (const std::string& c : property.categories) categories.push_back(valid_utf8(c));
  return Json{{"name", valid_utf8(property.name)},
              {"unit", valid_utf8(property.unit)},
              {"scale", std::string(to_string(property.scale))},
              {"range", Json::array({property.range.lo, property.range.hi})},
              {"values", values},
              {"colours", table},
              {"categories", categories}};
}

}  // namespace

ViewerPayload pack_viewer_payload(const ViewerData& data) {
  const std::size_t n = data.surface_positions.size();
  Json arrays = Json::object();
  BlobWriter out(arrays);
  StringTable strings;
  pack_positions(out, "surface_positions", data.surface_positions);
  pack_positions(out, "sphere_positions", data.sphere_positions);
  out.begin("triangles", "uint32", data.triangles.size() * 3);
  out.u32s(data.triangles.size() * 3,
           [&](std::size_t k) { return static_cast<std::uint32_t>(data.triangles[k / 3][k % 3]); });
  out.begin("vertex_atoms", "int32", n);
  out.u32s(n, [&](std::size_t v) {
    return static_cast<std::uint32_t>(data.vertex_atoms.empty() ? -1 : data.vertex_atoms[v]);
  });
  pack_atoms(out, strings, data.atoms);
  Json properties = Json::array();
  for (std::size_t i = 0; i < data.properties.size(); ++i)
    properties.push_back(pack_property(out, data.properties[i], i));

  const Json manifest{
      {"format", "spheremap-viewer"},
      {"version", 1},
      {"title", valid_utf8(data.title)},
      {"vertex_count", n},
      {"triangle_count", data.triangles.size()},
      {"atom_count", data.atoms.size()},
      {"missing_colour", Json::array({kMissingValueColour.r, kMissingValueColour.g, kMissingValueColour.b})},
      {"properties", properties},
      {"strings", strings.strings()},
      {"arrays", arrays}};
  return {manifest.dump(), out.take()};
}

std::string deflate_zlib(std::string_view bytes, int level) {
  if (level < 1 || level > 12)
    throw std::invalid_argument("deflate_zlib: level " + std::to_string(level) + " is outside 1..12");
  const std::unique_ptr<libdeflate_compressor, void (*)(libdeflate_compressor*)> compressor(
      libdeflate_alloc_compressor(level), libdeflate_free_compressor);
  if (compressor == nullptr) throw std::runtime_error("libdeflate could not allocate a compressor (out of memory?)");
  // A buffer of the bound's size, not zero-filled first (megabytes, of which the stream uses a fraction).
  const std::size_t bound = libdeflate_zlib_compress_bound(compressor.get(), bytes.size());
  const std::unique_ptr<char[]> buffer(new char[bound]);
  const std::size_t size = libdeflate_zlib_compress(compressor.get(), bytes.data(), bytes.size(), buffer.get(), bound);
  // The buffer has the bound's size, so 0 (too small) means libdeflate broke its own contract.
  if (size == 0) throw std::runtime_error("libdeflate could not compress " + std::to_string(bytes.size()) + " bytes");
  return std::string(buffer.get(), size);
}

std::string base64_encode(const std::string& bytes) {
  static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto byte = [&](std::size_t i) -> std::uint32_t { return static_cast<std::uint8_t>(bytes[i]); };
  std::string out((bytes.size() + 2) / 3 * 4, '=');
  char* o = out.data();
  // Whole groups of three bytes written in place (megabytes: no push_back's capacity check), then the tail.
  const std::size_t whole = bytes.size() / 3 * 3;
  // Two characters per lookup: the pair of each 12-bit half of a group.
  static const std::array<std::array<char, 2>, 4096> kPairs = [] {
    std::array<std::array<char, 2>, 4096> pairs{};
    for (std::size_t k = 0; k < pairs.size(); ++k) pairs[k] = {kAlphabet[k >> 6], kAlphabet[k & 63]};
    return pairs;
  }();
  for (std::size_t i = 0; i < whole; i += 3, o += 4) {
    const std::uint32_t group = byte(i) << 16 | byte(i + 1) << 8 | byte(i + 2);
    std::memcpy(o, kPairs[group >> 12].data(), 2);
    std::memcpy(o + 2, kPairs[group & 4095].data(), 2);
  }
  if (const std::size_t left = bytes.size() - whole; left > 0) {
    const std::uint32_t group = byte(whole) << 16 | (left > 1 ? byte(whole + 1) << 8 : 0);
    o[0] = kAlphabet[(group >> 18) & 63];
    o[1] = kAlphabet[(group >> 12) & 63];
    if (left > 1) o[2] = kAlphabet[(group >> 6) & 63];  // else '=' (as o[3])
  }
  return out;
}

std::string valid_utf8(const std::string& text) {
  // nlohmann's serializer already knows UTF-8: its "replace" handler substitutes U+FFFD for every invalid
  // sequence; parsing its output back gives the repaired text.
  return Json::parse(Json(text).dump(-1, ' ', false, Json::error_handler_t::replace)).get<std::string>();
}

}  // namespace spheremap::detail
