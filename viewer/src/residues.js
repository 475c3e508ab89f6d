// Atoms and residues: how the page names them, and the residue search ("A:45", "A:45B", "45", "A:GLY45").

export function atomText(atoms, atom, field) {
  return atoms.strings[atoms[field][atom]];
}

// "A:GLY 45" (chain, residue name, number and insertion code), the residue's name as the labels show it.
export function residueLabel(atoms, atom) {
  const chain = atomText(atoms, atom, 'chain');
  const name = atomText(atoms, atom, 'residueName');
  const number = `${atoms.residueNumber[atom]}${atomText(atoms, atom, 'insertionCode')}`;
  return `${chain ? `${chain}:` : ''}${name ? `${name} ` : ''}${number}`;
}

// Parses a residue query: [chain ':'] [residue name] number [insertion code]. Returns null if it is not
// one; chain and name are null when not given (any chain / any name matches).
export function parseResidueQuery(text) {
  const m = /^\s*(?:([^:\s]+)\s*:)?\s*([A-Za-z]{1,4}(?=\s*-?\d))?\s*(-?\d+)\s*([A-Za-z]?)\s*$/.exec(text);
  if (!m) return null;
  return {
    chain: m[1] ?? null,
    name: m[2] ? m[2].toUpperCase() : null,
    number: Number(m[3]),
    insertion: m[4] ?? '',
  };
}

function atomMatches(atoms, atom, query) {
  if (atoms.residueNumber[atom] !== query.number) return false;
  if (atomText(atoms, atom, 'insertionCode').toUpperCase() !== query.insertion.toUpperCase()) return false;
  if (query.chain !== null && atomText(atoms, atom, 'chain') !== query.chain) return false;
  return query.name === null || atomText(atoms, atom, 'residueName').toUpperCase() === query.name;
}

// The vertices whose atom belongs to the residue(s) the query names, and one matching atom (for the
// label), or { vertices: [], atom: -1 }.
export function findResidueVertices(data, query) {
  const { atoms, vertexAtoms } = data;
  const matching = new Uint8Array(atoms.count);
  let firstAtom = -1;
  for (let a = 0; a < atoms.count; ++a) {
    if (atomMatches(atoms, a, query)) {
      matching[a] = 1;
      if (firstAtom < 0) firstAtom = a;
    }
  }
  const vertices = [];
  for (let v = 0; v < vertexAtoms.length; ++v) {
    const a = vertexAtoms[v];
    if (a >= 0 && matching[a]) vertices.push(v);
  }
  return { vertices, atom: firstAtom };
}
