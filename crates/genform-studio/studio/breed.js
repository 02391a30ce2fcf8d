// Breed: interactive evolution. The server shows 9–16 individuals; the user marks favourites;
// the next generation is bred from them (optionally mixed with the scene's fitness).

import * as api from './api.js';
import { entryOption, h, field, fmt, setChildren } from './dom.js';
import { on, store, toast } from './store.js';
import { Viewer } from './viewer.js';

// Interactive evolution needs a genome: shape grammars and L-systems and their scenes (tree
// genomes, bred with the GA), and codon scenes such as Genr8's (codon genomes, bred with GE).
const BREEDABLE = new Set(['shape grammar', 'L-system', 'scene', 'codon scene']);
let els;
let viewer;
let session = null; // the server's answer for the current generation
const favourites = new Set();
const history = []; // {generation, favourites}

export function mount(section) {
  const source = h('select', { testid: 'breed-source', onchange: () => updateMix() });
  const seed = h('input', { type: 'number', min: 0, step: 1, value: 0, testid: 'breed-seed' });
  const size = h('input', { type: 'number', min: 9, max: 16, step: 1, value: 12, testid: 'breed-size' });
  const mix = h('input', { type: 'range', min: 0, max: 1, step: 0.05, value: 0, testid: 'breed-mix', oninput: () => updateMix() });
  const mixLabel = h('span', { class: 'mix-label', testid: 'breed-mix-label' });
  const start = h('button', { class: 'primary', testid: 'breed-start', text: 'New population', onclick: startSession });
  const next = h('button', { class: 'primary', testid: 'breed-next', text: 'Next generation', disabled: true, onclick: nextGeneration });
  const clear = h('button', { class: 'ghost', testid: 'breed-clear', text: 'Clear picks', onclick: () => {
    favourites.clear();
    renderGrid();
  } });
  const save = h('button', { class: 'ghost', testid: 'breed-save', text: 'Save favourites', disabled: true, onclick: saveSession });
  const generation = h('span', { class: 'big-number', testid: 'breed-generation', text: '–' });
  const count = h('span', { class: 'muted', testid: 'breed-count' });
  const historyList = h('ol', { class: 'breed-history', testid: 'breed-history' });
  const side = h('aside', { class: 'side' },
    h('h2', { text: 'Breed by eye' }),
    field('Grammar or scene', source),
    h('div', { class: 'grid2' }, field('Seed', seed), field('Population (9–16)', size)),
    field('Mix with the scene\u2019s fitness', h('div', { class: 'mix-row' }, mix, mixLabel), '0 = only your picks count; set before “New population”'),
    h('div', { class: 'actions' }, start),
    h('h2', { text: 'Generation' }),
    h('div', { class: 'row' }, generation, count),
    h('p', { class: 'muted small', text: 'Click individuals to mark your favourites, then breed the next generation from them.' }),
    h('div', { class: 'actions' }, next, clear),
    h('div', { class: 'actions' }, save),
    h('h3', { text: 'History' }),
    historyList);
  const grid = h('div', { class: 'breed-grid', testid: 'breed-grid' }, h('p', { class: 'muted', text: 'Start a population to breed.' }));
  const viewHost = h('div', { class: 'panel breed-view' }, h('div', { class: 'panel-title', text: 'Inspect' }));
  section.append(h('div', { class: 'layout' }, side, h('div', { class: 'main breed-main' }, grid, viewHost)));
  viewer = new Viewer(viewHost, { testid: 'breed-viewer' });
  viewer.clear('Use “3D” on an individual to inspect it here.');
  els = { source, seed, size, mix, mixLabel, start, next, save, generation, count, historyList, grid };
  on('entries', fillSources);
  if (store.entries.length) fillSources();
  updateMix();
}

export function shown() {
  viewer?.resize();
}

function fillSources() {
  const breedable = store.entries.filter((e) => BREEDABLE.has(e.formalism));
  const grammars = breedable.filter((e) => e.kind !== 'scene');
  const scenes = breedable.filter((e) => e.kind === 'scene');
  setChildren(els.source,
    grammars.length ? h('optgroup', { label: 'Grammars (your eye is the fitness)' }, grammars.map(entryOption)) : null,
    scenes.length ? h('optgroup', { label: 'Scenes (can mix in their fitness)' }, scenes.map(entryOption)) : null);
  const preferred = breedable.find((e) => e.default) || grammars.find((e) => e.path.endsWith('spaceship.sg')) || breedable[0];
  if (preferred) els.source.value = preferred.path;
  updateMix();
}

