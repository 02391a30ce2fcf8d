// Explore: pick a grammar, change the seed and the formalism's options, sample, look at the
// model (3D, or the SVG drawing for 2D formalisms) and download it in any format.

import * as api from './api.js';
import { h, field, fmt } from './dom.js';
import { grammarEntries, on, store } from './store.js';
import { Viewer } from './viewer.js';

// How each sample option is edited; options not named here get a text field.
const OPTION_INPUTS = {
  steps: { type: 'number', min: 0, step: 1, hint: 'derivation / growth steps' },
  'max-modules': { type: 'number', min: 1, step: 1 },
  box: { type: 'text', placeholder: 'x0,y0,z0,x1,y1,z1', hint: 'block box (inclusive)' },
  env: { type: 'text', placeholder: 'examples/hemls/repellers.toml', hint: 'environment file (root path)', list: 'env-files' },
  smooth: { type: 'number', min: 0, step: 1, hint: 'subdivision levels' },
  'max-genes': { type: 'number', min: 1, step: 1 },
  'max-depth': { type: 'number', min: 1, step: 1 },
  'max-primitives': { type: 'number', min: 1, step: 1 },
  granularity: { choices: ['', 'auto', 'merged', 'tag', 'instanced'] },
  'schem-version': { choices: ['', '2', '3'] },
  'data-version': { type: 'number', step: 1 },
};
const PRIMARY = new Set(['steps', 'env', 'box', 'smooth']);
const NUMERIC = new Set(['steps', 'max-modules', 'smooth', 'max-genes', 'max-depth', 'max-primitives', 'schem-version', 'data-version']);

let els;
let viewer;
let current = null; // the entry being sampled
let lastSample = null;
let sampling = 0;

const optionName = (name) => name.replaceAll('_', '-');

export function mount(section) {
  const grammarSelect = h('select', { testid: 'explore-grammar', onchange: () => selectGrammar(grammarSelect.value) });
  const seed = h('input', { type: 'number', min: 0, step: 1, value: 0, testid: 'explore-seed', class: 'seed-input',
    onchange: () => sampleNow() }); // change fires on Enter and on leaving the field
  const stepSeed = (d) => {
    seed.value = Math.max(0, (Number(seed.value) || 0) + d);
    sampleNow();
  };
  const seedRow = h('div', { class: 'seed-row' },
    h('button', { class: 'ghost icon', title: 'previous seed', testid: 'explore-seed-prev', onclick: () => stepSeed(-1), text: '‹' }),
    seed,
    h('button', { class: 'ghost icon', title: 'next seed', testid: 'explore-seed-next', onclick: () => stepSeed(1), text: '›' }),
    h('button', { class: 'ghost', title: 'random seed', testid: 'explore-seed-random', text: 'Random',
      onclick: () => {
        seed.value = Math.floor(Math.random() * 2 ** 31);
        sampleNow();
      } }));
  const options = h('div', { class: 'options', testid: 'explore-options' });
  const more = h('details', { class: 'more-options' }, h('summary', { text: 'More options' }));
  const sampleButton = h('button', { class: 'primary', testid: 'explore-sample', text: 'Sample', onclick: () => sampleNow() });
  const summary = h('p', { class: 'summary', testid: 'explore-summary' });
  const downloads = h('div', { class: 'downloads', testid: 'explore-downloads' });
  const formalism = h('span', { class: 'badge', testid: 'explore-formalism' });
  const sourceText = h('pre', { class: 'source', testid: 'explore-source' });
  const source = h('details', { class: 'source-panel', ontoggle: () => source.open && loadSource() },
    h('summary', { text: 'Grammar source' }), sourceText);
  const envList = h('datalist', { id: 'env-files' });

  const side = h('aside', { class: 'side' },
    h('h2', { text: 'Grammar' }),
    field('Grammar', grammarSelect),
    h('div', { class: 'row' }, formalism),
    field('Seed', seedRow),
    options, more, envList,
    h('div', { class: 'actions' }, sampleButton),
    h('h2', { text: 'Model' }),
    summary,
    h('h3', { text: 'Download' }),
    downloads);
  const mainArea = h('div', { class: 'main explore-main' });
  section.append(h('div', { class: 'layout' }, side, mainArea));
  viewer = new Viewer(mainArea, { testid: 'explore-viewer' });
  mainArea.append(source);
  els = { grammarSelect, seed, options, more, summary, downloads, formalism, sourceText, source, envList, sampleButton };

  on('entries', fill);
  if (store.entries.length) fill();
}

