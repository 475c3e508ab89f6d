// The default view, as PyMOL's "orient": the camera looks along the surface's axis of least spread, with
// the axis of most spread across the screen, so that the widest face of the molecule is shown.

// Eigenvectors of a symmetric 3x3 matrix (rows of arrays) by cyclic Jacobi rotations, as columns sorted by
// decreasing eigenvalue: [[x, y, z], ...] for the largest, middle and smallest.
export function principalAxes(m) {
  const a = m.map((row) => [...row]);
  const v = [[1, 0, 0], [0, 1, 0], [0, 0, 1]];
  for (let sweep = 0; sweep < 50; ++sweep) {
    const off = a[0][1] ** 2 + a[0][2] ** 2 + a[1][2] ** 2;
    if (off < 1e-30) break;
    for (const [p, q] of [[0, 1], [0, 2], [1, 2]]) {
      if (Math.abs(a[p][q]) < 1e-300) continue;
      const theta = (a[q][q] - a[p][p]) / (2 * a[p][q]);
      const t = Math.sign(theta || 1) / (Math.abs(theta) + Math.sqrt(theta * theta + 1));
      const c = 1 / Math.sqrt(t * t + 1), s = t * c;
      for (let k = 0; k < 3; ++k) {  // a = a J
        const akp = a[k][p], akq = a[k][q];
        a[k][p] = c * akp - s * akq;
        a[k][q] = s * akp + c * akq;
      }
      for (let k = 0; k < 3; ++k) {  // a = J^T a
        const apk = a[p][k], aqk = a[q][k];
        a[p][k] = c * apk - s * aqk;
        a[q][k] = s * apk + c * aqk;
      }
      for (let k = 0; k < 3; ++k) {  // v = v J
        const vkp = v[k][p], vkq = v[k][q];
        v[k][p] = c * vkp - s * vkq;
        v[k][q] = s * vkp + c * vkq;
      }
    }
  }
  const order = [0, 1, 2].sort((i, j) => a[j][j] - a[i][i]);
  return order.map((i) => {
    const axis = [v[0][i], v[1][i], v[2][i]];
    // A fixed sign (largest component positive), so the same data always opens the same way.
    let big = 0;
    for (let k = 1; k < 3; ++k) if (Math.abs(axis[k]) > Math.abs(axis[big])) big = k;
    return axis[big] < 0 ? axis.map((x) => -x) : axis;
  });
}

// The covariance of packed xyz positions (already centred).
export function covariance(positions) {
  const m = [[0, 0, 0], [0, 0, 0], [0, 0, 0]];
  const n = positions.length / 3;
  for (let v = 0; v < n; ++v) {
    for (let i = 0; i < 3; ++i) {
      for (let j = i; j < 3; ++j) m[i][j] += positions[3 * v + i] * positions[3 * v + j];
    }
  }
  for (let i = 0; i < 3; ++i) for (let j = i; j < 3; ++j) { m[i][j] /= n; m[j][i] = m[i][j]; }
  return m;
}

// Camera direction (from the centre towards the camera) and up vector: the least and middle axes, made
// right-handed with the largest axis pointing right on screen.
export function orientation(positions) {
  const [largest, middle] = principalAxes(covariance(positions));
  // right x up = towards the viewer.
  const towards = [
    largest[1] * middle[2] - largest[2] * middle[1],
    largest[2] * middle[0] - largest[0] * middle[2],
    largest[0] * middle[1] - largest[1] * middle[0],
  ];
  return { towards, up: middle };
}
