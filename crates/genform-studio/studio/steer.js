// Steer: change the watched run's criteria weights and targets (Genr8 surface scenes) or
// fitness weights (volume/image scenes) while it runs. Each change is posted to the server,
// which applies it between generations; the log shows the generation it took effect at.

import * as api from './api.js';
import { describeChange, h, setChildren } from './dom.js';
import { LinePlot } from './plot.js';
import { on, store, toast } from './store.js';

const ACTIVE = new Set(['running', 'paused']);
let els;
let plot;
let criteriaPlot;
let baseline = { weights: {}, targets: {} }; // the values the form was built from / last applied
let formFor = null; // run id the form was built for
const pending = []; // {generation, set} queued but not yet seen as applied

export function mount(section) {
  const runLine = h('p', { class: 'muted', testid: 'steer-run', text: 'No run is being watched. Start one in the Run tab.' });
  const form = h('div', { class: 'steer-form', testid: 'steer-form' });
  const apply = h('button', { class: 'primary', testid: 'steer-apply', text: 'Apply changes', onclick: applyChanges });
  const reset = h('button', { class: 'ghost', testid: 'steer-reset', text: 'Reset form', onclick: () => buildForm(true) });
  const note = h('p', { class: 'muted small', text: 'Changes take effect between generations: at the generation after the one running. They are logged in run.json, so the run can be replayed with genform evolve --steering run.json.' });
  const log = h('ol', { class: 'steer-log', testid: 'steer-log' });
  const side = h('aside', { class: 'side' },
    h('h2', { text: 'Steer the run' }), runLine, form, h('div', { class: 'actions' }, apply, reset), note);
  const plotHost = h('div', { class: 'panel' }, h('div', { class: 'panel-title', text: 'Best so far, with the changes marked' }));
  const criteriaTitle = h('div', { class: 'panel-title', text: 'Criteria of the best individual, w/(1+e)' });
  const criteriaHost = h('div', { class: 'panel', hidden: true }, criteriaTitle);
  const logPanel = h('div', { class: 'panel steer-log-panel' }, h('div', { class: 'panel-title', text: 'Steering log' }), log);
  section.append(h('div', { class: 'layout' }, side, h('div', { class: 'main steer-main' }, logPanel, plotHost, criteriaHost)));
  plot = new LinePlot(plotHost, { testid: 'steer-plot', yLabel: 'fitness', height: 220 });
  criteriaPlot = new LinePlot(criteriaHost, { testid: 'steer-criteria-plot', yLabel: 'contribution', height: 220 });
  criteriaPlot.host = criteriaHost;
  criteriaPlot.title = criteriaTitle;
  els = { runLine, form, apply, reset, log };

  on('run', () => {
    pending.length = 0;
    plot.clear();
    criteriaPlot.clear();
    criteriaPlot.host.hidden = true;
    for (const row of store.run.stats || []) plotRow(row);
    for (const s of store.run.steering || []) markOnPlot(s);
    buildForm(true);
    renderLog();
  });
  on('snapshot', () => {
    // A change queued by another tab (or before a reload) shows as queued too.
    const queued = store.run.pending;
    if (!queued) pending.length = 0;
    else if (!pending.some((p) => JSON.stringify(p.set) === JSON.stringify(queued))) {
      pending.length = 0;
      pending.push({ generation: (store.run.generation ?? -1) + 1, set: queued, approximate: true });
    }
    buildForm(false);
    renderLog();
  });
  on('generation', (row) => {
    plotRow(row);
    renderRunLine();
  });
  on('status', () => {
    renderRunLine();
    updateButtons();
  });
  on('steering', (s) => {
    // Changes queued for this generation or earlier have taken effect (the server merges
    // several changes sent within one generation into one entry).
    for (let i = pending.length - 1; i >= 0; i--) if (pending[i].generation <= s.generation) pending.splice(i, 1);
    if (s.criteria && !els.form.querySelector('.changed')) {
      store.run.criteria = s.criteria;
      buildForm(true);
    }
    markOnPlot(s);
    renderLog();
  });
  updateButtons();
}

export function shown() {
  plot?.render();
  criteriaPlot?.render();
}

function plotRow(row) {
  if (row.best_so_far !== undefined) plot.push('best so far', row.generation, row.best_so_far);
  if (row.best !== undefined) plot.push('generation best', row.generation, row.best);
  const criteria = Object.entries(row.criteria || {});
  if (criteria.length > 1) {
    criteriaPlot.host.hidden = false;
    // The scene's form: w/(1+e) (bounded, the default) or −w·e (paper).
    criteriaPlot.title.textContent = `Criteria of the best individual, ${store.run?.criteria_formula || 'w/(1+e)'}`;
    for (const [name, value] of criteria) criteriaPlot.push(name, row.generation, value);
  }
}

function markOnPlot(s) {
  const label = `generation ${s.generation}: ${describeChange(s.set)}`;
  plot.mark(s.generation, label);
  criteriaPlot.mark(s.generation, label);
}

