// Run: start `evolve` on a scene with any algorithm and watch it live — fitness plot (one line
// per criterion where the scene has several), the gallery of the population's distinct best,
// the best model with the target, pause/resume/stop and the run folder's files.

import * as api from './api.js';
import { describeChange, entryOption, h, field, fmt, setChildren } from './dom.js';
import { LinePlot } from './plot.js';
import { emit, on, sceneEntries, store, toast } from './store.js';
import { Gallery } from './gallery.js';
import { Viewer } from './viewer.js';

const ACTIVE = new Set(['running', 'paused']);
let els;
let viewer;
let fitnessPlot;
let gallery;
let criteriaPlot;
let events = null;
let watching = null; // run id
let shownModel = null; // URL of the model in the viewer
let shownTarget = null;
let sceneTargetPicture = false; // the scene has a target picture (shown instead of best.png)

export function mount(section) {
  const scene = h('select', { testid: 'run-scene', onchange: () => fillAlgorithms() });
  const algorithm = h('select', { testid: 'run-algorithm' });
  const seed = h('input', { type: 'number', min: 0, step: 1, value: 0, testid: 'run-seed' });
  const generations = h('input', { type: 'number', min: 1, step: 1, placeholder: "scene's", testid: 'run-generations' });
  const budget = h('input', { type: 'text', placeholder: 'e.g. 30s', testid: 'run-budget' });
  const start = h('button', { class: 'primary', testid: 'run-start', text: 'Start run', onclick: startRun });
  const pause = h('button', { testid: 'run-pause', text: 'Pause', onclick: () => control('pause') });
  const resume = h('button', { testid: 'run-resume', text: 'Resume', onclick: () => control('resume') });
  const stop = h('button', { class: 'danger', testid: 'run-stop', text: 'Stop', onclick: () => control('stop') });
  const steerLink = h('a', { class: 'button ghost', href: '#steer', testid: 'run-steer-link', text: 'Steer…' });
  const previous = h('select', { testid: 'run-previous', onchange: () => previous.value && watch(previous.value) });
  const status = h('span', { class: 'status-pill', testid: 'run-status', dataset: { status: 'idle' }, text: 'idle' });
  const stats = h('dl', { class: 'stats', testid: 'run-stats' });
  const files = h('ul', { class: 'files', testid: 'run-files' });
  const folder = h('p', { class: 'muted', testid: 'run-folder' });
  const error = h('p', { class: 'error', testid: 'run-error', hidden: true });
  const memory = h('p', { class: 'muted', testid: 'run-memory', title: 'the memory budget every run and breeding session on this server shares (--max-memory)' });

  const side = h('aside', { class: 'side' },
    h('h2', { text: 'New run' }),
    field('Scene', scene),
    field('Algorithm', algorithm),
    h('div', { class: 'grid2' }, field('Seed', seed), field('Generations', generations)),
    field('Budget', budget, 'stops at whichever comes first'),
    h('div', { class: 'actions' }, start),
    memory,
    h('h2', { text: 'Watched run' }),
    field('Runs on this server', previous),
    h('div', { class: 'row' }, status),
    h('div', { class: 'actions' }, pause, resume, stop, steerLink),
    error,
    stats,
    h('h3', { text: 'Run folder' }),
    folder,
    files);

  const viewHost = h('div', { class: 'panel run-model' }, h('div', { class: 'panel-title', text: 'Best model' }));
  const targetImg = h('img', { class: 'target-picture', testid: 'run-target', alt: 'target', hidden: true });
  const targetTitle = h('div', { class: 'panel-title', text: 'Target' });
  const targetPanel = h('div', { class: 'panel run-target', testid: 'run-target-panel', hidden: true }, targetTitle, targetImg);
  const plotHost = h('div', { class: 'panel run-plot' }, h('div', { class: 'panel-title', text: 'Fitness' }));
  const criteriaTitle = h('div', { class: 'panel-title', text: 'Criteria (best individual, w/(1+e))' });
  const criteriaHost = h('div', { class: 'panel run-criteria', testid: 'run-criteria-panel', hidden: true }, criteriaTitle);
  const bottom = h('div', { class: 'run-bottom' });
  const mainArea = h('div', { class: 'main run-main' },
    h('div', { class: 'run-top' }, viewHost, h('div', { class: 'run-charts' }, plotHost, criteriaHost)),
    bottom);
  section.append(h('div', { class: 'layout' }, side, mainArea));
  viewer = new Viewer(viewHost, { testid: 'run-viewer' });
  viewer.clear('The best model appears here when the run has one.');
  fitnessPlot = new LinePlot(plotHost, { testid: 'run-plot', yLabel: 'fitness' });
  criteriaPlot = new LinePlot(criteriaHost, { testid: 'run-criteria-plot', yLabel: 'contribution', height: 200 });
  gallery = new Gallery(bottom);
  bottom.append(targetPanel);
  els = { scene, algorithm, seed, generations, budget, start, pause, resume, stop, previous, status, stats, files, folder,
    error, targetImg, targetTitle, targetPanel, criteriaHost, criteriaTitle, memory };

  on('entries', fillScenes);
  if (store.entries.length) fillScenes();
  refreshRunList().then(followLatest);
  updateControls();
}

