#include "spheremap/topology/prepare.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>
#include <unordered_set>

#include <fmt/format.h>

#include "../util/union_find.hpp"
#include "spheremap/error.hpp"
#include "spheremap/geometry/vec.hpp"

namespace spheremap {
namespace {

using detail::UnionFind;

// representative[i] = smallest input index of the vertices welded with i.
std::vector<std::int32_t> weld_representatives(const std::vector<Vec3>& positions, double tolerance) {
  const auto n = static_cast<std::int32_t>(positions.size());
  std::vector<std::int32_t> representative(n);
  std::iota(representative.begin(), representative.end(), 0);
  if (tolerance <= 0) {
    std::vector<std::int32_t> order(n);
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](std::int32_t a, std::int32_t b) {
      return positions[a] != positions[b] ? positions[a] < positions[b] : a < b;
    });
    for (std::int32_t k = 1; k < n; ++k) {
      if (positions[order[k]] == positions[order[k - 1]]) representative[order[k]] = representative[order[k - 1]];
    }
    return representative;
  }
  double largest = 0;
  for (const auto& p : positions) largest = std::max({largest, std::abs(p[0]), std::abs(p[1]), std::abs(p[2])});
  if (largest / tolerance > 1e15)
    throw InputError(
        fmt::format("weld tolerance {} is too small for coordinates as large as {} (below double "
                    "precision); use 0 to weld exactly coincident vertices",
                    tolerance, largest));
  // Grid hashing with cells of the tolerance: welded pairs lie in the same or adjacent cells.
  auto cell_of = [&](const Vec3& p) {
    return std::array<std::int64_t, 3>{static_cast<std::int64_t>(std::floor(p[0] / tolerance)),
                                       static_cast<std::int64_t>(std::floor(p[1] / tolerance)),
                                       static_cast<std::int64_t>(std::floor(p[2] / tolerance))};
  };
  auto key_of = [](const std::array<std::int64_t, 3>& c) {
    return static_cast<std::uint64_t>(c[0]) * 73856093ULL ^ static_cast<std::uint64_t>(c[1]) * 19349663ULL ^
           static_cast<std::uint64_t>(c[2]) * 83492791ULL;
  };
  std::unordered_multimap<std::uint64_t, std::int32_t> grid;
  grid.reserve(positions.size());
  for (std::int32_t i = 0; i < n; ++i) grid.emplace(key_of(cell_of(positions[i])), i);
  UnionFind<std::int64_t> clusters(static_cast<std::size_t>(n));
  const double tolerance_squared = tolerance * tolerance;
  for (std::int32_t i = 0; i < n; ++i) {
    const auto c = cell_of(positions[i]);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          auto [begin, end] = grid.equal_range(key_of({c[0] + dx, c[1] + dy, c[2] + dz}));
          for (auto it = begin; it != end; ++it) {
            if (it->second > i && squared_distance(positions[i], positions[it->second]) <= tolerance_squared)
              clusters.join(i, it->second);
          }
        }
  }
  for (std::int32_t i = 0; i < n; ++i) representative[i] = static_cast<std::int32_t>(clusters.find(i));
  return representative;
}

struct EdgeIncidence {
  std::int32_t low, high;  // vertex indices, low < high
  std::int32_t face;
  bool forward;  // the face runs low -> high
};

// All half-edges grouped by undirected edge (sorted by (low, high, face)), using a counting sort on the
// low vertex so that millions of triangles are grouped in linear time.
std::vector<EdgeIncidence> group_edges(std::int32_t vertex_count, const std::vector<Triangle>& triangles) {
  std::vector<std::int64_t> start(static_cast<std::size_t>(vertex_count) + 1, 0);
  for (const auto& t : triangles)
    for (int k = 0; k < 3; ++k) ++start[std::min(t[k], t[(k + 1) % 3]) + 1];
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<EdgeIncidence> edges(triangles.size() * 3);
  std::vector<std::int64_t> fill(start.begin(), start.end() - 1);
  for (std::int32_t f = 0; f < static_cast<std::int32_t>(triangles.size()); ++f) {
    const auto& t = triangles[f];
    for (int k = 0; k < 3; ++k) {
      const std::int32_t a = t[k], b = t[(k + 1) % 3];
      edges[fill[std::min(a, b)]++] = {std::min(a, b), std::max(a, b), f, a < b};
    }
  }
  for (std::int32_t v = 0; v < vertex_count; ++v) {
    std::sort(edges.begin() + start[v], edges.begin() + start[v + 1],
              [](const auto& x, const auto& y) { return x.high != y.high ? x.high < y.high : x.face < y.face; });
  }
  return edges;
}

