// Opens a generated index.html from file:// in a real browser and checks what a user sees: headless Chromium
// driven by playwright-core from the viewer's npm lock, or Firefox driven through Marionette
// (firefox_marionette.mjs), in a window of an X server such as Xvfb: headless Firefox makes no WebGL context
// without a GPU. Always the system's browser, never a downloaded one.
//
//   node viewer_browser_test.mjs SPEC.json
//
// SPEC (written by tests/render/viewer_browser_test.cpp): { browser: "chromium" | "firefox", executable, html,
// nodeModules, outputDir, title, hovers: [{ view, vertex, residue, atom }], search: { query, highlighted },
// colourChecks: [{ scale, lo, hi, value, index }] }. Prints what it checks; exit 0 when everything holds,
// 1 otherwise.
import { createRequire } from 'node:module';
import { mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { pathToFileURL } from 'node:url';
import { launchFirefox } from './firefox_marionette.mjs';

const spec = JSON.parse(readFileSync(process.argv[2], 'utf8'));
const playwright = createRequire(join(spec.nodeModules, 'noop.js'))('playwright-core');
const failures = [];
const check = (ok, what) => {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`);
  if (!ok) failures.push(what);
};

const started = Date.now();
const profile = mkdtempSync(join(tmpdir(), `spheremap-${spec.browser}-`));
const viewport = { width: 1400, height: 760 };
let context;
try {
  let page;
  const errors = [], requests = [];
  if (spec.browser === 'firefox') {
    page = await launchFirefox({ executable: spec.executable, profile, width: viewport.width, height: viewport.height });
    context = page;  // closed the same way
  } else {
    context = await playwright.chromium.launchPersistentContext(profile, {
      executablePath: spec.executable,
      headless: true,
      viewport,
      args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--disable-gpu-sandbox',
             '--no-first-run', '--disable-background-networking', '--disable-component-update', '--disable-sync'],
    });
    page = context.pages()[0] ?? await context.newPage();
    page.on('pageerror', (e) => errors.push(String(e)));
    page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
    page.on('request', (r) => {
      if (!r.url().startsWith('file:') && !r.url().startsWith('data:')) requests.push(r.url());
    });
  }

  await page.goto(pathToFileURL(spec.html).href);
  await page.waitForFunction(() => window.spheremapViewer?.ready || window.spheremapViewer?.error, null,
                             { timeout: 60000 });
  const error = await page.evaluate(() => window.spheremapViewer.error ?? null);
  check(error === null, `the viewer starts${error ? `: ${error}` : ''}`);
  if (error !== null) throw new Error(error);
  await page.waitForFunction(() => window.spheremapViewer.frames() > 3, null, { timeout: 30000 });
  console.log(`     drawn ${Date.now() - started} ms after launch`);

  const title = await page.title();
  check(title === spec.title, `the page's title is the data's title (${JSON.stringify(title)})`);
  const painted = await page.evaluate(() => window.spheremapViewer.paintedPixels());
  const half = (painted.width * painted.height) / 2;
  check(painted.surface > 0.05 * half && painted.sphere > 0.05 * half,
        `both views are drawn: ${painted.surface} and ${painted.sphere} of ${half} pixels differ from the background`);
  await page.screenshot({ path: join(spec.outputDir, 'viewer.png') });

  // The picks below are chosen in plain view from +z: look from there (the page opens "oriented").
  await page.evaluate(() => window.spheremapViewer.lookAlong([0, 0, 1], [0, 1, 0]));
  const frames = await page.evaluate(() => window.spheremapViewer.frames());
  await page.waitForFunction((n) => window.spheremapViewer.frames() > n, frames);
  for (const hover of spec.hovers) {
    const at = await page.evaluate(([view, v]) => window.spheremapViewer.vertexOnPage(view, v),
                                   [hover.view, hover.vertex]);
    await page.mouse.move(at.x, at.y);
    await page.waitForFunction((v) => document.getElementById('pick-where').textContent.startsWith(`vertex ${v} `),
                               hover.vertex, { timeout: 10000 }).catch(() => {});
    const label = await page.evaluate(() => ({
      residue: document.getElementById('pick-residue').textContent,
      atom: document.getElementById('pick-atom').textContent,
      value: document.getElementById('pick-value').textContent,
      where: document.getElementById('pick-where').textContent,
    }));
    check(label.where.startsWith(`vertex ${hover.vertex} `),
          `hover on the ${hover.view} at vertex ${hover.vertex} picks it (${label.where})`);
    check(label.residue === hover.residue && label.atom === `atom ${hover.atom}`,
          `the label names ${hover.residue}, atom ${hover.atom} ` +
          `(shows "${label.residue}", "${label.atom}", "${label.value}")`);
    // Both markers sit on the vertex, in both views.
    const markers = await page.evaluate(() => window.spheremapViewer.markersOnPage());
    for (const [i, view] of ['surface', 'sphere'].entries()) {
      const expected = await page.evaluate(([name, v]) => window.spheremapViewer.vertexOnPage(name, v),
                                           [view, hover.vertex]);
      const off = markers[i] ? Math.hypot(markers[i].x - expected.x, markers[i].y - expected.y) : Infinity;
      check(off < 4, `the ${view} view marks the point (${off.toFixed(2)} px from the vertex)`);
    }
  }
  await page.screenshot({ path: join(spec.outputDir, 'viewer-hover.png') });

  await page.fill('#search', spec.search.query);
  await page.press('#search', 'Enter');
  const highlighted = await page.evaluate(() => window.spheremapViewer.highlightedVertices());
  const result = await page.evaluate(() => document.getElementById('search-result').textContent);
  check(highlighted === spec.search.highlighted,
        `the search "${spec.search.query}" highlights ${highlighted} vertices, ` +
        `expected ${spec.search.highlighted} ("${result}")`);
  await page.waitForFunction(() => window.spheremapViewer.frames() > 0);
  await page.screenshot({ path: join(spec.outputDir, 'viewer-search.png') });

  const indices = await page.evaluate((checks) => checks.map(
    (c) => window.spheremapViewer.colourIndex(c.scale, c.lo, c.hi, c.value === null ? NaN : c.value)),
  spec.colourChecks);
  const wrong = spec.colourChecks.filter((c, i) => indices[i] !== c.index);
  check(wrong.length === 0, `the page's colour rule equals the C++ one on ${spec.colourChecks.length} values` +
        (wrong.length ? `; differs on ${JSON.stringify(wrong.slice(0, 3))}` : ''));

  // Marionette sees neither console messages nor requests (and the page's resource timing omits failed
  // loads, so it could not fail offline): these two are checked in Chromium.
  if (spec.browser === 'chromium') {
    check(errors.length === 0, `no script errors${errors.length ? `: ${errors.join(' | ')}` : ''}`);
    check(requests.length === 0, `no network requests${requests.length ? `: ${requests.join(' ')}` : ''}`);
  }
} catch (e) {
  check(false, `the browser session: ${e.message}`);
} finally {
  await context?.close();
  rmSync(profile, { recursive: true, force: true });
}
console.log(`${failures.length === 0 ? 'passed' : `${failures.length} failed`} in ${Date.now() - started} ms; ` +
            `${spec.browser}: screenshots in ${spec.outputDir}`);
process.exit(failures.length === 0 ? 0 : 1);
