// The studio's entry point: loads the grammar/scene list, mounts the four views and switches
// between them with the URL hash (#explore, #run, #steer, #breed).

import * as api from './api.js';
import { store, emit, on, toast } from './store.js';
import * as explore from './explore.js';
import * as runView from './run.js';
import * as steer from './steer.js';
import * as breed from './breed.js';

const VIEWS = { explore, run: runView, steer, breed };
const mounted = new Set();

function show(name) {
  if (!VIEWS[name]) name = 'explore';
  for (const key of Object.keys(VIEWS)) {
    const section = document.getElementById(`view-${key}`);
    section.hidden = key !== name;
    document.querySelector(`.tabs [data-view="${key}"]`).setAttribute('aria-selected', String(key === name));
  }
  const section = document.getElementById(`view-${name}`);
  if (!mounted.has(name)) {
    mounted.add(name);
    VIEWS[name].mount(section);
  }
  VIEWS[name].shown?.();
  document.body.dataset.current = name;
}

function indicator() {
  const el = document.querySelector('[data-testid="run-indicator"]');
  const update = () => {
    const run = store.run;
    el.hidden = !run;
    if (!run) return;
    el.dataset.status = run.status;
    el.textContent = `${run.id} · ${run.status} · gen ${run.generation ?? 0}`;
  };
  for (const name of ['run', 'snapshot', 'generation', 'status']) on(name, update);
  el.addEventListener('click', () => (location.hash = '#run'));
}

async function main() {
  for (const button of document.querySelectorAll(".tabs [data-view]")) {
    button.addEventListener('click', () => (location.hash = `#${button.dataset.view}`));
  }
  window.addEventListener('hashchange', () => show(location.hash.slice(1)));
  indicator();
  try {
    store.entries = await api.grammars();
  } catch (err) {
    toast(`Could not list grammars: ${err.message}`, { error: true });
    store.entries = [];
  }
  emit('entries', store.entries);
  // Mount every view once so the Run view can follow a run while another tab is shown.
  for (const name of Object.keys(VIEWS)) {
    if (!mounted.has(name)) {
      mounted.add(name);
      VIEWS[name].mount(document.getElementById(`view-${name}`));
    }
  }
  const first = location.hash.slice(1) || (store.entries.find((e) => e.default)?.kind === 'scene' ? 'run' : 'explore');
  show(first);
  document.body.dataset.ready = 'true';
}

main();