std::string plural(std::int64_t n, const char* singular, const char* many) {
  return fmt::format("{} {}", n, n == 1 ? singular : many);
}

// Every face index in range and every coordinate finite; throws InputError naming the first that is not.
template <typename Faces>
void check_input(const std::vector<Vec3>& positions, const Faces& faces, const std::string& name) {
  if (faces.empty())
    throw InputError(fmt::format("{}: the file has no faces; spheremap needs a closed triangle mesh", name));
  const auto input_count = static_cast<std::int32_t>(positions.size());
  for (std::size_t f = 0; f < faces.size(); ++f) {
    for (auto index : faces[f]) {
      if (index < 0 || index >= input_count)
        throw InputError(
            fmt::format("{}: face {} refers to vertex {}, but there are only {} vertices; the file is corrupt", name, f,
                        index, input_count));
    }
  }
  for (std::int32_t i = 0; i < input_count; ++i) {
    const auto& p = positions[i];
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
      throw InputError(fmt::format("{}: vertex {} has a non-finite coordinate; fix or remove it", name, i));
  }
}

// The faces as triangles of welded vertices. Fan triangulation from the first corner whose diagonals are
// not edges already: a fan whose diagonal duplicates an existing edge would make that edge non-manifold
// (only polygons need the table: a mesh of triangles, such as every molecular surface, skips it).
// Faces of fewer than 3 corners and triangles with a repeated corner are dropped (and counted).
template <typename Faces>
std::vector<Triangle> triangulate(const Faces& faces, const std::vector<std::int32_t>& representative,
                                  PrepareReport& report) {
  std::unordered_set<std::uint64_t> edges_in_use;
  auto edge_key = [](std::int32_t a, std::int32_t b) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(std::min(a, b))) << 32) |
           static_cast<std::uint32_t>(std::max(a, b));
  };
  const bool any_polygon = std::any_of(faces.begin(), faces.end(), [](const auto& face) { return face.size() > 3; });
  if (any_polygon) {
    for (const auto& face : faces) {
      for (std::size_t k = 0; k < face.size(); ++k)
        edges_in_use.insert(edge_key(representative[face[k]], representative[face[(k + 1) % face.size()]]));
    }
  }
  std::vector<Triangle> triangles;
  triangles.reserve(faces.size() * 2);
  for (const auto& face : faces) {
    if (face.size() > 3) ++report.polygons_triangulated;
    if (face.size() < 3) {
      ++report.degenerate_faces_dropped;
      continue;
    }
    const std::size_t corners = face.size();
    std::size_t apex = 0;
    if (corners > 3) {
      for (std::size_t start = 0; start < corners; ++start) {
        bool free = true;
        for (std::size_t k = 2; k + 1 < corners && free; ++k)
          free =
              !edges_in_use.count(edge_key(representative[face[start]], representative[face[(start + k) % corners]]));
        if (free) {
          apex = start;
          break;
        }
      }
      for (std::size_t k = 2; k + 1 < corners; ++k)
        edges_in_use.insert(edge_key(representative[face[apex]], representative[face[(apex + k) % corners]]));
    }
    for (std::size_t k = 1; k + 1 < corners; ++k) {
      const Triangle t{representative[face[apex]], representative[face[(apex + k) % corners]],
                       representative[face[(apex + k + 1) % corners]]};
      if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) {
        ++report.degenerate_faces_dropped;
        continue;
      }
      triangles.push_back(t);
    }
  }
  return triangles;
}

