// The two views: the surface on the left, the sphere on the right, drawn by one renderer into two halves
// of one canvas with ONE camera, so rotation and zoom are linked by construction.
import {
  BufferAttribute, BufferGeometry, Color, Mesh, MeshBasicMaterial, PerspectiveCamera, Raycaster, Scene,
  SphereGeometry, Vector2, Vector3, WebGLRenderer,
} from 'three';
import { TrackballControls } from 'three/examples/jsm/controls/TrackballControls.js';
import { surfaceMaterial } from './material.js';
import { orientation } from './orient.js';

export const VIEW_NAMES = ['surface', 'sphere'];
const BACKGROUND = new Color(0xffffff);
const FIELD_OF_VIEW = 25;  // degrees, vertical
const MARKER_RADIUS = 0.022;  // in units of the model's radius

// Positions moved to their centroid and scaled into the unit ball, so both models share one camera.
function normalized(positions) {
  const n = positions.length / 3;
  const centre = [0, 0, 0];
  for (let v = 0; v < n; ++v) for (let k = 0; k < 3; ++k) centre[k] += positions[3 * v + k] / n;
  let radius = 0;
  for (let v = 0; v < n; ++v) {
    const dx = positions[3 * v] - centre[0], dy = positions[3 * v + 1] - centre[1];
    radius = Math.max(radius, Math.hypot(dx, dy, positions[3 * v + 2] - centre[2]));
  }
  const scale = radius > 0 ? 1 / radius : 1;
  const out = new Float32Array(positions.length);
  for (let v = 0; v < n; ++v) for (let k = 0; k < 3; ++k) out[3 * v + k] = (positions[3 * v + k] - centre[k]) * scale;
  return out;
}

function makeMarker(scene) {
  // A white dot in a black ring, drawn over everything: visible on every colour scale. When the point is
  // hidden (the far side, or behind another part) the marker fades, and still shows where the point is.
  const ringMaterial = new MeshBasicMaterial({ color: 0x000000, depthTest: false, transparent: true });
  const dotMaterial = new MeshBasicMaterial({ color: 0xffffff, depthTest: false, transparent: true });
  const ring = new Mesh(new SphereGeometry(MARKER_RADIUS, 24, 16), ringMaterial);
  const dot = new Mesh(new SphereGeometry(MARKER_RADIUS * 0.6, 24, 16), dotMaterial);
  ring.renderOrder = 10;
  dot.renderOrder = 11;
  ring.add(dot);
  ring.visible = false;
  scene.add(ring);
  return ring;
}

function setMarkerHidden(marker, hidden) {
  marker.material.opacity = hidden ? 0.35 : 1;
  marker.children[0].material.opacity = hidden ? 0.35 : 1;
}

function makeModel(positions, triangles, material, entries, highlight) {
  const geometry = new BufferGeometry();
  geometry.setAttribute('position', new BufferAttribute(normalized(positions), 3));
  geometry.setIndex(new BufferAttribute(triangles, 1));
  geometry.computeVertexNormals();
  geometry.setAttribute('colourEntry', entries);
  geometry.setAttribute('highlight', highlight);
  geometry.computeBoundingSphere();
  const scene = new Scene();
  scene.background = BACKGROUND;
  const mesh = new Mesh(geometry, material);
  scene.add(mesh);
  return { scene, mesh, positions: geometry.attributes.position.array, marker: makeMarker(scene) };
}

export class Views {
  constructor(canvas, data) {
    this.canvas = canvas;
    this.data = data;
    this.renderer = new WebGLRenderer({ canvas, antialias: true });
    this.renderer.setPixelRatio(window.devicePixelRatio || 1);
    this.renderer.setScissorTest(true);
    this.material = surfaceMaterial(data.missingColour);
    // Shared by both models: one colour entry and one highlight per vertex.
    this.entries = new BufferAttribute(new Float32Array(data.vertexCount), 1);
    this.highlight = new BufferAttribute(new Float32Array(data.vertexCount), 1);
    this.models = [data.surface, data.sphere].map(
      (p) => makeModel(p, data.triangles, this.material, this.entries, this.highlight));
    this.camera = new PerspectiveCamera(FIELD_OF_VIEW, 1, 0.01, 100);
    this.raycaster = new Raycaster();
    this.needsRender = true;
    this.resize();
    this.lookAlong(orientation(this.models[0].positions));
    this.controls = new TrackballControls(this.camera, canvas);
    this.controls.rotateSpeed = 3.0;
    this.controls.zoomSpeed = 1.2;
    this.controls.panSpeed = 0.6;
    this.controls.dynamicDampingFactor = 0.25;
    this.controls.keys = ['', '', ''];  // no key bindings: the search box takes letters
    this.controls.addEventListener('change', () => { this.needsRender = true; });
    this.controls.saveState?.();
    // The canvas changes size with the window and with the header above it (which wraps as it fills).
    new ResizeObserver(() => this.resize()).observe(canvas);
  }

  // Puts the camera on the side `towards` (from the centre), at the fitting distance, `up` up.
  lookAlong({ towards, up }) {
    this.camera.position.set(...towards).normalize().multiplyScalar(this.fittingDistance());
    this.camera.up.set(...up).normalize();
    this.camera.lookAt(0, 0, 0);
    this.needsRender = true;
  }

  // The camera distance at which the unit ball fills ~80% of the view's height and width.
  fittingDistance() {
    const halfHeight = Math.tan((FIELD_OF_VIEW * Math.PI) / 360);
    return 1.25 / (halfHeight * Math.min(1, this.camera.aspect));
  }

