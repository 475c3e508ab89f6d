// Reads the data that spheremap embedded in the page: a JSON manifest and a deflated, base64-encoded
// blob of little-endian typed arrays (src/render/viewer_payload.cpp writes them).

const ARRAY_TYPES = { float32: Float32Array, int32: Int32Array, uint32: Uint32Array, uint8: Uint8Array };

function base64Bytes(text) {
  const binary = atob(text.trim());
  const bytes = new Uint8Array(binary.length);
  for (let i = 0; i < binary.length; ++i) bytes[i] = binary.charCodeAt(i);
  return bytes;
}

async function inflate(bytes) {
  if (typeof DecompressionStream === 'undefined') {
    throw new Error('this browser cannot decompress the embedded data (no DecompressionStream): ' +
                    'open the page in Chromium/Chrome 80+, Firefox 113+ or Safari 16.4+');
  }
  const stream = new Blob([bytes]).stream().pipeThrough(new DecompressionStream('deflate'));
  return new Response(stream).arrayBuffer();
}

function view(buffer, arrays, name) {
  const a = arrays[name];
  if (!a) throw new Error(`the embedded data lacks the array "${name}"`);
  return new ARRAY_TYPES[a.type](buffer, a.offset, a.count);
}

// Returns { title, vertexCount, triangleCount, surface, sphere, triangles, vertexAtoms, atoms, properties,
// missingColour }; atoms holds columns (chain, residueName, residueNumber, insertionCode, atomName) where
// the texts are indices into atoms.strings.
export async function readEmbeddedData(doc) {
  const manifest = JSON.parse(doc.getElementById('spheremap-manifest').textContent);
  if (manifest.format !== 'spheremap-viewer' || manifest.version !== 1) {
    throw new Error(`unknown data format ${manifest.format} ${manifest.version}`);
  }
  const buffer = await inflate(base64Bytes(doc.getElementById('spheremap-data').textContent));
  const arrays = manifest.arrays;
  const get = (name) => view(buffer, arrays, name);
  return {
    title: manifest.title,
    vertexCount: manifest.vertex_count,
    triangleCount: manifest.triangle_count,
    surface: get('surface_positions'),
    sphere: get('sphere_positions'),
    triangles: get('triangles'),
    vertexAtoms: get('vertex_atoms'),
    atoms: {
      count: manifest.atom_count,
      strings: manifest.strings,
      chain: get('atom_chain'),
      residueName: get('atom_residue_name'),
      residueNumber: get('atom_residue_number'),
      insertionCode: get('atom_insertion_code'),
      atomName: get('atom_name'),
    },
    properties: manifest.properties.map((p) => ({
      name: p.name,
      unit: p.unit,
      scale: p.scale,
      range: [p.range[0], p.range[1]],
      defaultRange: [p.range[0], p.range[1]],
      values: get(p.values),
      colours: get(p.colours),
      categories: p.categories,
    })),
    missingColour: manifest.missing_colour,
  };
}