// Drops every triangle with the same three vertices as an earlier one (and counts them).
void drop_duplicate_triangles(std::vector<Triangle>& triangles, PrepareReport& report) {
  std::vector<std::pair<Triangle, std::int32_t>> sorted(triangles.size());
  for (std::size_t f = 0; f < triangles.size(); ++f) {
    Triangle key = triangles[f];
    std::sort(key.begin(), key.end());
    sorted[f] = {key, static_cast<std::int32_t>(f)};
  }
  std::sort(sorted.begin(), sorted.end());
  std::vector<char> keep(triangles.size(), 1);
  for (std::size_t k = 1; k < sorted.size(); ++k) {
    if (sorted[k].first == sorted[k - 1].first) {
      keep[sorted[k].second] = 0;
      ++report.duplicate_faces_dropped;
    }
  }
  std::size_t out = 0;
  for (std::size_t f = 0; f < triangles.size(); ++f)
    if (keep[f]) triangles[out++] = triangles[f];
  triangles.resize(out);
}

// The referenced vertices, in input order: original_vertex[v] is the input index of vertex v, new_index[i]
// the vertex input vertex i became (-1: unreferenced). The triangles are renumbered.
struct Compacted {
  std::vector<std::int32_t> original_vertex, new_index;
};

Compacted compact_vertices(std::vector<Triangle>& triangles, const std::vector<std::int32_t>& representative,
                           PrepareReport& report) {
  const auto input_count = static_cast<std::int32_t>(representative.size());
  Compacted compacted;
  auto& new_index = compacted.new_index;
  new_index.assign(input_count, -1);
  for (const auto& t : triangles)
    for (auto v : t) new_index[v] = 0;
  for (std::int32_t i = 0; i < input_count; ++i) {
    if (new_index[i] == 0) {
      new_index[i] = static_cast<std::int32_t>(compacted.original_vertex.size());
      compacted.original_vertex.push_back(i);
    } else if (representative[i] == i) {
      ++report.unreferenced_vertices;
    }
  }
  for (auto& t : triangles)
    for (auto& v : t) v = new_index[v];
  return compacted;
}

// Throws MeshRefused when an edge has one triangle (a hole) or more than two.
void require_closed_manifold_edges(const std::vector<EdgeIncidence>& edges, const std::string& name,
                                   double weld_tolerance) {
  std::int64_t boundary_edges = 0, nonmanifold_edges = 0;
  for (std::size_t k = 0; k < edges.size();) {
    std::size_t j = k;
    while (j < edges.size() && edges[j].low == edges[k].low && edges[j].high == edges[k].high) ++j;
    if (j - k == 1) ++boundary_edges;
    if (j - k > 2) ++nonmanifold_edges;
    k = j;
  }
  if (boundary_edges == 0 && nonmanifold_edges == 0) return;
  std::vector<std::string> problems;
  if (boundary_edges > 0)
    problems.push_back(plural(boundary_edges, "boundary edge (the surface is open: it has holes)",
                              "boundary edges (the surface is open: it has holes)"));
  if (nonmanifold_edges > 0)
    problems.push_back(plural(nonmanifold_edges, "non-manifold edge (shared by more than two triangles)",
                              "non-manifold edges (shared by more than two triangles)"));
  throw MeshRefused(fmt::format(
      "{}: not a closed 2-manifold: {}. spheremap maps closed surfaces only: close the holes and remove "
      "the extra sheets (e.g. MeshLab 'Close Holes', 'Repair non Manifold Edges'){}",
      name, fmt::join(problems, "; "), weld_tolerance == 0 ? ", or weld nearby vertices with --weld-tolerance" : ""));
}