function isScene() {
  return store.entries.find((e) => e.path === els.source.value)?.kind === 'scene';
}

function updateMix() {
  const scene = isScene();
  els.mix.disabled = !scene;
  const m = Number(els.mix.value);
  els.mixLabel.textContent = scene ? `${Math.round(m * 100)} % fitness` : 'grammars have no fitness';
}

async function startSession() {
  const body = {
    path: els.source.value,
    seed: Math.max(0, Math.floor(Number(els.seed.value) || 0)),
    size: Math.min(16, Math.max(9, Math.floor(Number(els.size.value) || 12))),
  };
  if (isScene()) body.mix = Number(els.mix.value);
  els.start.disabled = true;
  try {
    session = await api.startBreed(body);
    favourites.clear();
    history.length = 0;
    render();
  } catch (err) {
    toast(err.message, { error: true });
  } finally {
    els.start.disabled = false;
  }
}

async function nextGeneration() {
  if (!session || !favourites.size) return;
  const picked = [...favourites].sort((a, b) => a - b);
  const body = { favourites: picked };
  els.next.disabled = true;
  els.grid.dataset.loading = 'true';
  try {
    const answer = await api.breedPick(session.id, body);
    history.push({ generation: session.generation, favourites: picked });
    session = answer;
    favourites.clear();
    render();
  } catch (err) {
    toast(err.message, { error: true });
  } finally {
    delete els.grid.dataset.loading;
    updateButtons();
  }
}

async function saveSession() {
  if (!session) return;
  try {
    const answer = await api.breedSave(session.id);
    toast(`Saved ${answer.files?.length ?? 0} files to ${answer.folder}`);
  } catch (err) {
    toast(err.message, { error: true });
  }
}

function render() {
  els.generation.textContent = String(session.generation);
  if (session.mix > 0) els.generation.title = `mixed with ${Math.round(session.mix * 100)} % of the scene's fitness`;
  els.grid.dataset.generation = String(session.generation);
  els.grid.style.setProperty('--cols', String(Math.ceil(Math.sqrt(session.individuals.length))));
  setChildren(els.historyList, history.map((h0) => h('li', { text: `gen ${h0.generation}: picked ${h0.favourites.map((i) => `#${i}`).join(', ')}` })));
  renderGrid();
  updateMix();
}

function renderGrid() {
  if (!session) return;
  setChildren(els.grid, session.individuals.map((ind) => {
    const picked = favourites.has(ind.index);
    const card = h('div', { class: `breed-card${picked ? ' picked' : ''}`, testid: `breed-card-${ind.index}`, role: 'button', tabindex: 0,
      'aria-pressed': String(picked), title: 'click to mark as a favourite',
      onclick: () => toggle(ind.index),
      onkeydown: (e) => (e.key === ' ' || e.key === 'Enter') && (e.preventDefault(), toggle(ind.index)) },
      h('img', { src: ind.preview, alt: `individual ${ind.index}`, loading: 'eager', draggable: 'false' }),
      h('div', { class: 'breed-caption' },
        h('span', { text: `#${ind.index}` }),
        ind.fitness !== null && ind.fitness !== undefined ? h('span', { class: 'muted', title: 'the scene\u2019s fitness', text: `f ${fmt(ind.fitness, 3)}` }) : null,
        ind.model ? h('button', { class: 'ghost tiny', testid: `breed-inspect-${ind.index}`, text: '3D', onclick: (e) => {
          e.stopPropagation();
          viewer.showGlb(ind.model, { info: `generation ${session.generation}, #${ind.index}` })
            .catch(() => toast(`#${ind.index} builds no model to show`, { error: true }));
        } }) : null),
      h('span', { class: 'star', 'aria-hidden': 'true', text: picked ? '★' : '☆' }));
    return card;
  }));
  updateButtons();
}

function toggle(index) {
  if (favourites.has(index)) favourites.delete(index);
  else favourites.add(index);
  renderGrid();
}

function updateButtons() {
  els.count.textContent = session ? `${favourites.size} of ${session.individuals.length} picked` : '';
  els.count.dataset.count = String(favourites.size);
  els.next.disabled = !session || favourites.size === 0;
  els.save.disabled = !session;
}
