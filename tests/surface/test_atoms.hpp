// Atoms for the surface tests.
#pragma once

#include "spheremap/molecule/structure.hpp"

namespace spheremap::testing_support {

/// A carbon atom at p; residue and model vary with the serial, so that provenance can be told apart.
inline Atom atom_at(const Vec3& p, double radius, int serial) {
  Atom a;
  a.position = p;
  a.radius = radius;
  a.serial = serial;
  a.element = "C";
  a.residue_number = serial / 10;
  a.model = 1 + serial % 2;
  return a;
}

}  // namespace spheremap::testing_support