// Throws MeshRefused when the corners at a vertex, joined across shared edges, form more than one fan
// (sheets touching at a single point). Preconditions: every edge has exactly two incidences.
void require_single_fans(const std::vector<Triangle>& triangles, const std::vector<EdgeIncidence>& edges,
                         const std::vector<std::int32_t>& original_vertex, const std::string& name) {
  const auto vertex_count = static_cast<std::int32_t>(original_vertex.size());
  UnionFind<std::int64_t> corners(triangles.size() * 3);
  auto corner_of = [&](std::int32_t face, std::int32_t vertex) {
    const auto& t = triangles[face];
    return static_cast<std::int64_t>(face) * 3 + (t[0] == vertex ? 0 : t[1] == vertex ? 1 : 2);
  };
  for (std::size_t k = 0; k < edges.size(); k += 2) {
    const auto& e = edges[k];
    const auto& g = edges[k + 1];
    corners.join(corner_of(e.face, e.low), corner_of(g.face, e.low));
    corners.join(corner_of(e.face, e.high), corner_of(g.face, e.high));
  }
  std::vector<std::int64_t> first_fan(vertex_count, -1);
  std::vector<char> pinched(vertex_count, 0);
  for (std::size_t f = 0; f < triangles.size(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const auto v = triangles[f][k];
      const auto root = corners.find(static_cast<std::int64_t>(f) * 3 + k);
      if (first_fan[v] < 0)
        first_fan[v] = root;
      else if (first_fan[v] != root)
        pinched[v] = 1;
    }
  }
  const auto pinched_count = std::count(pinched.begin(), pinched.end(), 1);
  if (pinched_count == 0) return;
  const auto first = std::find(pinched.begin(), pinched.end(), 1) - pinched.begin();
  throw MeshRefused(
      fmt::format("{}: not a 2-manifold: {} where separate sheets touch at a single point (first: input vertex {}). "
                  "Split the vertex into one copy per sheet, or remove the extra sheet, and try again",
                  name, plural(pinched_count, "pinched (non-manifold) vertex", "pinched (non-manifold) vertices"),
                  original_vertex[first]));
}

// Connected components of the triangles (across shared edges), numbered in the order of their first
// triangle: component_of_face, and the triangle count of each.
struct FaceComponents {
  std::vector<std::int32_t> component_of_face;
  std::vector<std::int64_t> sizes;
};

FaceComponents face_components(std::size_t triangle_count, const std::vector<EdgeIncidence>& edges) {
  UnionFind<std::int64_t> sets(triangle_count);
  for (std::size_t k = 0; k < edges.size(); k += 2) sets.join(edges[k].face, edges[k + 1].face);
  FaceComponents components;
  components.component_of_face.resize(triangle_count);
  std::vector<std::int32_t> number_of_root(triangle_count, -1);  // roots are face indices
  for (std::size_t f = 0; f < triangle_count; ++f) {
    auto& number = number_of_root[static_cast<std::size_t>(sets.find(static_cast<std::int64_t>(f)))];
    if (number < 0) number = static_cast<std::int32_t>(components.sizes.size()), components.sizes.push_back(0);
    components.component_of_face[f] = number;
    ++components.sizes[static_cast<std::size_t>(number)];
  }
  return components;
}

// The component options.component asks for; throws MeshRefused when there are several and it says to
// refuse them, and InputError (a command-line error) when the one asked for does not exist.
std::int32_t choose_component(const std::vector<std::int64_t>& sizes, const PrepareOptions& options,
                              const std::string& name) {
  if (sizes.size() > 1) {
    if (options.component.mode == ComponentChoice::Mode::kRefuse) {
      std::vector<std::string> listed;
      for (std::size_t c = 0; c < sizes.size() && c < 8; ++c)
        listed.push_back(fmt::format("#{}: {} triangles", c, sizes[c]));
      if (sizes.size() > 8) listed.push_back("...");
      throw MeshRefused(
          fmt::format("{}: the mesh has {} separate connected components ({}); a sphere map needs one. "
                      "Choose one with --component largest or --component N",
                      name, sizes.size(), fmt::join(listed, ", ")));
    }
    if (options.component.mode == ComponentChoice::Mode::kLargest)
      return static_cast<std::int32_t>(std::max_element(sizes.begin(), sizes.end()) - sizes.begin());
    if (options.component.mode == ComponentChoice::Mode::kNumbered && options.component.number >= 0 &&
        options.component.number < static_cast<std::int32_t>(sizes.size()))
      return options.component.number;
    throw InputError(fmt::format("{}: --component {} does not exist: the mesh has {} components, numbered 0 to {}",
                                 name, options.component.number, sizes.size(), sizes.size() - 1));
  }
  if (options.component.mode == ComponentChoice::Mode::kNumbered && options.component.number >= 1)
    throw InputError(fmt::format("{}: --component {} does not exist: the mesh has 1 component, numbered 0", name,
                                 options.component.number));
  return 0;
}

