#!/usr/bin/env node
// End-to-end test of genform's browser studio: starts the real `genform serve`, drives the page
// in Debian's headless Chromium through playwright-core, and checks each view does what a user
// would notice: sampling shows a model, a run plots live, a weight changed mid-run shows in the
// steering log and in run.json, breeding by picks advances two generations, and the best GLB
// downloads and passes the Khronos glTF validator. Screenshots of each view go to docs/img/.
//
//   node tests/studio/e2e.mjs            (from anywhere; scripts/test-studio installs and builds first)
//
// Environment: GENFORM_BIN (default target/debug/genform, under CARGO_TARGET_DIR when set), CHROMIUM (default /usr/bin/chromium),
// STUDIO_SCREENSHOTS (folder, default docs/img; "none" to skip), STUDIO_KEEP=1 keeps the temp folders,
// STUDIO_URL (test a server that is already running instead of starting one).

import { spawn } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';
import validator from 'gltf-validator';

const HERE = path.dirname(fileURLToPath(import.meta.url));
const REPO = path.resolve(HERE, '../..');
const BIN = path.resolve(REPO, process.env.GENFORM_BIN || path.join(process.env.CARGO_TARGET_DIR || 'target', 'debug/genform'));
const CHROMIUM = process.env.CHROMIUM || '/usr/bin/chromium';
const SHOTS = process.env.STUDIO_SCREENSHOTS === 'none' ? null : path.resolve(REPO, process.env.STUDIO_SCREENSHOTS || 'docs/img');
const KEEP = process.env.STUDIO_KEEP === '1';
// The scenes and grammars the test uses (root paths, as the server lists them).
const GRAMMAR_3D = 'examples/shape/spaceship.sg';
const GRAMMAR_2D = 'examples/graph/koch.gg.yaml';
const GRAMMAR_OPTIONS = { path: 'examples/hemls/tiles4.gr8', options: { steps: '6', env: 'examples/hemls/drape_sphere.toml' } };
const SCENE = 'examples/scenes/genr8_canopy.toml';
const VOLUME_SCENE = { path: 'examples/scenes/spaceship_volume.toml', generations: 40 };
// Two changes, one at a time: a criterion's weight, then a criterion's target.
const STEERED = [{ group: 'weights', name: 'symmetry', value: 3.5 }, { group: 'targets', name: 'size', value: 12 }];
const BREED_GRAMMAR = 'examples/shape/spaceship.sg';

const started = Date.now();
const tmp = fs.mkdtempSync(path.join(os.tmpdir(), 'genform-studio-e2e-'));
const outDir = path.join(tmp, 'out');
const profileDir = path.join(tmp, 'chromium-profile');
const downloads = path.join(tmp, 'downloads');
fs.mkdirSync(downloads, { recursive: true });

let server = null;
let serving = ''; // the server the page may talk to
let serverLog = '';
let context = null;
let page = null;
const pageErrors = [];
let editingDrafts = false; // the editor's step: a broken draft's 400 is expected
const liveModels = [];
let currentStep = 'setup';

class TestFailure extends Error {}
/** Fails the current step with `message` unless `cond`. */
function check(cond, message) {
  if (!cond) throw new TestFailure(message);
}

function log(message) {
  console.log(`[${((Date.now() - started) / 1000).toFixed(1).padStart(5)} s] ${message}`);
}

/** Runs one named step; its name prefixes any failure. */
async function step(name, fn) {
  currentStep = name;
  const t0 = Date.now();
  await fn();
  log(`ok   ${name} (${((Date.now() - t0) / 1000).toFixed(1)} s)`);
}

async function screenshot(name) {
  if (!SHOTS || !page) return;
  fs.mkdirSync(SHOTS, { recursive: true });
  await page.evaluate(() => document.querySelectorAll('.toast').forEach((t) => t.remove()));
  await page.mouse.move(0, 0); // no hover highlights
  await page.screenshot({ path: path.join(SHOTS, `studio-${name}.png`) });
}

