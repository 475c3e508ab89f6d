// write_glb: the JSON chunk by nlohmann-json, the BIN chunk packed by hand (little-endian, 4-byte aligned).
#include "spheremap/io/gltf.hpp"

#include <algorithm>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "spheremap/io/atomic_file.hpp"

namespace spheremap {
namespace {

constexpr int kFloat = 5126, kUnsignedByte = 5121, kUnsignedInt = 5125;
constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;

template <typename T>
void put(std::string& out, T value) {
  std::array<char, sizeof(T)> bytes;
  std::memcpy(bytes.data(), &value, sizeof(T));
  if constexpr (std::endian::native == std::endian::big) std::reverse(bytes.begin(), bytes.end());
  out.append(bytes.data(), bytes.size());
}

void pad(std::string& out, char with) {
  while (out.size() % 4 != 0) out.push_back(with);
}

// Appends a buffer view of `bytes` (its offset aligned to 4) and an accessor on it; returns the accessor's index.
int add_accessor(nlohmann::ordered_json& gltf, std::string& bin, const std::string& bytes, int target,
                 nlohmann::ordered_json accessor) {
  pad(bin, '\0');
  const int view = static_cast<int>(gltf["bufferViews"].size());
  gltf["bufferViews"].push_back(
      {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes.size()}, {"target", target}});
  bin += bytes;
  accessor["bufferView"] = view;
  accessor["byteOffset"] = 0;
  gltf["accessors"].push_back(std::move(accessor));
  return static_cast<int>(gltf["accessors"].size()) - 1;
}

int add_vectors(nlohmann::ordered_json& gltf, std::string& bin, const std::vector<Vec3>& vectors, bool bounds) {
  std::string bytes;
  std::array<float, 3> lo{}, hi{};
  lo.fill(std::numeric_limits<float>::infinity());
  hi.fill(-std::numeric_limits<float>::infinity());
  for (const Vec3& v : vectors)
    for (std::size_t k = 0; k < 3; ++k) {
      const auto f = static_cast<float>(v[k]);
      put(bytes, f);
      lo[k] = std::min(lo[k], f), hi[k] = std::max(hi[k], f);
    }
  nlohmann::ordered_json accessor = {{"componentType", kFloat}, {"count", vectors.size()}, {"type", "VEC3"}};
  if (bounds) accessor["min"] = lo, accessor["max"] = hi;  // the float values as written
  return add_accessor(gltf, bin, bytes, kArrayBuffer, std::move(accessor));
}

void check(const GlbMesh& mesh) {
  const std::size_t n = mesh.positions.size();
  if (n == 0) throw std::invalid_argument("write_glb: no vertices");
  if ((!mesh.normals.empty() && mesh.normals.size() != n) || (!mesh.colours.empty() && mesh.colours.size() != n))
    throw std::invalid_argument("write_glb: normals or colours of another count than the positions");
  for (const auto& [name, values] : mesh.attributes)
    if (name.empty() || name.front() != '_' || values.size() != n)
      throw std::invalid_argument("write_glb: attribute '" + name + "' needs a leading '_' and one value per vertex");
  for (const Triangle& t : mesh.triangles)
    for (const auto v : t)
      if (v < 0 || static_cast<std::size_t>(v) >= n)
        throw std::invalid_argument("write_glb: a vertex index is out of range");
}

}  // namespace

std::string glb_attribute_name(const std::string& property) {
  std::string name = "_" + property;
  std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return std::toupper(c); });
  return name;
}

void write_glb(const std::filesystem::path& path, const GlbMesh& mesh) {
  check(mesh);
  nlohmann::ordered_json gltf = {{"asset", {{"version", "2.0"}, {"generator", "spheremap"}}},
                                 {"scene", 0},
                                 {"scenes", {{{"nodes", {0}}}}},
                                 {"nodes", {{{"mesh", 0}, {"name", mesh.name}}}},
                                 {"bufferViews", nlohmann::ordered_json::array()},
                                 {"accessors", nlohmann::ordered_json::array()}};
  std::string bin;
  nlohmann::ordered_json attributes = nlohmann::ordered_json::object();
  attributes["POSITION"] = add_vectors(gltf, bin, mesh.positions, true);
  if (!mesh.normals.empty()) attributes["NORMAL"] = add_vectors(gltf, bin, mesh.normals, false);
  if (!mesh.colours.empty()) {
    std::string bytes;
    for (const auto& c : mesh.colours)
      bytes.append({static_cast<char>(c[0]), static_cast<char>(c[1]), static_cast<char>(c[2]), static_cast<char>(255)});
    attributes["COLOR_0"] = add_accessor(
        gltf, bin, bytes, kArrayBuffer,
        {{"componentType", kUnsignedByte}, {"normalized", true}, {"count", mesh.colours.size()}, {"type", "VEC4"}});
  }
  for (const auto& [name, values] : mesh.attributes) {
    std::string bytes;
    for (const double v : values) put(bytes, std::isnan(v) ? kGlbMissingValue : static_cast<float>(v));
    attributes[name] = add_accessor(gltf, bin, bytes, kArrayBuffer,
                                    {{"componentType", kFloat},
                                     {"count", values.size()},
                                     {"type", "SCALAR"},
                                     {"extras", {{"missing_value", kGlbMissingValue}}}});
  }
  std::string indices;
  for (const Triangle& t : mesh.triangles)
    for (const auto v : t) put(indices, static_cast<std::uint32_t>(v));
  const int index_accessor =
      add_accessor(gltf, bin, indices, kElementArrayBuffer,
                   {{"componentType", kUnsignedInt}, {"count", 3 * mesh.triangles.size()}, {"type", "SCALAR"}});
  gltf["meshes"] = {
      {{"name", mesh.name}, {"primitives", {{{"attributes", attributes}, {"indices", index_accessor}, {"mode", 4}}}}}};
  pad(bin, '\0');
  gltf["buffers"] = {{{"byteLength", bin.size()}}};
  std::string json = gltf.dump();
  while (json.size() % 4 != 0) json.push_back(' ');  // the JSON chunk is padded with spaces
  std::string out;
  put(out, std::uint32_t{0x46546C67});  // "glTF"
  put(out, std::uint32_t{2});
  put(out, static_cast<std::uint32_t>(12 + 8 + json.size() + 8 + bin.size()));
  put(out, static_cast<std::uint32_t>(json.size()));
  put(out, std::uint32_t{0x4E4F534A});  // "JSON"
  out += json;
  put(out, static_cast<std::uint32_t>(bin.size()));
  put(out, std::uint32_t{0x004E4942});  // "BIN\0"
  out += bin;
  write_file_atomically(path, out);
}

}  // namespace spheremap