// Orients the triangles `face_ids` (one component) consistently by breadth-first search across shared
// edges, then outward (positive enclosed volume); counts the flips. Throws MeshRefused if the component
// is not orientable.
void orient_outward(std::vector<Triangle>& triangles, const std::vector<EdgeIncidence>& edges,
                    const std::vector<std::int32_t>& face_ids, const std::vector<Vec3>& input_positions,
                    const std::vector<std::int32_t>& original_vertex, const std::string& name, PrepareReport& report) {
  // Neighbour across each edge: the other incidence of the same undirected edge.
  std::vector<std::array<std::int32_t, 3>> across(triangles.size());
  std::vector<std::array<char, 3>> same_direction(triangles.size());
  for (std::size_t k = 0; k < edges.size(); k += 2) {
    const auto& e = edges[k];
    const auto& g = edges[k + 1];
    auto slot = [&](const EdgeIncidence& x) {
      const auto& t = triangles[x.face];
      for (int s = 0; s < 3; ++s)
        if (std::min(t[s], t[(s + 1) % 3]) == x.low && std::max(t[s], t[(s + 1) % 3]) == x.high) return s;
      return 0;
    };
    const int se = slot(e), sg = slot(g);
    across[e.face][se] = g.face;
    across[g.face][sg] = e.face;
    same_direction[e.face][se] = same_direction[g.face][sg] = (e.forward == g.forward);
  }
  std::vector<signed char> flip(triangles.size(), -1);
  std::vector<std::int32_t> queue;
  queue.reserve(face_ids.size());
  flip[face_ids.front()] = 0;
  queue.push_back(face_ids.front());
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const auto f = queue[head];
    for (int s = 0; s < 3; ++s) {
      const auto g = across[f][s];
      const signed char wanted = static_cast<signed char>(flip[f] ^ (same_direction[f][s] ? 1 : 0));
      if (flip[g] < 0) {
        flip[g] = wanted;
        queue.push_back(g);
      } else if (flip[g] != wanted) {
        throw MeshRefused(
            fmt::format("{}: the surface is not orientable (like a Moebius strip or Klein bottle), so it cannot be "
                        "mapped one-to-one onto a sphere",
                        name));
      }
    }
  }
  // Relative to a point of the surface: far from the origin, raw triple products cancel and the sign of
  // the volume is lost (a mesh offset by 1e9 came out inside-out).
  const Vec3 origin = input_positions[original_vertex[triangles[face_ids.front()][0]]];
  double volume6 = 0;
  for (auto f : face_ids) {
    auto& t = triangles[f];
    if (flip[f]) std::swap(t[1], t[2]);
    volume6 +=
        dot(input_positions[original_vertex[t[0]]] - origin,
            cross(input_positions[original_vertex[t[1]]] - origin, input_positions[original_vertex[t[2]]] - origin));
  }
  const bool turn_outward = volume6 < 0;
  for (auto f : face_ids) {
    if (turn_outward) std::swap(triangles[f][1], triangles[f][2]);
    report.triangles_flipped += (flip[f] != 0) != turn_outward;
  }
}

// The vertices' attributes of `from` (input indices) for the mesh's vertices.
void copy_attributes(const Mesh& from, const std::vector<std::int32_t>& original_vertex, Mesh& mesh) {
  for (const auto& [key, values] : from.real_attributes) {
    auto& out = mesh.real_attributes[key];
    for (auto v : original_vertex) out.push_back(values[v]);
  }
  for (const auto& [key, values] : from.integer_attributes) {
    auto& out = mesh.integer_attributes[key];
    for (auto v : original_vertex) out.push_back(values[v]);
  }
  for (const auto& [key, text] : from.text_attributes) {
    auto& out = mesh.text_attributes[key];
    out.dictionary = text.dictionary;
    for (auto v : original_vertex) out.codes.push_back(text.codes[v]);
  }
}

