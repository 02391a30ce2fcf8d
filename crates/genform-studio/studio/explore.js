// Explore: pick a grammar, change the seed and the formalism's options, sample, look at the
// model (3D, or the SVG drawing for 2D formalisms) and download it in any format; or edit the
// grammar's text and see its diagnostics (line:col) and the re-sampled model as you type.

import * as api from './api.js';
import { entryOption, h, field, fmt } from './dom.js';
import { emit, grammarEntries, on, store, toast } from './store.js';
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
let editing = null; // {name, timer} while the editor is open

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
  const editor = h('textarea', { class: 'source editor', spellcheck: 'false', testid: 'editor-text', rows: 18,
    oninput: () => editSoon() });
  const diagnostics = h('ul', { class: 'diagnostics', testid: 'editor-diagnostics' });
  const editName = h('input', { type: 'text', testid: 'editor-name', placeholder: 'name.sg', oninput: () => editSoon() });
  const editBar = h('div', { class: 'row editor-bar' },
    h('button', { class: 'ghost', testid: 'editor-open', text: 'Edit', onclick: () => openEditor() }),
    editName,
    h('button', { class: 'ghost', testid: 'editor-save', text: 'Save', onclick: () => saveEdited() }),
    h('button', { class: 'ghost', testid: 'editor-close', text: 'Close editor', onclick: () => closeEditor() }));
  const source = h('details', { class: 'source-panel', ontoggle: () => source.open && loadSource() },
    h('summary', { text: 'Grammar source' }), editBar, sourceText, editor, diagnostics);
  const envList = h('datalist', { id: 'env-files' });

  const emptyNote = h('p', { class: 'empty-note', testid: 'explore-empty', hidden: true },
    'No grammars found. The studio lists the grammars under --examples (default: ./examples, when the ',
    'studio is started from the repository\u2019s root), the folder of a file given on the command line, ',
    'and those saved from the editor. Start it with `genform serve --examples PATH/examples`, or open ',
    'Grammar source \u2192 Edit to write a new one.');
  const side = h('aside', { class: 'side' },
    h('h2', { text: 'Grammar' }),
    emptyNote,
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
  els = { grammarSelect, seed, options, more, summary, downloads, formalism, sourceText, source, envList, sampleButton,
    editor, diagnostics, editName, editBar, emptyNote };
  showEditor(false);

  on('entries', fill);
  fill();
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
    for (const e of entries) group.append(entryOption(e));
    els.grammarSelect.append(group);
  }
  els.envList.replaceChildren(...store.entries.filter((e) => e.kind === 'environment').map((e) => h('option', { value: e.path })));
  // A refreshed list (a grammar saved from the editor) keeps the grammar being looked at.
  if (current && grammarEntries().some((e) => e.path === current.path)) {
    els.grammarSelect.value = current.path;
    return;
  }
  const preferred = grammarEntries().find((e) => e.default) || grammarEntries()[0];
  if (preferred) {
    els.grammarSelect.value = preferred.path;
    selectGrammar(preferred.path);
  }
  els.emptyNote.hidden = grammarEntries().length > 0;
  if (!grammarEntries().length) {
    els.source.open = true;
    viewer.clear('No grammars yet: write one with Edit, or restart the studio with --examples.');
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
  closeEditor();
  if (els.source.open) loadSource();
  sampleNow();
}

// The editor: the grammar's text in a text area; each pause in typing saves a draft in the
// studio's folder (runs/drafts/) and samples it with the seed and options of the side panel.

function showEditor(open) {
  els.editor.hidden = !open;
  els.diagnostics.hidden = !open;
  els.editName.hidden = !open;
  els.editBar.querySelector('[data-testid="editor-save"]').hidden = !open;
  els.editBar.querySelector('[data-testid="editor-close"]').hidden = !open;
  els.editBar.querySelector('[data-testid="editor-open"]').hidden = open;
  els.sourceText.hidden = open;
}

/** A grammar to start from when there is none to edit: a box, in the shape grammar language. */
const EMPTY_GRAMMAR = '// A new shape grammar: edit it and the model follows.\nStart {\n  size(4, 3, 2);\n  box;\n}\n';