function renderRunLine() {
  const run = store.run;
  if (!run) return;
  els.runLine.textContent = `${run.id} · ${run.scene} · ${run.algorithm} · ${run.status} · generation ${run.generation ?? 0}`;
  els.runLine.dataset.status = run.status;
  els.runLine.dataset.generation = String(run.generation ?? 0);
}

/** Whether the run's scene is a Genr8 surface scene (criteria with targets; weights ≥ 0). */
const isSurface = () => Object.keys(baseline.targets).length > 0;

/** Slider range for a value: generous around the current value; below 0 only for the
 * fitness weights of volume/image scenes, which may be negative. */
function rangeFor(group, name, value) {
  if (group === 'targets' && ['smoothness', 'subdivisions', 'symmetry', 'soft_boundary'].includes(name)) return [0, Math.max(1, value * 2)];
  const top = Math.max(group === 'weights' ? 5 : 1, Math.ceil(Math.abs(value) * 2));
  return [isSurface() ? 0 : Math.min(0, -top), top];
}

/** Rebuilds the inputs from the run's current values (`force`, or when the run changed). */
function buildForm(force) {
  const run = store.run;
  renderRunLine();
  if (!run) return;
  if (!force && formFor === run.id) return; // keep the user's unsent edits
  formFor = run.id;
  const criteria = run.criteria || store.entries.find((e) => e.path === run.scene)?.criteria || {};
  baseline = { weights: { ...(criteria.weights || {}) }, targets: { ...(criteria.targets || {}) } };
  const groups = [];
  for (const group of ['weights', 'targets']) {
    const values = baseline[group];
    const names = Object.keys(values);
    if (!names.length) continue;
    groups.push(h('h3', { text: group === 'weights' ? 'Weights' : 'Targets' }));
    for (const name of names) groups.push(inputRow(group, name, values[name]));
  }
  if (!groups.length) groups.push(h('p', { class: 'muted', text: 'This scene has nothing to steer.' }));
  setChildren(els.form, groups);
  updateButtons();
}

function inputRow(group, name, value) {
  const [lo, hi] = rangeFor(group, name, value);
  const testid = `steer-${group === 'weights' ? 'weight' : 'target'}-${name}`;
  const number = h('input', { type: 'number', step: 'any', min: lo, value, testid, dataset: { group, name } });
  const range = h('input', { type: 'range', min: lo, max: hi, step: (hi - lo) / 200, value, testid: `${testid}-range` });
  const row = h('div', { class: 'steer-row' }, h('span', { class: 'steer-name', text: name }), range, number);
  const mark = () => row.classList.toggle('changed', Number(number.value) !== baseline[group][name]);
  range.addEventListener('input', () => {
    number.value = range.value;
    mark();
  });
  number.addEventListener('input', () => {
    range.value = number.value;
    mark();
  });
  return row;
}

async function applyChanges() {
  const run = store.run;
  if (!run) return;
  const body = {};
  for (const input of els.form.querySelectorAll('input[type="number"]')) {
    const { group, name } = input.dataset;
    const value = Number(input.value);
    if (input.value.trim() === '' || !Number.isFinite(value) || (isSurface() && value < 0)) {
      toast(`${name}: "${input.value}" is not a number${isSurface() ? ' ≥ 0' : ''}`, { error: true });
      return;
    }
    if (value !== baseline[group][name]) (body[group] ||= {})[name] = value;
  }
  if (!Object.keys(body).length) {
    toast('Nothing changed.');
    return;
  }
  els.apply.disabled = true;
  try {
    const answer = await api.steer(run.id, body);
    const entry = { generation: answer.generation, set: answer.queued || body };
    if (!(run.steering || []).some((s) => s.generation === entry.generation && JSON.stringify(s.set) === JSON.stringify(entry.set))) pending.push(entry);
    for (const [group, values] of Object.entries(body)) Object.assign(baseline[group], values);
    for (const row of els.form.querySelectorAll('.changed')) row.classList.remove('changed');
    toast(`Queued for generation ${answer.generation}`);
    renderLog();
  } catch (err) {
    toast(err.message, { error: true });
  } finally {
    updateButtons();
  }
}

function renderLog() {
  const applied = (store.run?.steering || []).map((s) => ({ ...s, state: 'applied' }));
  const queued = pending.map((s) => ({ ...s, state: 'queued' }));
  const entries = [...applied, ...queued].sort((a, b) => a.generation - b.generation);
  if (!entries.length) {
    setChildren(els.log, h('li', { class: 'muted', text: 'No changes yet.' }));
    return;
  }
  setChildren(els.log, entries.map((s) => h('li', { class: `steer-entry ${s.state}`, testid: 'steer-log-entry',
    dataset: { generation: String(s.generation), state: s.state } },
    h('span', { class: 'steer-gen', text: `gen ${s.approximate ? '≥ ' : ''}${s.generation}` }),
    h('span', { class: 'steer-change', text: describeChange(s.set) }),
    h('span', { class: 'steer-state', text: s.state === 'applied' ? 'took effect' : 'queued' }))));
}

function updateButtons() {
  const active = ACTIVE.has(store.run?.status);
  els.apply.disabled = !active || !els.form.querySelector('input');
}

/** The steering entries shown (for debugging in the console). */
export const log = () => [...(store.run?.steering || []), ...pending];
