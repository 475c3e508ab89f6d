// The surfaces' material: colour from the property's colour table (entry per vertex, looked up per
// fragment, so that the colours between vertices follow the values), a highlight, and headlight shading
// (Lambert plus ambient plus a little specular) that shows shape from any angle.
import { DataTexture, DoubleSide, NearestFilter, RGBAFormat, ShaderMaterial, UnsignedByteType, Vector3 } from 'three';

const vertexShader = /* glsl */ `
uniform sampler2D colourTable;
uniform bool categorical;
uniform vec3 missingColour;
attribute float colourEntry;  // table entry + 0.5, or -1 for a missing value
attribute float highlight;     // 1 on the residue searched for
varying vec3 vNormal;
varying vec3 vViewPosition;
varying float vEntry;
varying float vMissing;
varying vec3 vVertexColour;
varying float vHighlight;
void main() {
  vec4 viewPosition = modelViewMatrix * vec4(position, 1.0);
  vViewPosition = -viewPosition.xyz;
  vNormal = normalize(normalMatrix * normal);
  vEntry = colourEntry;
  vMissing = colourEntry < 0.0 ? 1.0 : 0.0;
  // Classes are not ordered: a categorical colour is taken at the vertex and only blended between vertices.
  vVertexColour = colourEntry < 0.0 ? missingColour
                                    : texelFetch(colourTable, ivec2(int(colourEntry), 0), 0).rgb;
  vHighlight = highlight;
  gl_Position = projectionMatrix * viewPosition;
}
`;

const fragmentShader = /* glsl */ `
uniform sampler2D colourTable;
uniform bool categorical;
uniform vec3 missingColour;
uniform vec3 highlightColour;
uniform vec3 lightDirection;  // in view space, towards the light
varying vec3 vNormal;
varying vec3 vViewPosition;
varying float vEntry;
varying float vMissing;
varying vec3 vVertexColour;
varying float vHighlight;
void main() {
  vec3 base;
  if (vMissing > 0.5) {
    base = missingColour;
  } else if (categorical) {
    base = vVertexColour;
  } else {
    base = texelFetch(colourTable, ivec2(clamp(int(floor(vEntry)), 0, 255), 0), 0).rgb;
  }
  base = mix(base, highlightColour, 0.75 * clamp(vHighlight, 0.0, 1.0));
  vec3 n = normalize(vNormal);
  if (!gl_FrontFacing) n = -n;
  vec3 toEye = normalize(vViewPosition);
  float diffuse = max(dot(n, lightDirection), 0.0);
  float specular = pow(max(dot(n, normalize(lightDirection + toEye)), 0.0), 60.0);
  gl_FragColor = vec4(base * (0.42 + 0.58 * diffuse) + vec3(0.12 * specular), 1.0);
}
`;

// A colour table (256 RGB bytes) as a 256 x 1 texture read with texelFetch: exact entries, no filtering,
// no colour-space conversion (the table is sRGB and so is the canvas).
export function colourTableTexture(table) {
  const rgba = new Uint8Array(256 * 4);
  for (let i = 0; i < 256; ++i) {
    rgba[4 * i] = table[3 * i];
    rgba[4 * i + 1] = table[3 * i + 1];
    rgba[4 * i + 2] = table[3 * i + 2];
    rgba[4 * i + 3] = 255;
  }
  const texture = new DataTexture(rgba, 256, 1, RGBAFormat, UnsignedByteType);
  texture.minFilter = NearestFilter;
  texture.magFilter = NearestFilter;
  texture.generateMipmaps = false;
  texture.needsUpdate = true;
  return texture;
}

export function surfaceMaterial(missingColour) {
  return new ShaderMaterial({
    vertexShader,
    fragmentShader,
    side: DoubleSide,
    uniforms: {
      colourTable: { value: null },
      categorical: { value: false },
      missingColour: { value: new Vector3(...missingColour.map((c) => c / 255)) },
      highlightColour: { value: new Vector3(1.0, 0.0, 1.0) },
      lightDirection: { value: new Vector3(-0.35, 0.45, 1.0).normalize() },
    },
  });
}