async function openEditor() {
  if (current) {
    await loadSource();
    const file = current.path.split('/').pop();
    const dot = file.indexOf('.');
    els.editName.value = `${file.slice(0, dot)}-edit${file.slice(dot)}`;
    els.editor.value = els.sourceText.textContent;
  } else {
    els.editName.value = 'new.sg';
    els.editor.value = EMPTY_GRAMMAR;
  }
  editing = { timer: null };
  showEditor(true);
  els.editor.focus();
  if (!current) editSoon(); // a new grammar: show its model at once
}

function closeEditor() {
  if (editing?.timer) clearTimeout(editing.timer);
  editing = null;
  if (els) showEditor(false);
}

function editSoon() {
  if (!editing) return;
  clearTimeout(editing.timer);
  editing.timer = setTimeout(() => sampleEdited(), 400);
}

/** Saves the editor's text as a draft and samples it; diagnostics are listed at their line:col. */
async function sampleEdited() {
  if (!editing) return;
  const token = ++sampling;
  els.summary.classList.remove('error');
  els.summary.textContent = 'Checking…';
  try {
    const { path } = await api.saveGrammar({ name: els.editName.value.trim(), text: els.editor.value, draft: true });
    const seed = Math.max(0, Math.floor(Number(els.seed.value) || 0));
    const result = await api.sample({ path, seed, options: collectOptions() });
    if (token !== sampling) return;
    showDiagnostics([]);
    viewer.setStale(false);
    await showSample(result, result.summary || '');
  } catch (err) {
    if (token !== sampling) return;
    // The errors are listed once, under the editor; the side panel only points there,
    // and the model on screen is marked as the last good one.
    const list = err.diagnostics || [];
    showDiagnostics(list, err.message);
    const count = list.length || 1;
    els.summary.textContent = `${count} error${count === 1 ? '' : 's'}: see the list under the editor`;
    els.summary.classList.add('error');
    viewer.setStale(viewer.root.dataset.state === 'loaded');
  }
}

function showDiagnostics(list, message) {
  els.editor.classList.toggle('has-errors', list.length > 0 || Boolean(message));
  const items = list.map((d) => h('li', { class: 'diagnostic', dataset: { line: d.line, col: d.col },
    text: `line ${d.line}:${d.col}: ${d.message}${d.hint ? ` (${d.hint})` : ''}`,
    onclick: () => selectLine(d.line) }));
  if (!list.length && message) items.push(h('li', { class: 'diagnostic', text: message.split('\n')[0] }));
  els.diagnostics.replaceChildren(...items);
}

/** Puts the editor's caret at the start of line `line` (1-based). */
function selectLine(line) {
  const lines = els.editor.value.split('\n');
  const at = lines.slice(0, line - 1).reduce((n, l) => n + l.length + 1, 0);
  els.editor.focus();
  els.editor.setSelectionRange(at, at + (lines[line - 1] || '').length);
}

/** Saves the editor's text in runs/grammars/ and lists it among the grammars. */
async function saveEdited() {
  try {
    const { path } = await api.saveGrammar({ name: els.editName.value.trim(), text: els.editor.value });
    store.entries = await api.grammars();
    emit('entries', store.entries);
    toast(`saved as ${path}`);
  } catch (err) {
    toast(err.message, { error: true });
  }
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
    const ms = performance.now() - started;
    await showSample(result, `${result.summary || ''} (${fmt(ms / 1000, 2)} s)`);
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

/** Shows a sample's answer: its summary line, its downloads and the model (3D, or the 2D drawing). */
async function showSample(result, summary) {
  lastSample = result;
  els.summary.textContent = summary;
  els.summary.dataset.sampleId = result.id;
  showDownloads(result);
  if (result.preview === 'glb') await viewer.showGlb(result.model);
  else await viewer.showPicture(result.model, '2D drawing');
}

function showDownloads(result) {
  // With no grammar selected (a new one in the editor) downloads take the editor's name.
  const base = (current?.path || els.editName.value || 'model').split('/').pop().replace(/\.[^.]*(\.yaml)?$/, '');
  els.downloads.replaceChildren(...(result.formats || []).map((ext) => h('a', {
    class: 'button ghost', href: api.modelUrl(result.id, ext, true), download: `${base}-${els.seed.value}.${ext}`,
    testid: `explore-download-${ext}`, text: `.${ext}`,
  })));
}

/** The last sample's answer (for the tests' console checks). */
export const last = () => lastSample;
