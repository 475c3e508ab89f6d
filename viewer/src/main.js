// The viewer's entry point: reads the embedded data, builds the two views and the controls, and exposes a
// small hook for the browser test (window.spheremapViewer).
import { colourIndex, cssColour, drawColourBar, formatValue } from './colour.js';
import { readEmbeddedData } from './data.js';
import { colourTableTexture } from './material.js';
import { atomText, findResidueVertices, parseResidueQuery, residueLabel } from './residues.js';
import { VIEW_NAMES, Views } from './views.js';

const $ = (id) => document.getElementById(id);

// With no property, both surfaces are drawn in one light colour.
function plainProperty(vertexCount) {
  const colours = new Uint8Array(256 * 3);
  for (let i = 0; i < 256; ++i) colours.set([190, 196, 210], 3 * i);
  return { name: 'none', unit: '', scale: 'categorical', range: [0, 255], defaultRange: [0, 255],
           values: new Float32Array(vertexCount), colours, categories: [], plain: true };
}

class Viewer {
  constructor(data) {
    this.data = data;
    this.properties = data.properties.length > 0 ? data.properties : [plainProperty(data.vertexCount)];
    this.textures = this.properties.map((p) => colourTableTexture(p.colours));
    this.views = new Views($('view'), data);
    this.current = 0;
    this.pinned = false;
    this.pointer = null;
    this.lastPick = null;
    this.highlighted = 0;
    this.frames = 0;
    this.setUpPanel();
    this.selectProperty(0);
    this.setUpPointer();
  }

  get property() { return this.properties[this.current]; }

  setUpPanel() {
    document.title = this.data.title || document.title;
    $('title').textContent = this.data.title;
    $('counts').textContent = `${this.data.vertexCount.toLocaleString('en')} vertices, ` +
      `${this.data.triangleCount.toLocaleString('en')} triangles, ${this.data.atoms.count.toLocaleString('en')} atoms`;
    const picker = $('property');
    this.properties.forEach((p, i) => {
      const option = document.createElement('option');
      option.value = String(i);
      option.textContent = p.unit ? `${p.name} (${p.unit})` : p.name;
      picker.append(option);
    });
    picker.disabled = this.properties.length < 2 && this.properties[0].plain === true;
    picker.addEventListener('change', () => this.selectProperty(Number(picker.value)));
    const onRange = () => this.setRange(Number($('range-lo').value), Number($('range-hi').value));
    $('range-lo').addEventListener('change', onRange);
    $('range-hi').addEventListener('change', onRange);
    $('range-reset').addEventListener('click', () => {
      this.property.range = [...this.property.defaultRange];
      this.selectProperty(this.current);
    });
    $('search').addEventListener('keydown', (event) => {
      if (event.key === 'Enter') this.search($('search').value);
      if (event.key === 'Escape') { $('search').value = ''; this.search(''); }
    });
    $('search-go').addEventListener('click', () => this.search($('search').value));
    $('reset-view').addEventListener('click', () => this.views.resetCamera());
  }

  selectProperty(i) {
    this.current = i;
    $('property').value = String(i);
    const p = this.property;
    this.views.material.uniforms.colourTable.value = this.textures[i];
    this.views.material.uniforms.categorical.value = p.scale === 'categorical';
    const continuous = p.scale !== 'categorical';
    $('colour-bar-box').hidden = !continuous;
    $('legend').hidden = continuous || p.plain === true;
    if (continuous) {
      // Four significant digits in the boxes; the range itself stays exact until edited.
      $('range-lo').value = String(Number(p.range[0].toPrecision(4)));
      $('range-hi').value = String(Number(p.range[1].toPrecision(4)));
      $('range-unit').textContent = p.unit;
      drawColourBar($('colour-bar'), p.colours);
      this.drawTicks();
    } else {
      this.fillLegend();
    }
    this.recolour();
  }

  setRange(lo, hi) {
    const valid = Number.isFinite(lo) && Number.isFinite(hi) && hi > lo;
    $('range-error').hidden = valid;
    if (!valid) return;
    this.property.range = [lo, hi];
    this.drawTicks();
    this.recolour();
  }

  drawTicks() {
    const [lo, hi] = this.property.range;
    $('tick-mid').textContent = formatValue((lo + hi) / 2);
  }

