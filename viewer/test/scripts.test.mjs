// The viewer's plain functions, under node's own test runner (node --test): the colour rule, residue
// queries, the default orientation. The page as a whole is tested in Chromium (tests/render/).
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { colourIndex, formatValue } from '../src/colour.js';
import { orientation, principalAxes } from '../src/orient.js';
import { findResidueVertices, parseResidueQuery, residueLabel } from '../src/residues.js';

test('continuous values fall in 256 equal bins and saturate; NaN is missing', () => {
  assert.equal(colourIndex('sequential', -2, 2, -2), 0);
  assert.equal(colourIndex('sequential', -2, 2, 0), 128);
  assert.equal(colourIndex('diverging', -2, 2, 2), 255);
  assert.equal(colourIndex('diverging', -2, 2, -1e300), 0);
  assert.equal(colourIndex('diverging', -2, 2, Infinity), 255);
  assert.equal(colourIndex('sequential', -2, 2, NaN), -1);
  assert.equal(colourIndex('sequential', 1, 1, 7), 128);
  for (let i = 0; i < 256; ++i) assert.equal(colourIndex('sequential', 0, 1, (i + 0.5) / 256), i);
});

test('categorical values round halves away from zero, as C++ std::round', () => {
  assert.equal(colourIndex('categorical', 0, 0, 2.5), 3);
  assert.equal(colourIndex('categorical', 0, 0, -0.4), 0);
  assert.equal(colourIndex('categorical', 0, 0, -0.5), -1);
  assert.equal(colourIndex('categorical', 0, 0, 255.5), -1);
});

test('values are shown with three significant digits', () => {
  assert.equal(formatValue(12.3456), '12.3');
  assert.equal(formatValue(-0.000123), '-1.23e-4');
  assert.equal(formatValue(NaN), 'no value');
  assert.equal(formatValue(0), '0');
});

test('residue queries', () => {
  assert.deepEqual(parseResidueQuery('A:45'), { chain: 'A', name: null, number: 45, insertion: '' });
  assert.deepEqual(parseResidueQuery(' B : gly 12a '), { chain: 'B', name: 'GLY', number: 12, insertion: 'a' });
  assert.deepEqual(parseResidueQuery('-3'), { chain: null, name: null, number: -3, insertion: '' });
  assert.deepEqual(parseResidueQuery('AB:TYR700'), { chain: 'AB', name: 'TYR', number: 700, insertion: '' });
  assert.equal(parseResidueQuery('A:'), null);
  assert.equal(parseResidueQuery('hello'), null);
});

test('a residue query finds the vertices of its atoms', () => {
  const strings = ['A', 'GLY', '', 'CA', 'B', 'N'];
  const atoms = {
    count: 3, strings,
    chain: [0, 0, 4], residueName: [1, 1, 1], residueNumber: [45, 45, 45], insertionCode: [2, 2, 2],
    atomName: [3, 5, 3],
  };
  const data = { atoms, vertexAtoms: Int32Array.from([0, 2, 1, -1, 1]) };
  assert.deepEqual(findResidueVertices(data, parseResidueQuery('A:45')), { vertices: [0, 2, 4], atom: 0 });
  assert.deepEqual(findResidueVertices(data, parseResidueQuery('45')).vertices, [0, 1, 2, 4]);
  assert.deepEqual(findResidueVertices(data, parseResidueQuery('A:46')), { vertices: [], atom: -1 });
  assert.equal(residueLabel(atoms, 2), 'B:GLY 45');
});

test('the default view looks along the axis of least spread, the longest axis across', () => {
  const axes = principalAxes([[4, 1, 0.5], [1, 3, 0.2], [0.5, 0.2, 1]]);
  const values = axes.map((a) => {
    const m = [[4, 1, 0.5], [1, 3, 0.2], [0.5, 0.2, 1]];
    const ma = m.map((row) => row[0] * a[0] + row[1] * a[1] + row[2] * a[2]);
    const lambda = ma.reduce((s, x, k) => s + x * a[k], 0);
    assert.ok(Math.hypot(...ma.map((x, k) => x - lambda * a[k])) < 1e-12);  // an eigenvector
    return lambda;
  });
  assert.ok(values[0] > values[1] && values[1] > values[2]);
  // A slab long in y, wide in z, thin in x: seen from +-x with z up.
  const points = [];
  for (let i = 0; i < 2000; ++i) points.push(0.2 * Math.sin(0.7 * i), 3 * Math.cos(i), 1.5 * Math.sin(1.3 * i));
  const { towards, up } = orientation(Float32Array.from(points));
  assert.ok(Math.abs(Math.abs(towards[0]) - 1) < 1e-3, `towards ${towards}`);
  assert.ok(Math.abs(Math.abs(up[2]) - 1) < 1e-3, `up ${up}`);
});