/** Starts `genform serve --port 0` and resolves with the URL from its first stdout line. */
function startServer(cwd = REPO, out = outDir) {
  check(fs.existsSync(BIN), `${BIN} does not exist: build it with cargo build -p genform-cli (scripts/test-studio does)`);
  fs.mkdirSync(out, { recursive: true });
  server = spawn(BIN, ['serve', '--port', '0', '--out', out], { cwd, stdio: ['ignore', 'pipe', 'pipe'] });
  return new Promise((resolve, reject) => {
    let stdout = '';
    const timer = setTimeout(() => reject(new TestFailure(`genform serve printed no URL within 60 s; output so far:\n${stdout}${serverLog}`)), 60_000);
    server.stdout.on('data', (chunk) => {
      stdout += chunk;
      const firstLine = stdout.split('\n')[0];
      if (stdout.includes('\n')) {
        const match = firstLine.match(/https?:\/\/[^\s]+/);
        clearTimeout(timer);
        if (match) resolve(match[0].endsWith('/') ? match[0] : `${match[0]}/`);
        else reject(new TestFailure(`the first stdout line of genform serve has no URL: ${JSON.stringify(firstLine)}`));
      }
    });
    server.stderr.on('data', (chunk) => {
      serverLog += chunk;
    });
    server.on('exit', (code, signal) => {
      clearTimeout(timer);
      reject(new TestFailure(`genform serve exited early (code ${code}, signal ${signal}):\n${serverLog}`));
    });
  });
}

async function stopServer() {
  if (!server || server.exitCode !== null || server.signalCode !== null) return;
  const exited = new Promise((resolve) => server.once('exit', resolve));
  server.kill('SIGTERM');
  const timeout = new Promise((resolve) => setTimeout(() => resolve('timeout'), 5000));
  if ((await Promise.race([exited, timeout])) === 'timeout') {
    server.kill('SIGKILL');
    await exited;
  }
}

const byId = (id) => `[data-testid="${id}"]`;

/** Waits until `fn` (run in the page) returns a truthy value; fails with `what` after `ms`. */
async function waitFor(what, fn, arg, ms = 30_000) {
  try {
    const handle = await page.waitForFunction(fn, arg, { timeout: ms, polling: 100 });
    return await handle.jsonValue();
  } catch (err) {
    throw new TestFailure(`timed out after ${ms / 1000} s waiting for ${what}`);
  }
}

/** Counts the canvas's pixels that differ from its background (the model was drawn). */
const drawnPixels = (testid) => page.evaluate((id) => {
  const canvas = document.querySelector(`[data-testid="${id}"]`);
  if (!canvas) return -1;
  const probe = document.createElement('canvas');
  probe.width = 200;
  probe.height = Math.max(1, Math.round((200 * canvas.height) / canvas.width));
  const ctx = probe.getContext('2d');
  ctx.drawImage(canvas, 0, 0, probe.width, probe.height);
  const data = ctx.getImageData(0, 0, probe.width, probe.height).data;
  const [r0, g0, b0] = [data[0], data[1], data[2]];
  let differing = 0;
  for (let i = 0; i < data.length; i += 4) {
    if (Math.abs(data[i] - r0) + Math.abs(data[i + 1] - g0) + Math.abs(data[i + 2] - b0) > 40) differing++;
  }
  return differing;
}, testid);

/** Validates GLB bytes with the Khronos validator; fails listing the errors. */
async function validateGlb(bytes, name) {
  check(bytes.length > 20, `${name}: only ${bytes.length} bytes`);
  check(bytes.subarray(0, 4).toString('latin1') === 'glTF', `${name}: does not start with the GLB magic "glTF"`);
  const report = await validator.validateBytes(new Uint8Array(bytes), { uri: name, format: 'glb', maxIssues: 50 });
  const errors = report.issues.messages.filter((m) => m.severity === 0);
  check(report.issues.numErrors === 0,
    `${name}: gltf-validator found ${report.issues.numErrors} errors:\n${errors.map((m) => `  ${m.code} ${m.pointer || ''}: ${m.message}`).join('\n')}`);
  return report;
}

/** GET `url` from the page's origin (same cookies/origin as the page) as a Buffer. */
async function getBytes(url) {
  const res = await context.request.get(url);
  check(res.ok(), `GET ${url} answered ${res.status()}: ${(await res.text()).slice(0, 300)}`);
  return Buffer.from(await res.body());
}

async function getJson(url) {
  return JSON.parse((await getBytes(url)).toString('utf8'));
}