  // The classes that occur, with their colours (at most 64 listed).
  fillLegend() {
    const p = this.property;
    const present = new Set();
    for (const v of p.values) {
      const k = colourIndex('categorical', 0, 0, v);
      if (k >= 0) present.add(k);
    }
    const legend = $('legend');
    legend.replaceChildren();
    [...present].sort((a, b) => a - b).slice(0, 64).forEach((k) => {
      const item = document.createElement('span');
      item.className = 'legend-item';
      const swatch = document.createElement('span');
      swatch.className = 'swatch';
      swatch.style.background = cssColour(p.colours, k, this.data.missingColour);
      item.append(swatch, document.createTextNode(p.categories[k] ?? String(k)));
      legend.append(item);
    });
  }

  recolour() {
    const p = this.property;
    const entries = this.views.entries.array;
    for (let v = 0; v < entries.length; ++v) {
      const k = colourIndex(p.scale, p.range[0], p.range[1], p.values[v]);
      entries[v] = k < 0 ? -1 : k + 0.5;
    }
    this.views.entries.needsUpdate = true;
    this.views.needsRender = true;
    if (this.lastPick) this.showPick(this.lastPick);
  }

  setUpPointer() {
    const canvas = $('view');
    canvas.addEventListener('pointermove', (event) => {
      const r = canvas.getBoundingClientRect();
      this.pointer = { x: event.clientX - r.left, y: event.clientY - r.top, buttons: event.buttons };
    });
    canvas.addEventListener('pointerleave', () => { this.pointer = null; });
    // A click (press and release without dragging) pins the label; another click releases it.
    canvas.addEventListener('pointerdown', (event) => { this.down = { x: event.clientX, y: event.clientY }; });
    canvas.addEventListener('pointerup', (event) => {
      if (!this.down || Math.hypot(event.clientX - this.down.x, event.clientY - this.down.y) > 3) return;
      const r = canvas.getBoundingClientRect();
      const pick = this.views.pick(event.clientX - r.left, event.clientY - r.top);
      this.pinned = pick !== null && !this.pinned;
      if (pick) this.showPick(pick);
    });
  }

  // Picks at most once per frame, and not while a button is down (rotating).
  hover() {
    if (!this.pointer || this.pinned || this.pointer.buttons) return;
    const pick = this.views.pick(this.pointer.x, this.pointer.y);
    this.pointer = null;
    if (pick) this.showPick(pick);
  }

  showPick(pick) {
    this.lastPick = pick;
    const hidden = this.views.mark(pick.corners, pick.weights);
    const v = pick.vertex;
    const atom = this.data.vertexAtoms[v];
    $('pick-residue').textContent = atom >= 0 ? residueLabel(this.data.atoms, atom) : 'no atom';
    $('pick-atom').textContent = atom >= 0 ? `atom ${atomText(this.data.atoms, atom, 'atomName')}` : '';
    const p = this.property;
    let value = '';
    if (!p.plain) {
      const raw = p.values[v];
      const category = p.scale === 'categorical' ? p.categories[colourIndex('categorical', 0, 0, raw)] : undefined;
      value = `${p.name}: ${category ?? formatValue(raw)}${p.unit && !Number.isNaN(raw) ? ` ${p.unit}` : ''}`;
    }
    $('pick-value').textContent = value;
    const unseen = VIEW_NAMES.filter((name, i) => hidden[i]);
    $('pick-where').textContent = `vertex ${v} · ${VIEW_NAMES[pick.view]} view` +
      `${unseen.length ? ` · out of sight on the ${unseen.join(' and ')}: rotate to see` : ''}` +
      `${this.pinned ? ' · pinned' : ''}`;
    $('pick').hidden = false;
  }

