// The value -> colour-table entry rule, the same as colour_index in src/render/colour_scale.cpp (keep them
// equal), and the colour bar.

export const TABLE_SIZE = 256;

// C++'s std::round: halves away from zero (Math.round sends -0.5 to 0).
function roundHalfAway(x) {
  return Math.sign(x) * Math.round(Math.abs(x));
}

// The table entry of `value`, or -1 for a missing value (NaN).
export function colourIndex(scale, lo, hi, value) {
  if (Number.isNaN(value)) return -1;
  if (scale === 'categorical') {
    const k = roundHalfAway(value);
    return k >= 0 && k < TABLE_SIZE ? Math.abs(k) : -1;  // abs: -0 (from -0.4) is class 0
  }
  if (!(hi > lo)) return TABLE_SIZE / 2;
  const t = (value - lo) / (hi - lo);
  if (!(t > 0)) return 0;
  if (t >= 1) return TABLE_SIZE - 1;
  return Math.min(Math.trunc(t * TABLE_SIZE), TABLE_SIZE - 1);
}

export function cssColour(table, index, missing) {
  const c = index < 0 ? missing : [table[3 * index], table[3 * index + 1], table[3 * index + 2]];
  return `rgb(${c[0]}, ${c[1]}, ${c[2]})`;
}

// Draws the 256 entries left to right on `canvas` (its CSS size, at the device's pixel ratio).
export function drawColourBar(canvas, table) {
  const ratio = window.devicePixelRatio || 1;
  const width = Math.max(1, Math.round(canvas.clientWidth * ratio));
  const height = Math.max(1, Math.round(canvas.clientHeight * ratio));
  canvas.width = width;
  canvas.height = height;
  const context = canvas.getContext('2d');
  for (let x = 0; x < width; ++x) {
    const i = Math.min(TABLE_SIZE - 1, Math.floor((x / width) * TABLE_SIZE));
    context.fillStyle = cssColour(table, i, null);
    context.fillRect(x, 0, 1, height);
  }
}

// A number for the colour bar and the labels: 3 significant digits, no exponent for everyday magnitudes.
export function formatValue(value) {
  if (Number.isNaN(value)) return 'no value';
  if (value === 0) return '0';
  const magnitude = Math.abs(value);
  if (magnitude >= 1e-3 && magnitude < 1e6) return String(Number(value.toPrecision(3)));
  return value.toExponential(2);
}