async function main() {
  let base = process.env.STUDIO_URL; // a server already running (for developing the test)
  if (!base) {
    await step('start genform serve', async () => {
      base = await startServer();
      log(`     server at ${base}`);
    });
  }

  serving = base;
  await step('launch Chromium', async () => {
    check(fs.existsSync(CHROMIUM), `${CHROMIUM} is missing: apt-get install -y chromium (scripts/test-studio does)`);
    context = await chromium.launchPersistentContext(profileDir, {
      executablePath: CHROMIUM,
      headless: true,
      args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run', '--disable-background-networking',
        '--disable-component-update', '--disable-sync'],
      viewport: { width: 1400, height: 860 },
      acceptDownloads: true,
      baseURL: base,
    });
    page = context.pages()[0] || (await context.newPage());
    page.on('pageerror', (err) => pageErrors.push(`page error: ${err.message}`));
    // Live best models the page fetched while runs went (`/api/runs/<id>/best.glb`).
    page.on('response', (r) => {
      if (r.url().includes('/best.glb?') && r.ok()) liveModels.push(r.url());
    });
    page.on('console', (msg) => {
      // A draft that does not compile answers 400 with its diagnostics: expected while editing.
      const draftError = editingDrafts && msg.text().includes('status of 400') && msg.location().url.endsWith('/api/sample');
      if (msg.type() === 'error' && !draftError) pageErrors.push(`console error: ${msg.text()}`);
    });
    // The page must work offline: any request that leaves the server is a failure.
    await context.route((url) => !url.href.startsWith(serving), (route) => {
      pageErrors.push(`request outside the server: ${route.request().url()}`);
      route.abort();
    });
  });

  await step('load the page', async () => {
    await page.goto(base);
    await waitFor('the page to load the grammar list', () => document.body.dataset.ready === 'true');
    const names = await page.locator(`${byId('explore-grammar')} option`).count();
    check(names > 5, `the grammar list has ${names} entries; expected the shipped examples`);
    for (const tab of ['explore', 'run', 'steer', 'breed']) check(await page.locator(byId(`tab-${tab}`)).isVisible(), `tab ${tab} is not visible`);
  });

  await step('explore: sample a 2D grammar (SVG)', async () => {
    await page.click(byId('tab-explore'));
    await page.selectOption(byId('explore-grammar'), GRAMMAR_2D);
    await waitFor(`the SVG drawing of ${GRAMMAR_2D}`, () => {
      const v = document.querySelector('[data-testid="explore-viewer"]');
      const img = document.querySelector('[data-testid="explore-viewer-picture"]');
      return v.dataset.state === 'loaded' && v.dataset.kind === '2d' && img.naturalWidth > 0 && img.src.includes('.svg');
    }, null, 60_000);
  });

  await step('explore: sample a 3D grammar (GLB in the 3D view)', async () => {
    await page.selectOption(byId('explore-grammar'), GRAMMAR_3D);
    await waitFor(`a loaded 3D model of ${GRAMMAR_3D}`, () => {
      const v = document.querySelector('[data-testid="explore-viewer"]');
      return v.dataset.state === 'loaded' && v.dataset.kind === '3d';
    }, null, 60_000);
    const first = await page.locator(byId('explore-viewer')).getAttribute('data-triangles');
    const firstId = await page.getAttribute(byId('explore-summary'), 'data-sample-id');
    await page.fill(byId('explore-seed'), '15');
    await page.press(byId('explore-seed'), 'Enter');
    await waitFor('the seed-15 sample', (id) => document.querySelector('[data-testid="explore-summary"]').dataset.sampleId !== id
      && document.querySelector('[data-testid="explore-viewer"]').dataset.state === 'loaded', firstId, 60_000);
    const triangles = Number(await page.locator(byId('explore-viewer')).getAttribute('data-triangles'));
    check(triangles > 0, `the 3D view holds ${triangles} triangles`);
    await page.waitForTimeout(300);
    const drawn = await drawnPixels('explore-viewer-canvas');
    check(drawn > 200, `the 3D canvas shows almost nothing (${drawn} of the probe's pixels differ from the background)`);
    log(`     spaceship seed 15: ${triangles} triangles (seed 0: ${first}), ${drawn} drawn probe pixels`);
    const formats = await page.locator(`${byId('explore-downloads')} a`).allTextContents();
    check(formats.includes('.glb') && formats.includes('.obj'), `the download list lacks .glb/.obj: ${formats.join(' ')}`);
    // Download the GLB the way a user does and validate it.
    const [download] = await Promise.all([page.waitForEvent('download'), page.click(byId('explore-download-glb'))]);
    const file = path.join(downloads, download.suggestedFilename() || 'sample.glb');
    await download.saveAs(file);
    await validateGlb(fs.readFileSync(file), `explore download ${download.suggestedFilename()}`);
  });

  await step('explore: edit a grammar — its error at its line, then the model once fixed', async () => {
    await page.selectOption(byId('explore-grammar'), GRAMMAR_3D);
    await page.click('.source-panel summary');
    await page.click(byId('editor-open'));
    editingDrafts = true;
    await page.fill(byId('editor-name'), 'cube.sg');
    await page.fill(byId('editor-text'), 'grammar "cube";\naxiom A;\nA { boxx; }\n');
    await waitFor('the error at line 3', () => [...document.querySelectorAll('[data-testid="editor-diagnostics"] li')]
      .some((li) => li.dataset.line === '3' && li.textContent.includes('boxx')), null, 30_000);
    // Shown once (under the editor; the side panel points there), the last good model marked stale.
    const summary = await page.textContent(byId('explore-summary'));
    check(/^1 error: see the list under the editor$/.test(summary), `the side panel repeats the error: ${summary}`);
    check(await page.getAttribute(byId('explore-viewer'), 'data-stale') !== null, 'the last good model is not marked stale');
    await page.locator(byId('editor-diagnostics')).scrollIntoViewIfNeeded();
    await screenshot('editor');
    editingDrafts = false;
    const previousId = await page.getAttribute(byId('explore-summary'), 'data-sample-id');
    await page.fill(byId('editor-text'), 'grammar "cube";\naxiom A;\nA { box; }\n');
    await waitFor('the fixed grammar\'s model', (id) => {
      const v = document.querySelector('[data-testid="explore-viewer"]');
      return document.querySelector('[data-testid="editor-diagnostics"]').children.length === 0
        && document.querySelector('[data-testid="explore-summary"]').dataset.sampleId !== id
        && v.dataset.state === 'loaded' && Number(v.dataset.triangles) === 12 && v.dataset.stale === undefined;
    }, previousId, 60_000);
    await page.click(byId('editor-save'));
    await waitFor('the saved grammar in the list', () => [...document.querySelectorAll('[data-testid="explore-grammar"] option')]
      .some((o) => o.value === 'runs/grammars/cube.sg'), null, 30_000);
    await page.click(byId('editor-close'));
  });

  await step('explore: formalism options (Genr8 steps and environment)', async () => {
    const previousId = await page.getAttribute(byId('explore-summary'), 'data-sample-id');
    await page.selectOption(byId('explore-grammar'), GRAMMAR_OPTIONS.path);
    await waitFor('the first sample of the Genr8 grammar', (id) => document.querySelector('[data-testid="explore-summary"]').dataset.sampleId !== id
      && document.querySelector('[data-testid="explore-viewer"]').dataset.state === 'loaded', previousId, 60_000);
    const before = Number(await page.getAttribute(byId('explore-viewer'), 'data-triangles'));
    for (const [name, value] of Object.entries(GRAMMAR_OPTIONS.options)) await page.fill(byId(`explore-option-${name}`), value);
    const firstId = await page.getAttribute(byId('explore-summary'), 'data-sample-id');
    await page.click(byId('explore-sample'));
    await waitFor('the sample with options', (id) => document.querySelector('[data-testid="explore-summary"]').dataset.sampleId !== id
      && document.querySelector('[data-testid="explore-viewer"]').dataset.state === 'loaded', firstId, 60_000);
    const after = Number(await page.getAttribute(byId('explore-viewer'), 'data-triangles'));
    const summary = await page.textContent(byId('explore-summary'));
    check(summary.includes(`${GRAMMAR_OPTIONS.options.steps} steps`), `the summary does not report ${GRAMMAR_OPTIONS.options.steps} steps: ${summary}`);
    check(after > before, `${GRAMMAR_OPTIONS.options.steps} growth steps gave ${after} triangles, not more than the default's ${before}`);
    // GLBs are +y up: the draped surface lies flat (lower than it is wide), it does not stand on edge.
    const [sx, sy, sz] = (await page.getAttribute(byId('explore-viewer'), 'data-size')).split(',').map(Number);
    check(sy < 0.75 * Math.max(sx, sz), `the Genr8 surface stands on edge in the view (size x ${sx}, y ${sy}, z ${sz}); GLBs should be +y up`);
    log(`     ${GRAMMAR_OPTIONS.path}: ${before} → ${after} triangles with ${JSON.stringify(GRAMMAR_OPTIONS.options)}`);
    await page.waitForTimeout(300);
    await screenshot('explore');
  });

  let runId;
  await step('run: start a Genr8 run and watch it live', async () => {
    await page.click(byId('tab-run'));
    await page.selectOption(byId('run-scene'), SCENE);
    await page.fill(byId('run-generations'), '100000'); // stopped by the test, not by the count
    await page.fill(byId('run-budget'), '10m');
    await page.click(byId('run-start'));
    await waitFor('the run to be running', () => document.querySelector('[data-testid="run-status"]').dataset.status === 'running', null, 60_000);
    runId = await page.getAttribute(byId('run-status'), 'data-run-id');
    await waitFor('3 generations in the fitness plot', () => {
      const path = document.querySelector('[data-testid="run-plot"] path.plot-line');
      return path && (path.getAttribute('d').match(/L/g) || []).length >= 2;
    }, null, 120_000);
    const snapshot = await getJson(`api/runs/${runId}`);
    check(snapshot.status === 'running', `snapshot status ${snapshot.status}`);
    check(snapshot.criteria_names.length > 1, `the canopy scene reports criteria ${JSON.stringify(snapshot.criteria_names)}; expected several`);
    const last = snapshot.stats[snapshot.stats.length - 1];
    const expected = Object.keys(last?.criteria || {});
    check(expected.length > 1, `the latest stats row has criteria ${JSON.stringify(last?.criteria)}; expected several`);
    const lines = await waitFor('one line per criterion', (n) => {
      const paths = [...document.querySelectorAll('[data-testid="run-criteria-plot"] path.plot-line')];
      return paths.length >= n && paths.map((p) => p.dataset.series);
    }, expected.length, 30_000);
    check(expected.every((name) => lines.includes(name)), `the criteria plot draws ${lines.join(', ')}; the run reports ${expected.join(', ')}`);
    log(`     run ${runId} at generation ${snapshot.generation}`);
  });

  const effective = []; // the generation each change in STEERED took effect at
  for (const change of STEERED) {
    await step(`steer: change the ${change.name} ${change.group === 'weights' ? 'weight' : 'target'} mid-run and see it in the log`, async () => {
      await page.click(byId('tab-steer'));
      const input = byId(`steer-${change.group === 'weights' ? 'weight' : 'target'}-${change.name}`);
      await page.waitForSelector(input);
      const before = Number(await page.inputValue(input));
      check(before !== change.value, `${change.name} is already ${before}`);
      const applied = await page.locator(`${byId('steer-log-entry')}[data-state="applied"]`).count();
      await page.fill(input, String(change.value));
      const generationNow = (await getJson(`api/runs/${runId}`)).generation;
      await page.click(byId('steer-apply'));
      const generation = Number(await waitFor('the change to take effect (a new steering log entry "took effect")', (n) => {
        const entries = document.querySelectorAll('[data-testid="steer-log-entry"][data-state="applied"]');
        return entries.length > n && entries[entries.length - 1].dataset.generation;
      }, applied, 120_000));
      const text = await page.locator(`${byId('steer-log-entry')}[data-state="applied"]`).last().textContent();
      check(text.includes(`${change.group} ${change.name} ${change.value}`), `the log entry says "${text}"`);
      check(generation > generationNow, `the change took effect at generation ${generation}, not after generation ${generationNow} when it was sent`);
      const snapshot = await getJson(`api/runs/${runId}`);
      const logged = (snapshot.steering || []).find((s) => s.generation === generation);
      check(logged && logged.set[change.group]?.[change.name] === change.value,
        `the run's snapshot does not log ${change.name} = ${change.value} at generation ${generation}: ${JSON.stringify(snapshot.steering)}`);
      check(snapshot.criteria[change.group][change.name] === change.value,
        `the snapshot's current ${change.name} is ${snapshot.criteria[change.group][change.name]}`);
      await waitFor('a generation after the change', (g) => Number(document.querySelector('[data-testid="steer-run"]').dataset.generation) > g, generation, 60_000);
      effective.push(generation);
      log(`     ${change.group} ${change.name} ${before} → ${change.value}, sent at generation ${generationNow}, took effect at ${generation}`);
    });
  }
  await screenshot('steer');

  await step('run: gallery, live best model, pause and resume', async () => {
    await page.click(byId('tab-run'));
    await waitFor('a gallery picture', () => {
      const img = document.querySelector('[data-testid="run-gallery-image"]');
      return img.getAttribute('src') && img.complete && img.naturalWidth > 0;
    }, null, 120_000);
    // The viewer showed the best so far before the run ended.
    const live = `api/runs/${runId}/best.glb?`;
    for (let i = 0; i < 100 && !liveModels.some((u) => u.includes(live)); i++) await page.waitForTimeout(100);
    check(liveModels.some((u) => u.includes(live)), `no live best model of run ${runId} was shown (fetched: ${liveModels.join(', ') || 'none'})`);
    await page.click(byId('run-pause'));
    await waitFor('the run to pause', () => document.querySelector('[data-testid="run-status"]').dataset.status === 'paused', null, 60_000);
    const g1 = (await getJson(`api/runs/${runId}`)).generation;
    await page.waitForTimeout(1500);
    const g2 = (await getJson(`api/runs/${runId}`)).generation;
    check(g2 <= g1 + 1, `a paused run went on from generation ${g1} to ${g2}`);
    await page.click(byId('run-resume'));
    await waitFor('the run to resume', () => document.querySelector('[data-testid="run-status"]').dataset.status === 'running', null, 30_000);
  });

  await step('run: a second tab follows the same run', async () => {
    const second = await context.newPage();
    second.on('pageerror', (err) => pageErrors.push(`page error (second tab): ${err.message}`));
    try {
      await second.goto(`${base}#run`);
      await second.waitForFunction(() => document.body.dataset.ready === 'true', null, { timeout: 30_000 });
      await second.waitForSelector(`${byId('run-previous')} option[value="${runId}"]`, { state: 'attached', timeout: 30_000 });
      await second.selectOption(byId('run-previous'), runId);
      const g0 = Number(await second.waitForFunction(() => {
        const text = document.querySelector('[data-testid="run-stat-generation"]')?.textContent;
        return text && Number(text) >= 0 && text;
      }, null, { timeout: 30_000 }).then((h) => h.jsonValue()));
      await second.waitForFunction((g) => Number(document.querySelector('[data-testid="run-stat-generation"]').textContent) > g, g0, { timeout: 60_000 });
      const history = await second.locator(`${byId('run-plot')} path.plot-line`).count();
      check(history > 0, 'the second tab shows no fitness history');
    } catch (err) {
      throw err instanceof TestFailure ? err : new TestFailure(`the second tab does not follow run ${runId}: ${err.message.split('\n')[0]}`);
    } finally {
      await second.close();
    }
  });

  await step('run: stop; the run folder has best.glb and run.json with the changes', async () => {
    await page.click(byId('run-stop'));
    await waitFor('the run to stop', () => document.querySelector('[data-testid="run-status"]').dataset.status === 'stopped', null, 120_000);
    await waitFor('best.glb in the run folder list', () => !!document.querySelector('[data-testid="run-file-best.glb"]'), null, 60_000);
    await waitFor('the runs list to say stopped', (id) => [...document.querySelectorAll('[data-testid="run-previous"] option')]
      .some((o) => o.value === id && o.textContent.includes(' · stopped · ')), runId, 30_000);
    const runJson = await getJson(`api/runs/${runId}/files/run.json`);
    STEERED.forEach((change, i) => {
      const logged = (runJson.steering || []).find((s) => s.generation === effective[i]);
      check(logged && logged.set[change.group]?.[change.name] === change.value,
        `run.json does not log ${change.name} = ${change.value} at generation ${effective[i]}: steering = ${JSON.stringify(runJson.steering)}`);
    });
    check(runJson.stopped_by === 'interrupted', `run.json says stopped_by ${JSON.stringify(runJson.stopped_by)}, expected "interrupted"`);
    const href = await page.getAttribute(byId('run-file-best.glb'), 'href');
    const bytes = await getBytes(href);
    fs.writeFileSync(path.join(downloads, 'best.glb'), bytes);
    const report = await validateGlb(bytes, 'best.glb');
    log(`     best.glb: ${bytes.length} bytes, ${report.info?.totalTriangleCount ?? '?'} triangles, 0 validator errors; run.json logs both changes`);
    await waitFor('the best model in the 3D view', () => document.querySelector('[data-testid="run-viewer"]').dataset.state === 'loaded', null, 60_000);
  });

  await step('run: a volume scene (GA) runs to its end', async () => {
    await page.selectOption(byId('run-scene'), VOLUME_SCENE.path);
    await page.selectOption(byId('run-algorithm'), 'ga');
    await page.fill(byId('run-generations'), String(VOLUME_SCENE.generations));
    await page.fill(byId('run-budget'), '');
    await page.click(byId('run-start'));
    await waitFor('a new run', (old) => document.querySelector('[data-testid="run-status"]').dataset.runId !== old, runId, 30_000);
    const id = await page.getAttribute(byId('run-status'), 'data-run-id');
    await waitFor(`${VOLUME_SCENE.generations} generations and the end of the run`,
      () => document.querySelector('[data-testid="run-status"]').dataset.status === 'finished', null, 240_000);
    const snapshot = await getJson(`api/runs/${id}`);
    check(snapshot.generation === VOLUME_SCENE.generations, `the run ended at generation ${snapshot.generation}, not ${VOLUME_SCENE.generations}`);
    const bests = snapshot.stats.map((r) => r.best_so_far);
    check(bests.every((b, i) => i === 0 || b >= bests[i - 1]), `best so far decreases: ${bests.join(' ')}`);
    for (const name of ['best.glb', 'best.png', 'gallery.png', 'run.json', 'stats.csv']) {
      await waitFor(`${name} in the run folder list`, (n) => !!document.querySelector(`[data-testid="run-file-${n}"]`), name, 30_000);
    }
    await waitFor('the best model inside its target volume, and best.png', () => document.querySelector('[data-testid="run-viewer"]').dataset.state === 'loaded'
      && document.querySelector('[data-testid="run-viewer"]').dataset.target === 'shown'
      && document.querySelector('[data-testid="run-target"]').naturalWidth > 0
      && document.querySelector('[data-testid="run-gallery-image"]').naturalWidth > 0, null, 60_000);
    const points = await page.locator(`${byId('run-plot')} path.plot-line[data-series="best so far"]`).getAttribute('d');
    check((points.match(/L/g) || []).length >= VOLUME_SCENE.generations - 1, `the fitness plot has ${(points.match(/L/g) || []).length + 1} points`);
    log(`     run ${id}: best ${bests[bests.length - 1]} after ${snapshot.generation} generations`);
    await page.waitForTimeout(300);
    await screenshot('run');
  });

  await step('run: the memory the server\'s runs hold is shown', async () => {
    await waitFor('the memory line', () => /^Memory: .+ of .+ held/.test(document.querySelector('[data-testid="run-memory"]').textContent), null, 30_000);
  });

  await step('run: a reload follows the last run, with its final gallery', async () => {
    const id = await page.getAttribute(byId('run-status'), 'data-run-id');
    await page.reload();
    await waitFor('the page after a reload', () => document.body.dataset.ready === 'true');
    await waitFor(`run ${id} followed again`, (want) => document.querySelector('[data-testid="run-status"]').dataset.runId === want
      && document.querySelector('[data-testid="run-status"]').dataset.status === 'finished'
      && document.querySelector('[data-testid="run-gallery-image"]').naturalWidth > 0, id, 30_000);
  });

  await step('run: a run over in a moment shows its final gallery', async () => {
    const old = await page.getAttribute(byId('run-status'), 'data-run-id');
    await page.selectOption(byId('run-scene'), VOLUME_SCENE.path);
    await page.selectOption(byId('run-algorithm'), 'ga');
    await page.fill(byId('run-generations'), '1');
    await page.click(byId('run-start'));
    await waitFor('the short run to end with a gallery', (o) => {
      const s = document.querySelector('[data-testid="run-status"]');
      const img = document.querySelector('[data-testid="run-gallery-image"]');
      return s.dataset.runId !== o && s.dataset.status === 'finished' && !img.hidden && img.naturalWidth > 0
        && !document.querySelector('[data-testid="run-gallery-caption"]').textContent.includes('Waiting');
    }, old, 60_000);
  });

  await step('breed: pick favourites for two generations', async () => {
    await page.click(byId('tab-breed'));
    await page.selectOption(byId('breed-source'), BREED_GRAMMAR);
    await page.fill(byId('breed-size'), '9');
    await page.click(byId('breed-start'));
    // Duplicates are shown once, so a generation may hold fewer than 9.
    const cardsLoaded = (generation) => waitFor(`the individuals of generation ${generation} with their pictures`, (g) => {
      const grid = document.querySelector('[data-testid="breed-grid"]');
      const imgs = [...grid.querySelectorAll('.breed-card img')];
      return grid.dataset.generation === String(g) && imgs.length >= 4 && imgs.length <= 9 && imgs.every((i) => i.complete && i.naturalWidth > 0)
        && [...grid.querySelectorAll('.breed-card')].map((c) => c.dataset.testid.replace('breed-card-', ''));
    }, generation, 120_000);
    const firstCards = await cardsLoaded(0);
    const firstPictures = await page.locator(`${byId('breed-grid')} img`).evaluateAll((imgs) => imgs.map((i) => i.src));
    let cards = firstCards;
    for (const [generation, positions] of [[0, [1, 3]], [1, [0, 2, 3]]]) {
      const picks = positions.map((p) => cards[p]);
      for (const i of picks) await page.click(byId(`breed-card-${i}`));
      const count = await page.getAttribute(byId('breed-count'), 'data-count');
      check(Number(count) === picks.length, `${count} favourites marked after clicking ${picks.length}`);
      const pressed = await page.locator(`${byId('breed-grid')} [aria-pressed="true"]`).count();
      check(pressed === picks.length, `${pressed} cards show as picked`);
      if (generation === 1) {
        // Inspect a favourite in 3D (its GLB), then take the view's picture.
        await page.click(byId(`breed-inspect-${picks[0]}`));
        await waitFor('the inspected individual in the 3D view', () => {
          const v = document.querySelector('[data-testid="breed-viewer"]');
          return v.dataset.state === 'loaded' && Number(v.dataset.triangles) > 0;
        }, null, 60_000);
        await page.waitForTimeout(300);
        await screenshot('breed');
        // At 1024 px the 3D view goes under the grid: nothing is cut off.
        await page.setViewportSize({ width: 1024, height: 768 });
        const cut = await page.evaluate(() => {
          const main = document.querySelector('[data-testid="breed-viewer"]').closest('.main');
          const view = document.querySelector('[data-testid="breed-viewer"]').getBoundingClientRect();
          return { overflow: main.scrollWidth - main.clientWidth, right: view.right, width: window.innerWidth };
        });
        check(cut.overflow <= 0 && cut.right <= cut.width, `at 1024 px the breed view is cut: ${JSON.stringify(cut)}`);
        await screenshot('breed-1024');
        await page.setViewportSize({ width: 1400, height: 860 });
      }
      await page.click(byId('breed-next'));
      cards = await cardsLoaded(generation + 1);
    }
    const lastPictures = await page.locator(`${byId('breed-grid')} img`).evaluateAll((imgs) => imgs.map((i) => i.src));
    check(lastPictures.every((src) => !firstPictures.includes(src)), 'generation 2 shows the same pictures as generation 0');
    const history = await page.locator(`${byId('breed-history')} li`).count();
    check(history === 2, `the history lists ${history} generations, expected 2`);
  });

  await step('a studio started where there are no grammars says where they come from', async () => {
    await stopServer();
    const empty = path.join(tmp, 'empty');
    fs.mkdirSync(empty, { recursive: true });
    serverLog = '';
    const url = await startServer(empty, path.join(empty, 'out'));
    for (let i = 0; i < 30 && !/no grammars/.test(serverLog); i++) await new Promise((r) => setTimeout(r, 100));
    serving = url;
    check(/no grammars or scenes found.*--examples/.test(serverLog), `no warning at start: ${serverLog}`);
    await page.goto(url);
    await waitFor('the page to load', () => document.body.dataset.ready === 'true');
    check(await page.locator(byId('explore-empty')).isVisible(), 'the page does not say that no grammars were found');
    check((await page.textContent(byId('explore-empty'))).includes('--examples'), 'the note does not name --examples');
    // Edit starts from a new grammar, and its model appears.
    editingDrafts = true;
    await page.click(byId('editor-open'));
    await waitFor('the new grammar\'s model', () => {
      const v = document.querySelector('[data-testid="explore-viewer"]');
      return v.dataset.state === 'loaded' && Number(v.dataset.triangles) === 12;
    }, null, 60_000);
    editingDrafts = false;
  });

  await step('no page errors', async () => {
    check(pageErrors.length === 0, `the page logged errors:\n  ${pageErrors.join('\n  ')}`);
  });
}