  resize() {
    const width = this.canvas.clientWidth, height = this.canvas.clientHeight;
    this.renderer.setSize(width, height, false);
    this.camera.aspect = Math.max(1, width / 2) / Math.max(1, height);
    this.camera.updateProjectionMatrix();
    this.controls?.handleResize();
    this.needsRender = true;
  }

  // The rectangle of view i in CSS pixels from the canvas's top-left corner.
  viewport(i) {
    const width = this.canvas.clientWidth, height = this.canvas.clientHeight;
    const half = Math.floor(width / 2);
    return i === 0 ? { x: 0, y: 0, width: half, height } : { x: half, y: 0, width: width - half, height };
  }

  render() {
    const height = this.canvas.clientHeight;
    this.models.forEach((model, i) => {
      const r = this.viewport(i);
      // WebGL's viewport origin is the bottom-left corner.
      this.renderer.setViewport(r.x, height - r.y - r.height, r.width, r.height);
      this.renderer.setScissor(r.x, height - r.y - r.height, r.width, r.height);
      this.renderer.render(model.scene, this.camera);
    });
    this.needsRender = false;
  }

  frame() {
    this.controls.update();
    if (this.needsRender) this.render();
  }

  // Which view a canvas point (CSS pixels) is in, and its normalized device coordinates there.
  locate(x, y) {
    const i = x < this.viewport(1).x ? 0 : 1;
    const r = this.viewport(i);
    return { view: i, ndc: new Vector2(((x - r.x) / r.width) * 2 - 1, 1 - ((y - r.y) / r.height) * 2) };
  }

  // The surface point under canvas point (x, y): { view, triangle, barycentric, vertex (the nearest corner) }
  // or null.
  pick(x, y) {
    const { view, ndc } = this.locate(x, y);
    this.raycaster.setFromCamera(ndc, this.camera);
    const hit = this.raycaster.intersectObject(this.models[view].mesh, false)[0];
    if (!hit) return null;
    const corners = [hit.face.a, hit.face.b, hit.face.c];
    const weights = hit.barycoord ? hit.barycoord.toArray() : this.barycentric(view, corners, hit.point);
    let best = 0;
    for (let k = 1; k < 3; ++k) if (weights[k] > weights[best]) best = k;
    return { view, corners, weights, vertex: corners[best] };
  }

  barycentric(view, corners, point) {
    const p = this.models[view].positions;
    const [a, b, c] = corners.map((v) => new Vector3(p[3 * v], p[3 * v + 1], p[3 * v + 2]));
    const v0 = b.clone().sub(a), v1 = c.clone().sub(a), v2 = point.clone().sub(a);
    const d00 = v0.dot(v0), d01 = v0.dot(v1), d11 = v1.dot(v1), d20 = v2.dot(v0), d21 = v2.dot(v1);
    const denom = d00 * d11 - d01 * d01 || 1;
    const w1 = (d11 * d20 - d01 * d21) / denom, w2 = (d00 * d21 - d01 * d20) / denom;
    return [1 - w1 - w2, w1, w2];
  }

  // The point with barycentric `weights` in triangle `corners` of view i (scene coordinates).
  pointOn(i, corners, weights) {
    const p = this.models[i].positions;
    const out = new Vector3();
    corners.forEach((v, k) => out.add(new Vector3(p[3 * v], p[3 * v + 1], p[3 * v + 2]).multiplyScalar(weights[k])));
    return out;
  }

  // Shows the markers at the same surface point on both views (null hides them). Returns, per view,
  // whether the point is hidden from the camera there.
  mark(corners, weights) {
    const hidden = this.models.map((model, i) => {
      model.marker.visible = corners !== null;
      if (!corners) return false;
      const point = this.pointOn(i, corners, weights);
      model.marker.position.copy(point);
      const isHidden = this.hidden(i, point);
      setMarkerHidden(model.marker, isHidden);
      return isHidden;
    });
    this.needsRender = true;
    return hidden;
  }

  // Whether something of model i lies between the camera and `point` (a point on model i).
  hidden(i, point) {
    const toPoint = point.clone().sub(this.camera.position);
    const distance = toPoint.length();
    this.raycaster.set(this.camera.position, toPoint.normalize());
    const hit = this.raycaster.intersectObject(this.models[i].mesh, false)[0];
    return hit !== undefined && hit.distance < distance - 1e-3;
  }

  // Canvas position (CSS pixels) of a scene point in view i.
  project(i, point) {
    const r = this.viewport(i);
    const ndc = point.clone().project(this.camera);
    return { x: r.x + ((ndc.x + 1) / 2) * r.width, y: r.y + ((1 - ndc.y) / 2) * r.height };
  }

  vertexPosition(i, v) {
    const p = this.models[i].positions;
    return new Vector3(p[3 * v], p[3 * v + 1], p[3 * v + 2]);
  }

  // The mean of the vertex normals of `vertices` on model i (unit, or zero).
  meanNormal(i, vertices) {
    const n = this.models[i].mesh.geometry.attributes.normal.array;
    const sum = new Vector3();
    for (const v of vertices) sum.add(new Vector3(n[3 * v], n[3 * v + 1], n[3 * v + 2]));
    return sum.normalize();
  }

  // Turns the camera (keeping its distance and target) to look along -direction: a patch whose normal is
  // `direction` faces the viewer in both views.
  face(direction) {
    const target = this.controls.target;
    if (direction.lengthSq() === 0) return;
    const distance = this.camera.position.distanceTo(target);
    this.camera.position.copy(target).addScaledVector(direction, distance);
    const up = this.camera.up.clone().addScaledVector(direction, -this.camera.up.dot(direction));
    if (up.lengthSq() > 1e-6) this.camera.up.copy(up.normalize());
    this.camera.lookAt(target);
    this.needsRender = true;
  }

  resetCamera() {
    this.controls.reset();
    this.needsRender = true;
  }
}