  search(text) {
    const highlight = this.views.highlight.array;
    highlight.fill(0);
    this.highlighted = 0;
    $('search-result').textContent = '';
    if (text.trim() !== '') {
      const query = parseResidueQuery(text);
      if (!query) {
        $('search-result').textContent = 'Type a residue as A:45, A:45B, A:GLY45 or 45';
      } else {
        const found = findResidueVertices(this.data, query);
        for (const v of found.vertices) highlight[v] = 1;
        this.highlighted = found.vertices.length;
        if (found.atom < 0) {
          $('search-result').textContent = 'No such residue';
        } else if (found.vertices.length === 0) {
          $('search-result').textContent = `${residueLabel(this.data.atoms, found.atom)} is buried: not on the surface`;
        } else {
          const label = residueLabel(this.data.atoms, found.atom);
          $('search-result').textContent = `${label}: ${found.vertices.length} surface points`;
          // Turn the residue's patch on the sphere (where nothing hides it) towards the viewer; the surface
          // turns with it. Mark the patch's middle on both views.
          this.views.face(this.views.meanNormal(1, found.vertices));
          const middle = this.nearest(found.vertices, this.centroid(found.vertices));
          this.showPick({ view: 0, corners: [middle, middle, middle], weights: [1, 0, 0], vertex: middle });
        }
      }
    }
    this.views.highlight.needsUpdate = true;
    this.views.needsRender = true;
  }

  centroid(vertices) {
    const c = this.views.vertexPosition(0, vertices[0]).multiplyScalar(0);
    for (const v of vertices) c.add(this.views.vertexPosition(0, v));
    return c.multiplyScalar(1 / vertices.length);
  }

  // The vertex of `vertices` nearest `point` on the surface.
  nearest(vertices, point) {
    let best = vertices[0], bestDistance = Infinity;
    for (const v of vertices) {
      const d = this.views.vertexPosition(0, v).distanceToSquared(point);
      if (d < bestDistance) { best = v; bestDistance = d; }
    }
    return best;
  }

  frame() {
    this.hover();
    this.views.frame();
    ++this.frames;
  }
}

// What the browser test reads and drives (tests/render/viewer_browser_test.cpp).
function testHook(viewer) {
  const views = viewer.views;
  const canvasPoint = (p) => {
    const r = views.canvas.getBoundingClientRect();
    return { x: r.left + p.x, y: r.top + p.y };
  };
  return {
    ready: true,
    frames: () => viewer.frames,
    // Page coordinates (CSS pixels) of vertex v in view 'surface' or 'sphere'.
    vertexOnPage: (view, v) => {
      const i = VIEW_NAMES.indexOf(view);
      return canvasPoint(views.project(i, views.vertexPosition(i, v)));
    },
    // Page coordinates of the two markers, or null when hidden.
    markersOnPage: () => views.models.map(
      (m, i) => (m.marker.visible ? canvasPoint(views.project(i, m.marker.position)) : null)),
    // Draws a frame and counts, per view, the pixels that differ from the background.
    paintedPixels: () => {
      views.render();
      const gl = views.renderer.getContext();
      const width = gl.drawingBufferWidth, height = gl.drawingBufferHeight;
      const pixels = new Uint8Array(width * height * 4);
      gl.readPixels(0, 0, width, height, gl.RGBA, gl.UNSIGNED_BYTE, pixels);
      const counts = [0, 0];
      for (let y = 0; y < height; ++y) {
        for (let x = 0; x < width; ++x) {
          const i = 4 * (y * width + x);
          if (Math.abs(pixels[i] - 255) + Math.abs(pixels[i + 1] - 255) + Math.abs(pixels[i + 2] - 255) > 24) {
            ++counts[x < width / 2 ? 0 : 1];
          }
        }
      }
      return { surface: counts[0], sphere: counts[1], width, height };
    },
    colourIndex,
    // The vertex picked at page point (x, y), or -1.
    pickAt: (x, y) => {
      const r = views.canvas.getBoundingClientRect();
      return views.pick(x - r.left, y - r.top)?.vertex ?? -1;
    },
    // Turns the camera to look from direction `towards` (from the centre) with `up` up.
    lookAlong: (towards, up) => { views.lookAlong({ towards, up }); views.controls.target.set(0, 0, 0); },
    highlightedVertices: () => viewer.highlighted,
    selectProperty: (i) => viewer.selectProperty(i),
  };
}

async function start() {
  try {
    const data = await readEmbeddedData(document);
    const viewer = new Viewer(data);
    const loop = () => { viewer.frame(); requestAnimationFrame(loop); };
    viewer.frame();
    window.spheremapViewer = testHook(viewer);
    requestAnimationFrame(loop);
  } catch (error) {
    $('error').textContent = `The viewer could not start: ${error.message}`;
    $('error').hidden = false;
    window.spheremapViewer = { ready: false, error: String(error.message) };
  }
}

start();
