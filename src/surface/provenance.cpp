#include "spheremap/surface/provenance.hpp"

#include <algorithm>
#include <optional>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include "spheremap/attributes.hpp"

namespace spheremap {
namespace {

// Builds a dictionary-coded text attribute; codes follow first appearance, so the output is deterministic.
// Vertices come from few atoms (each atom's code is looked up once, then reused).
class TextColumn {
 public:
  explicit TextColumn(std::size_t atoms, std::size_t vertices) : code_of_atom_(atoms, -1) {
    attribute_.codes.reserve(vertices);
  }
  // value_of(): the atom's text, asked for once per atom.
  template <typename Value>
  void push(std::size_t atom, Value&& value_of) {
    std::int32_t& code = code_of_atom_[atom];
    if (code < 0) {
      std::string value = value_of();
      auto [it, inserted] = index_.try_emplace(value, static_cast<std::int32_t>(attribute_.dictionary.size()));
      if (inserted) attribute_.dictionary.push_back(std::move(value));
      code = it->second;
    }
    attribute_.codes.push_back(code);
  }
  TextAttribute take() { return std::move(attribute_); }

 private:
  TextAttribute attribute_;
  std::unordered_map<std::string, std::int32_t> index_;
  std::vector<std::int32_t> code_of_atom_;
};

}  // namespace

void add_atom_provenance(Mesh& mesh, const std::vector<Atom>& atoms) {
  const auto found = mesh.integer_attributes.find(attributes::kAtomId);
  if (found == mesh.integer_attributes.end())
    throw std::invalid_argument("add_atom_provenance: the mesh has no 'atomid' attribute");
  const auto& atom_of = found->second;
  std::vector<std::int32_t> serial, residue_number, model;
  serial.reserve(atom_of.size());
  residue_number.reserve(atom_of.size());
  model.reserve(atom_of.size());
  TextColumn name(atoms.size(), atom_of.size()), element(atoms.size(), atom_of.size()),
      residue_name(atoms.size(), atom_of.size()), insertion_code(atoms.size(), atom_of.size()),
      chain(atoms.size(), atom_of.size());
  for (const std::int32_t index : atom_of) {
    if (index < 0 || static_cast<std::size_t>(index) >= atoms.size())
      throw std::invalid_argument("add_atom_provenance: an 'atomid' is not an index into the atoms");
    const Atom& atom = atoms[index];
    serial.push_back(atom.serial);
    residue_number.push_back(atom.residue_number);
    model.push_back(atom.model);
    const auto a = static_cast<std::size_t>(index);
    name.push(a, [&] { return atom.name; });
    element.push(a, [&] { return atom.element; });
    residue_name.push(a, [&] { return atom.residue_name; });
    insertion_code.push(
        a, [&] { return atom.insertion_code == ' ' ? std::string() : std::string(1, atom.insertion_code); });
    chain.push(a, [&] { return atom.chain; });
  }
  mesh.integer_attributes[attributes::kAtomSerial] = std::move(serial);
  mesh.integer_attributes[attributes::kResidueNumber] = std::move(residue_number);
  mesh.integer_attributes[attributes::kModel] = std::move(model);
  mesh.text_attributes[attributes::kAtomName] = name.take();
  mesh.text_attributes[attributes::kElement] = element.take();
  mesh.text_attributes[attributes::kResidueName] = residue_name.take();
  mesh.text_attributes[attributes::kInsertionCode] = insertion_code.take();
  mesh.text_attributes[attributes::kChain] = chain.take();
  // Per-atom values the file has (every atom of a PDB or mmCIF file has a B-factor, every atom of a PQR
  // file a charge): written only then, never as made-up zeros.
  auto per_vertex = [&](const char* attribute, std::optional<double> Atom::*value) {
    const bool present = !atoms.empty() &&
                         std::all_of(atoms.begin(), atoms.end(), [&](const Atom& a) { return (a.*value).has_value(); });
    if (!present) {
      mesh.real_attributes.erase(attribute);
      return;
    }
    std::vector<double> values;
    values.reserve(atom_of.size());
    for (const std::int32_t index : atom_of) values.push_back(*(atoms[static_cast<std::size_t>(index)].*value));
    mesh.real_attributes[attribute] = std::move(values);
  };
  per_vertex(attributes::kBFactor, &Atom::b_factor);
  per_vertex(attributes::kCharge, &Atom::charge);
}

}  // namespace spheremap
