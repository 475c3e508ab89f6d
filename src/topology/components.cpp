#include "spheremap/topology/components.hpp"

#include <algorithm>
#include <numeric>
#include <utility>

#include "../util/union_find.hpp"
#include "spheremap/geometry/vec.hpp"

namespace spheremap {

std::vector<MeshComponent> mesh_components(const Mesh& mesh) {
  const auto n = static_cast<std::int32_t>(mesh.positions.size());
  detail::UnionFind<std::int32_t> sets(mesh.positions.size());
  for (const auto& t : mesh.triangles)
    for (int k = 1; k < 3; ++k) sets.join(t[0], t[k]);
  std::vector<std::int32_t> component_of_root(n, -1);
  std::vector<MeshComponent> components;
  for (std::int32_t t = 0; t < static_cast<std::int32_t>(mesh.triangles.size()); ++t) {
    const auto root = sets.find(mesh.triangles[t][0]);
    if (component_of_root[root] < 0) {
      component_of_root[root] = static_cast<std::int32_t>(components.size());
      components.emplace_back();
    }
    auto& c = components[component_of_root[root]];
    c.triangles.push_back(t);
    const auto& tri = mesh.triangles[t];
    const Vec3 &a = mesh.positions[tri[0]], &b = mesh.positions[tri[1]], &p = mesh.positions[tri[2]];
    c.area += triangle_area(a, b, p);
    c.signed_volume += dot(a, cross(b, p)) / 6.0;
  }
  // Vertices per component, for the Euler characteristic; a closed 2-manifold has E = 3F/2.
  std::vector<std::int64_t> vertex_count(components.size(), 0);
  for (std::int32_t v = 0; v < n; ++v)
    if (component_of_root[sets.find(v)] >= 0) ++vertex_count[component_of_root[sets.find(v)]];
  for (std::size_t c = 0; c < components.size(); ++c) {
    auto& component = components[c];
    component.vertices = vertex_count[c];
    const auto faces = static_cast<std::int64_t>(component.triangles.size());
    const std::int64_t euler = component.vertices - 3 * faces / 2 + faces;
    component.genus = static_cast<int>((2 - euler) / 2);
  }
  std::stable_sort(components.begin(), components.end(),
                   [](const MeshComponent& a, const MeshComponent& b) { return a.area > b.area; });
  return components;
}

Mesh extract_component(const Mesh& mesh, const MeshComponent& component) {
  std::vector<std::int32_t> new_index(mesh.positions.size(), -1);
  for (const auto t : component.triangles)
    for (const auto v : mesh.triangles[t]) new_index[v] = 0;
  std::vector<std::int32_t> kept;
  for (std::int32_t v = 0; v < static_cast<std::int32_t>(new_index.size()); ++v)
    if (new_index[v] == 0) new_index[v] = static_cast<std::int32_t>(kept.size()), kept.push_back(v);
  Mesh out;
  for (const auto v : kept) out.positions.push_back(mesh.positions[v]);
  for (const auto t : component.triangles) {
    const auto& tri = mesh.triangles[t];
    out.triangles.push_back({new_index[tri[0]], new_index[tri[1]], new_index[tri[2]]});
  }
  for (const auto& [name, values] : mesh.real_attributes) {
    auto& o = out.real_attributes[name];
    for (const auto v : kept) o.push_back(values[v]);
  }
  for (const auto& [name, values] : mesh.integer_attributes) {
    auto& o = out.integer_attributes[name];
    for (const auto v : kept) o.push_back(values[v]);
  }
  for (const auto& [name, text] : mesh.text_attributes) {
    auto& o = out.text_attributes[name];
    o.dictionary = text.dictionary;
    for (const auto v : kept) o.codes.push_back(text.codes[v]);
  }
  return out;
}

Mesh extract_component(Mesh&& mesh, const MeshComponent& component) {
  std::vector<std::int32_t> new_index(mesh.positions.size(), -1);
  for (const auto t : component.triangles)
    for (const auto v : mesh.triangles[t]) new_index[v] = 0;
  std::int32_t kept = 0;
  for (auto& index : new_index)
    if (index == 0) index = kept++;
  // Kept vertices and triangles keep their order, so an entry only ever moves to a lower index: compacting
  // front to back never overwrites one still to be read. The copy that shrink_to_fit makes is of the kept
  // part only; without it the dropped tail would stay resident through the simplification.
  auto compact = [&](auto& values) {
    for (std::size_t v = 0; v < new_index.size(); ++v)
      if (new_index[v] >= 0) values[static_cast<std::size_t>(new_index[v])] = std::move(values[v]);
    values.resize(static_cast<std::size_t>(kept));
    values.shrink_to_fit();
  };
  compact(mesh.positions);
  for (auto& [name, values] : mesh.real_attributes) compact(values);
  for (auto& [name, values] : mesh.integer_attributes) compact(values);
  for (auto& [name, text] : mesh.text_attributes) compact(text.codes);
  for (std::size_t i = 0; i < component.triangles.size(); ++i) {
    const auto& tri = mesh.triangles[static_cast<std::size_t>(component.triangles[i])];
    mesh.triangles[i] = {new_index[tri[0]], new_index[tri[1]], new_index[tri[2]]};
  }
  mesh.triangles.resize(component.triangles.size());
  mesh.triangles.shrink_to_fit();
  return std::move(mesh);
}

}  // namespace spheremap