/** After a reload: follows the run this page followed last (kept in the session's storage),
 * else the newest run on the server, so the panels are not blank. */
async function followLatest(list) {
  if (watching || !list?.length) return;
  let last = null;
  try {
    last = sessionStorage.getItem('genform-run');
  } catch {
    /* storage may be off; the newest run will do */
  }
  const id = list.some((r) => r.id === last) ? last : list[list.length - 1].id;
  await watch(id);
}

export function shown() {
  viewer?.resize();
  fitnessPlot?.render();
  criteriaPlot?.render();
  refreshRunList();
}

function fillScenes() {
  const scenes = sceneEntries();
  setChildren(els.scene, scenes.map(entryOption));
  const preferred = scenes.find((s) => s.default) || scenes[0];
  if (preferred) els.scene.value = preferred.path;
  fillAlgorithms();
}

function fillAlgorithms() {
  const scene = store.entries.find((e) => e.path === els.scene.value);
  const algorithms = scene?.algorithms?.length ? scene.algorithms : ['ga'];
  setChildren(els.algorithm, algorithms.map((a) => h('option', { value: a, text: a })));
}

/** Bytes as people read them (powers of 1024, as the server's messages). */
function bytes(n) {
  const units = ['B', 'KiB', 'MiB', 'GiB', 'TiB'];
  let v = n;
  let u = 0;
  while (v >= 1024 && u < units.length - 1) {
    v /= 1024;
    u++;
  }
  return u ? `${v.toFixed(1)} ${units[u]}` : `${v} B`;
}

/** Shows the server's memory budget and what is held of it. */
async function refreshMemory() {
  try {
    const { memory } = await api.status();
    const held = memory.holders ? ` by ${memory.holders} run${memory.holders === 1 ? '' : 's'} or session${memory.holders === 1 ? '' : 's'}` : '';
    els.memory.textContent = `Memory: ${bytes(memory.in_use)} of ${bytes(memory.budget)} held${held}`;
    els.memory.dataset.inUse = String(memory.in_use);
  } catch {
    /* a convenience, like the run list */
  }
}

async function refreshRunList() {
  if (!els) return null;
  refreshMemory();
  try {
    const list = await api.runs();
    const keep = watching || '';
    setChildren(els.previous, h('option', { value: '', text: list.length ? 'choose a run…' : 'none yet' }),
      list.slice().reverse().map((r) => h('option', { value: r.id, text: `${r.id} · ${r.scene} · ${r.status} · gen ${r.generation}` })));
    els.previous.value = keep;
    return list;
  } catch {
    /* the list is a convenience; errors show elsewhere */
    return null;
  }
}

async function startRun() {
  const body = { scene: els.scene.value, algorithm: els.algorithm.value, seed: Math.max(0, Math.floor(Number(els.seed.value) || 0)) };
  if (els.generations.value) body.generations = Math.floor(Number(els.generations.value));
  if (els.budget.value.trim()) body.budget = els.budget.value.trim();
  els.start.disabled = true;
  try {
    const { id } = await api.startRun(body);
    toast(`Run ${id} started`);
    await watch(id);
  } catch (err) {
    toast(err.message, { error: true });
  } finally {
    els.start.disabled = false;
  }
}

async function control(action) {
  if (!watching) return;
  try {
    const answer = await api.control(watching, action);
    if (answer?.status) setStatus(answer.status);
    if (action === 'stop') await refreshSnapshot();
  } catch (err) {
    toast(err.message, { error: true });
  }
}

