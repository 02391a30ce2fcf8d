// State shared between views: the grammar/scene list and the run being watched. Views
// listen for `change` events here instead of calling each other.

/** The shared store; dispatches `run` (a new run is watched), `snapshot`, `generation`,
 * `steering`, `status` and `gallery` events with the server's data as `detail`. */
export const store = new EventTarget();

/** Every entry of GET /api/grammars (grammars and scenes). */
store.entries = [];
/** The snapshot of the watched run (kept current from its events), or null. */
store.run = null;

/** Dispatches `name` with `detail`. */
export function emit(name, detail) {
  store.dispatchEvent(new CustomEvent(name, { detail }));
}

/** Calls `fn(detail)` on every `name` event. */
export function on(name, fn) {
  store.addEventListener(name, (ev) => fn(ev.detail));
}

/** The grammars (not scenes) of the list. */
export const grammarEntries = () => store.entries.filter((e) => e.kind !== 'scene');
/** The scenes of the list. */
export const sceneEntries = () => store.entries.filter((e) => e.kind === 'scene');

/** Shows a transient message (errors stay until clicked). */
export function toast(message, { error = false } = {}) {
  const host = document.querySelector('.toasts');
  const el = document.createElement('div');
  el.className = `toast${error ? ' toast-error' : ''}`;
  el.dataset.testid = error ? 'toast-error' : 'toast';
  el.textContent = message;
  el.title = 'click to dismiss';
  el.addEventListener('click', () => el.remove());
  host.append(el);
  if (!error) setTimeout(() => el.remove(), 3000);
  if (error) console.error(message);
}
