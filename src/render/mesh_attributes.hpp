// Looking up a mapped mesh's per-vertex attributes by name, for the pictures and the viewer (render/).
#pragma once

#include <map>
#include <string>

namespace spheremap::detail {

/// The per-vertex attribute `name` in one of a Mesh's attribute maps (real_attributes, integer_attributes,
/// text_attributes), or nullptr when the mesh has none of that name. Never throws.
template <typename Values>
const Values* find_attribute(const std::map<std::string, Values>& attributes, const std::string& name) {
  const auto found = attributes.find(name);
  return found == attributes.end() ? nullptr : &found->second;
}

}  // namespace spheremap::detail