/** Follows run `id`: loads its snapshot (history) and subscribes to its events. */
export async function watch(id) {
  if (events) events.close();
  events = null;
  watching = id;
  try {
    sessionStorage.setItem('genform-run', id);
  } catch {
    /* storage may be off */
  }
  shownModel = shownTarget = null;
  fitnessPlot.clear();
  criteriaPlot.clear();
  viewer.clear('The best model appears here when the run has one.');
  els.criteriaHost.hidden = true;
  els.targetPanel.hidden = true;
  gallery.clear();
  const snapshot = await api.run(id);
  store.run = snapshot;
  for (const row of snapshot.stats || []) plotRow(row);
  for (const s of snapshot.steering || []) markSteering(s);
  if (snapshot.gallery) gallery.show({ url: snapshot.gallery, generation: snapshot.generation });
  showSceneTargets(snapshot);
  emit('run', snapshot);
  renderSnapshot();
  refreshRunList();
  if (ACTIVE.has(snapshot.status)) subscribe(id);
}

function subscribe(id) {
  events = api.runEvents(id, {
    generation: (row) => {
      if (watching !== id) return;
      const run = store.run;
      run.stats = run.stats || [];
      run.stats.push(row);
      run.generation = row.generation;
      run.evaluations = row.total_evaluations ?? run.evaluations;
      run.best = row.best_so_far ?? run.best;
      plotRow(row);
      renderStats();
      emit('generation', row);
    },
    gallery: (g) => {
      if (watching !== id) return;
      gallery.show(g);
      refreshSnapshot();
      refreshRunList(); // and its generation, every gallery picture or so
      emit('gallery', g);
    },
    steering: (s) => {
      if (watching !== id) return;
      const run = store.run;
      run.steering = run.steering || [];
      if (!run.steering.some((x) => x.generation === s.generation && JSON.stringify(x.set) === JSON.stringify(s.set))) run.steering.push(s);
      if (s.max_reachable !== undefined) run.max_reachable = s.max_reachable; // the weights changed what is reachable
      markSteering(s);
      emit('steering', s);
    },
    status: (s) => {
      if (watching !== id) return;
      setStatus(s.status, s.error);
      refreshRunList(); // the list shows each run's status
      if (!ACTIVE.has(s.status)) {
        events?.close();
        events = null;
        refreshSnapshot();
      }
    },
    // On (re)connecting, catch up with what happened since the snapshot.
    open: () => refreshSnapshot(),
    error: () => {
      // EventSource reconnects by itself while the run is active; a finished run closes.
      if (events && events.readyState === EventSource.CLOSED) events = null;
    },
  });
}

async function refreshSnapshot() {
  if (!watching) return;
  const id = watching;
  try {
    const snapshot = await api.run(id);
    if (watching !== id) return;
    // Merge the history: events may be ahead of the snapshot, and the snapshot holds rows
    // the events missed (between the first snapshot and the subscription, or a reconnect).
    const byGeneration = new Map((store.run?.stats || []).map((row) => [row.generation, row]));
    for (const row of snapshot.stats || []) {
      if (!byGeneration.has(row.generation)) {
        byGeneration.set(row.generation, row);
        plotRow(row);
      }
    }
    snapshot.stats = [...byGeneration.values()].sort((a, b) => a.generation - b.generation);
    // A run that ended before its first live picture answers its folder's final gallery.
    if (snapshot.gallery) gallery.show({ url: snapshot.gallery, generation: snapshot.generation });
    store.run = snapshot;
    emit('snapshot', snapshot);
    renderSnapshot();
  } catch (err) {
    toast(err.message, { error: true });
  }
}

function setStatus(status, error) {
  if (store.run) {
    store.run.status = status;
    if (error !== undefined) store.run.error = error;
  }
  emit('status', { status, error });
  renderStatus();
}

function plotRow(row) {
  const g = row.generation;
  if (row.best_so_far !== undefined) fitnessPlot.push('best so far', g, row.best_so_far);
  if (row.best !== undefined) fitnessPlot.push('generation best', g, row.best);
  if (row.mean !== undefined) fitnessPlot.push('mean', g, row.mean, { dashed: true });
  const criteria = row.criteria || {};
  const names = Object.keys(criteria);
  if (names.length > 1) {
    els.criteriaHost.hidden = false;
    // The scene's form: w/(1+e) (bounded, the default) or −w·e (paper).
    els.criteriaTitle.textContent = `Criteria (best individual, ${store.run?.criteria_formula || 'w/(1+e)'})`;
    for (const name of names) criteriaPlot.push(name, g, criteria[name]);
  }
}

