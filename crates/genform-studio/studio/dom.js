// Tiny DOM helpers: the page has no framework, so views build their elements with `h`.

/**
 * Creates an element. `attrs` keys: `class`, `text`, `testid` (→ data-testid), `on*`
 * (event listeners), `dataset`, anything else becomes an attribute (or a property for
 * `value`/`checked`/`disabled`). Children may be nodes, strings or arrays; null is skipped.
 */
export function h(tag, attrs = {}, ...children) {
  const el = document.createElement(tag);
  for (const [key, value] of Object.entries(attrs || {})) {
    if (value === null || value === undefined || value === false) continue;
    if (key === 'class') el.className = value;
    else if (key === 'text') el.textContent = value;
    else if (key === 'testid') el.dataset.testid = value;
    else if (key === 'dataset') Object.assign(el.dataset, value);
    else if (key.startsWith('on') && typeof value === 'function') el.addEventListener(key.slice(2), value);
    else if (key === 'value' || key === 'checked' || key === 'disabled') el[key] = value;
    else el.setAttribute(key, value === true ? '' : value);
  }
  append(el, children);
  return el;
}

function append(el, children) {
  for (const child of children) {
    if (child === null || child === undefined || child === false) continue;
    if (Array.isArray(child)) append(el, child);
    else el.append(child instanceof Node ? child : String(child));
  }
}

/** The element with `data-testid=id` inside `root` (document by default). */
export function byTestId(id, root = document) {
  return root.querySelector(`[data-testid="${id}"]`);
}

/** Replaces all children of `el`. */
export function setChildren(el, ...children) {
  el.replaceChildren();
  append(el, children);
}

/** A labelled form row: `<label><span>text</span>control</label>`. */
export function field(label, control, hint) {
  return h('label', { class: 'field' }, h('span', { class: 'field-label', text: label }), control,
    hint ? h('small', { class: 'field-hint', text: hint }) : null);
}

/** A `<select>` filled from `[{value, label}]`. */
export function select(testid, options, onchange) {
  const el = h('select', { testid, onchange });
  for (const opt of options) el.append(h('option', { value: opt.value, text: opt.label ?? opt.value }));
  return el;
}

/**
 * The `<option>` of a grammar or scene entry `{path, title}`: its file name first, so a
 * narrow picker still shows which file it is, then the title; the whole path as tooltip.
 */
export function entryOption(e) {
  const file = e.path.split('/').pop();
  return h('option', { value: e.path, text: e.title ? `${file} — ${e.title}` : file, title: `${e.path}${e.title ? ` — ${e.title}` : ''}` });
}

/** Formats a number for the UI: fixed significant digits, no exponent for ordinary values. */
export function fmt(x, digits = 4) {
  if (x === null || x === undefined || Number.isNaN(x)) return '–';
  if (typeof x !== 'number') return String(x);
  if (!Number.isFinite(x)) return x > 0 ? '∞' : '−∞';
  const abs = Math.abs(x);
  if (abs !== 0 && (abs >= 1e6 || abs < 1e-3)) return x.toExponential(2);
  return Number(x.toPrecision(digits)).toString();
}

/** "weights symmetry 3.5; targets size 12" for a steering entry's `set`. */
export function describeChange(set = {}) {
  return Object.entries(set)
    .map(([group, values]) => `${group} ${Object.entries(values || {}).map(([k, v]) => `${k} ${fmt(v)}`).join(', ')}`)
    .join('; ');
}