// Interrupted (Ctrl-C, a timeout's SIGTERM): never leave the server or the browser behind.
for (const signal of ['SIGINT', 'SIGTERM']) {
  process.on(signal, async () => {
    console.error(`\nstudio e2e: ${signal} in step "${currentStep}"; stopping the server and the browser`);
    await context?.close().catch(() => {});
    await stopServer().catch(() => {});
    process.exit(130);
  });
}
process.on('exit', () => {
  if (server && server.exitCode === null && server.signalCode === null) server.kill('SIGKILL');
});

let failed = false;
try {
  await main();
} catch (err) {
  failed = true;
  const message = err instanceof TestFailure ? err.message : err.stack || String(err);
  console.error(`\nFAILED in step "${currentStep}": ${message}`);
  if (pageErrors.length) console.error(`page errors:\n  ${pageErrors.join('\n  ')}`);
  if (page) {
    const shot = path.join(tmp, 'failure.png');
    await page.screenshot({ path: shot }).then(() => console.error(`screenshot of the failure: ${shot}`), () => {});
  }
  if (serverLog.trim()) console.error(`genform serve stderr (last 40 lines):\n${serverLog.trim().split('\n').slice(-40).join('\n')}`);
} finally {
  await context?.close().catch(() => {});
  await stopServer().catch(() => {});
  if (!KEEP && !failed) fs.rmSync(tmp, { recursive: true, force: true });
  else console.error(`temporary files kept in ${tmp}`);
}
log(failed ? 'studio e2e: FAILED' : 'studio e2e: all steps passed');
process.exit(failed ? 1 : 0);