function markSteering(s) {
  const label = `generation ${s.generation}: ${describeChange(s.set)}`;
  fitnessPlot.mark(s.generation, label);
  criteriaPlot.mark(s.generation, label);
}

function renderSnapshot() {
  renderStatus();
  renderStats();
  const run = store.run;
  if (!run) return;
  const files = run.files || [];
  els.folder.textContent = `${run.folder || `runs/${run.id}`} — ${run.scene}, ${run.algorithm}, seed ${run.seed}`;
  setChildren(els.files, files.map((name) => h('li', {}, h('a', { href: api.runFileUrl(run.id, name), target: '_blank',
    testid: `run-file-${name}`, text: name }))));
  // The best model: a live best-so-far if the server offers one, else the folder's best.glb.
  const modelUrl = run.best_model || (files.includes('best.glb') ? api.runFileUrl(run.id, 'best.glb') : null);
  // Reload when the best changed (or the run ended and wrote its final best.glb).
  const modelKey = `${modelUrl}|${run.best}|${ACTIVE.has(run.status)}`;
  if (modelUrl && modelKey !== shownModel) {
    const bust = `${modelUrl}${modelUrl.includes('?') ? '&' : '?'}g=${run.generation}`;
    shownModel = modelKey;
    viewer.showGlb(bust, { frame: !viewer.framed, info: `best so far: ${fmt(run.best)}` }).catch(() => {});
  }
  // The picture beside the model: the scene's target picture (image scenes), else the run's
  // best.png (the best model with its target behind it), refreshed when the best changes.
  if (!sceneTargetPicture && files.includes('best.png')) {
    const key = `best.png|${run.best}|${ACTIVE.has(run.status)}`;
    if (key !== shownTarget) {
      shownTarget = key;
      showTargetPicture(`${api.runFileUrl(run.id, 'best.png')}?g=${run.generation}`, 'Best with its target (best.png)', 'best.png');
    }
  }
}

/** Shows the scene's targets (from the scene list): a target mesh as glass around the model,
 * a target picture beside it. Genr8 surface scenes have none. */
function showSceneTargets(run) {
  const targets = run.targets || store.entries.find((e) => e.path === run.scene)?.targets;
  if (targets?.glb) viewer.showTarget(targets.glb).catch((err) => toast(`target: ${err.message}`, { error: true }));
  const picture = targets?.images?.[0];
  sceneTargetPicture = Boolean(picture);
  if (picture) showTargetPicture(picture, targets.images.length > 1 ? `Target picture (1 of ${targets.images.length})` : 'Target picture', 'target');
}

function showTargetPicture(url, title, kind) {
  els.targetImg.src = url;
  els.targetImg.dataset.file = kind;
  els.targetTitle.textContent = title;
  els.targetImg.hidden = false;
  els.targetPanel.hidden = false;
}

function renderStatus() {
  const run = store.run;
  const status = run?.status || 'idle';
  els.status.textContent = status;
  els.status.dataset.status = status;
  els.status.dataset.runId = run?.id || '';
  els.error.hidden = !run?.error;
  els.error.textContent = run?.error || '';
  updateControls();
}

function renderStats() {
  const run = store.run;
  if (!run) return;
  const last = (run.stats || [])[run.stats.length - 1] || {};
  const rows = [
    ['generation', run.generation],
    ['evaluations', run.evaluations],
    ['best so far', fmt(run.best)],
    ['generation best', fmt(last.best)],
    ['mean', fmt(last.mean)],
    ['invalid', last.invalid],
    ['seconds', fmt(last.seconds, 3)],
  ];
  if (run.max_reachable !== undefined && run.max_reachable !== null) rows.push(['reachable max', fmt(run.max_reachable)]);
  setChildren(els.stats, rows.flatMap(([k, v]) => [h('dt', { text: k }), h('dd', { text: v ?? '–', testid: `run-stat-${k.replaceAll(' ', '-')}` })]));
}

function updateControls() {
  const status = store.run?.status;
  els.pause.disabled = status !== 'running';
  els.resume.disabled = status !== 'paused';
  els.stop.disabled = !ACTIVE.has(status);
}