// Faces: a vector of polygons (a file's soup) or of Triangles (a Mesh, without a copy per face).
template <typename Faces>
PreparedMesh prepare_triangles(const std::vector<Vec3>& input_positions, const Faces& faces,
                               const PrepareOptions& options, const Mesh* attributes_from) {
  const std::string& name = options.source_name;
  PrepareReport report;
  report.input_vertices = static_cast<std::int64_t>(input_positions.size());
  report.input_faces = static_cast<std::int64_t>(faces.size());
  check_input(input_positions, faces, name);
  const auto input_count = static_cast<std::int32_t>(input_positions.size());
  const auto representative = weld_representatives(input_positions, options.weld_tolerance);
  for (std::int32_t i = 0; i < input_count; ++i) report.vertices_welded += representative[i] != i;

  std::vector<Triangle> triangles = triangulate(faces, representative, report);
  drop_duplicate_triangles(triangles, report);
  if (triangles.empty())
    throw MeshRefused(fmt::format("{}: every face is degenerate (repeated corners); nothing to map", name));
  const Compacted compacted = compact_vertices(triangles, representative, report);
  const auto& original_vertex = compacted.original_vertex;
  const auto vertex_count = static_cast<std::int32_t>(original_vertex.size());

  const auto edges = group_edges(vertex_count, triangles);
  require_closed_manifold_edges(edges, name, options.weld_tolerance);
  require_single_fans(triangles, edges, original_vertex, name);
  const FaceComponents components = face_components(triangles.size(), edges);
  report.components = static_cast<std::int64_t>(components.sizes.size());
  const std::int32_t kept = choose_component(components.sizes, options, name);
  report.component_kept = kept;
  std::vector<std::int32_t> face_ids;
  for (std::size_t f = 0; f < triangles.size(); ++f)
    if (components.component_of_face[f] == kept) face_ids.push_back(static_cast<std::int32_t>(f));
  orient_outward(triangles, edges, face_ids, input_positions, original_vertex, name, report);

  // Keep the chosen component; its vertices keep their input order, so that with nothing welded or
  // dropped a vertex has the same index in the outputs as in the input file.
  std::vector<std::int32_t> component_index(vertex_count, -1);
  PreparedMesh result;
  Mesh& mesh = result.mesh;
  std::int64_t edge_count = 0;
  for (std::size_t k = 0; k < edges.size(); k += 2) edge_count += components.component_of_face[edges[k].face] == kept;
  for (auto f : face_ids)
    for (auto v : triangles[f]) component_index[v] = 0;
  for (std::int32_t v = 0; v < vertex_count; ++v) {
    if (component_index[v] < 0) continue;
    component_index[v] = static_cast<std::int32_t>(mesh.positions.size());
    mesh.positions.push_back(input_positions[original_vertex[v]]);
    report.original_vertex.push_back(original_vertex[v]);
  }
  for (auto f : face_ids) {
    Triangle t = triangles[f];
    for (auto& v : t) v = component_index[v];
    mesh.triangles.push_back(t);
  }
  report.vertex_of_input.assign(input_count, -1);
  for (std::int32_t i = 0; i < input_count; ++i) {
    const auto compact = compacted.new_index[representative[i]];
    if (compact >= 0 && component_index[compact] >= 0) report.vertex_of_input[i] = component_index[compact];
  }
  const std::int64_t euler =
      static_cast<std::int64_t>(mesh.positions.size()) - edge_count + static_cast<std::int64_t>(mesh.triangles.size());
  report.genus = static_cast<int>((2 - euler) / 2);
  if (euler != 2) {
    throw MeshRefused(fmt::format(
        "{}: the surface has genus {} ({}; Euler characteristic {}), but a one-to-one map onto a sphere needs "
        "genus 0. Close the handles first (spheremap repairs the molecular surfaces it builds, not given meshes)",
        name, report.genus, plural(report.genus, "handle or tunnel", "handles or tunnels"), euler));
  }
  if (attributes_from) copy_attributes(*attributes_from, report.original_vertex, mesh);
  result.report = std::move(report);
  return result;
}

}  // namespace

PreparedMesh prepare_mesh(const PolygonSoup& soup, const PrepareOptions& options) {
  return prepare_triangles(soup.positions, soup.faces, options, nullptr);
}

PreparedMesh prepare_mesh(const Mesh& mesh, const PrepareOptions& options) {
  return prepare_triangles(mesh.positions, mesh.triangles, options, &mesh);
}

}  // namespace spheremap