export function shown() {
  viewer?.resize();
}

function fill() {
  const groups = new Map();
  for (const entry of grammarEntries()) {
    if (entry.kind === 'environment') continue;
    if (!groups.has(entry.formalism)) groups.set(entry.formalism, []);
    groups.get(entry.formalism).push(entry);
  }
  els.grammarSelect.replaceChildren();
  for (const [formalism, entries] of groups) {
    const group = h('optgroup', { label: formalism });
    for (const e of entries) group.append(h('option', { value: e.path, text: `${e.title} — ${e.path}` }));
    els.grammarSelect.append(group);
  }
  els.envList.replaceChildren(...store.entries.filter((e) => e.kind === 'environment').map((e) => h('option', { value: e.path })));
  const preferred = grammarEntries().find((e) => e.default) || grammarEntries()[0];
  if (preferred) {
    els.grammarSelect.value = preferred.path;
    selectGrammar(preferred.path);
  }
}

function selectGrammar(path) {
  current = store.entries.find((e) => e.path === path) || null;
  if (!current) return;
  els.formalism.textContent = current.formalism;
  els.options.replaceChildren();
  els.more.replaceChildren(h('summary', { text: 'More options' }));
  let moreCount = 0;
  for (const raw of current.options || []) {
    const name = optionName(raw);
    const spec = OPTION_INPUTS[name] || { type: 'text' };
    let input;
    if (spec.choices) {
      input = h('select', { testid: `explore-option-${name}`, dataset: { option: name } },
        spec.choices.map((c) => h('option', { value: c, text: c || 'default' })));
    } else {
      input = h('input', { type: spec.type, min: spec.min, step: spec.step, placeholder: spec.placeholder || 'default',
        list: spec.list, testid: `explore-option-${name}`, dataset: { option: name },
        onkeydown: (e) => e.key === 'Enter' && sampleNow() });
    }
    const row = field(name, input, spec.hint);
    if (PRIMARY.has(name)) els.options.append(row);
    else {
      els.more.append(row);
      moreCount++;
    }
  }
  els.more.hidden = moreCount === 0;
  els.sourceText.textContent = '';
  if (els.source.open) loadSource();
  sampleNow();
}

async function loadSource() {
  if (!current || els.sourceText.dataset.path === current.path) return;
  try {
    const { text } = await api.source(current.path);
    els.sourceText.textContent = text;
    els.sourceText.dataset.path = current.path;
  } catch (err) {
    els.sourceText.textContent = err.message;
  }
}

function collectOptions() {
  const options = {};
  for (const input of document.querySelectorAll('#view-explore [data-option]')) {
    const value = input.value.trim();
    if (value === '') continue;
    options[input.dataset.option] = NUMERIC.has(input.dataset.option) ? Number(value) : value;
  }
  return options;
}

/** Samples the selected grammar with the current seed and options. */
export async function sampleNow() {
  if (!current) return;
  const token = ++sampling;
  const seed = Math.max(0, Math.floor(Number(els.seed.value) || 0));
  els.sampleButton.disabled = true;
  els.summary.textContent = 'Sampling…';
  viewer.root.dataset.state = 'loading'; // the old model stays visible until the new one loads
  els.summary.classList.remove('error');
  const started = performance.now();
  try {
    const result = await api.sample({ path: current.path, seed, options: collectOptions() });
    if (token !== sampling) return;
    lastSample = result;
    const ms = performance.now() - started;
    els.summary.textContent = `${result.summary || ''} (${fmt(ms / 1000, 2)} s)`;
    els.summary.dataset.sampleId = result.id;
    showDownloads(result);
    if (result.preview === 'glb') await viewer.showGlb(result.model);
    else await viewer.showPicture(result.model, '2D drawing');
  } catch (err) {
    if (token !== sampling) return;
    els.summary.textContent = err.message;
    els.summary.classList.add('error');
    els.downloads.replaceChildren();
    viewer.clear('Sampling failed.');
  } finally {
    if (token === sampling) els.sampleButton.disabled = false;
  }
}

function showDownloads(result) {
  const base = current.path.split('/').pop().replace(/\.[^.]*(\.yaml)?$/, '');
  els.downloads.replaceChildren(...(result.formats || []).map((ext) => h('a', {
    class: 'button ghost', href: api.modelUrl(result.id, ext, true), download: `${base}-${els.seed.value}.${ext}`,
    testid: `explore-download-${ext}`, text: `.${ext}`,
  })));
}

/** The last sample's answer (for the tests' console checks). */
export const last = () => lastSample;
