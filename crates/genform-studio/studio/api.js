// Every request the page makes goes through here, so the HTTP contract (docs/studio.md,
// "API reference") lives in one file.

/** An HTTP error with the server's message (its JSON `error` field when it sent one). */
export class ApiError extends Error {
  constructor(status, message, diagnostics = []) {
    super(message);
    this.status = status;
    this.diagnostics = diagnostics;
  }
}

async function request(method, path, body) {
  const init = { method, headers: {} };
  if (body !== undefined) {
    init.headers['content-type'] = 'application/json';
    init.body = JSON.stringify(body);
  }
  let res;
  try {
    res = await fetch(path, init);
  } catch (err) {
    throw new ApiError(0, `the server does not answer (${err.message}); is genform serve still running?`);
  }
  const text = await res.text();
  let data = null;
  if (text) {
    try {
      data = JSON.parse(text);
    } catch {
      data = text;
    }
  }
  if (!res.ok) {
    const message = (data && (data.error || data.message)) || (typeof data === 'string' && data) || res.statusText;
    const diagnostics = (data && Array.isArray(data.diagnostics) && data.diagnostics) || [];
    const lines = diagnostics.map((d) => `${d.file}:${d.line}:${d.col}: ${d.message}${d.hint ? ` (${d.hint})` : ''}`);
    // Client errors carry the server's message for the user; server errors also say where.
    const text = res.status < 500 ? message : `${method} ${path} failed (${res.status}): ${message}`;
    throw new ApiError(res.status, [text, ...lines].join('\n'), diagnostics);
  }
  return data;
}

const enc = encodeURIComponent;

/** Every grammar and scene the server can sample or run (`kind`: "grammar" | "scene"). */
export const grammars = () => request('GET', '/api/grammars');
/** A grammar's or scene's text. */
export const source = (path) => request('GET', `/api/grammars/source?path=${enc(path)}`);
/** Saves `{name, text, draft?}` in the studio's own folder; answers `{path}` (a root path to sample). */
export const saveGrammar = (body) => request('POST', '/api/grammars/save', body);
/** Samples `{path, seed, options}`; answers `{id, summary, formats, preview, model}`. */
export const sample = (body) => request('POST', '/api/sample', body);
/** The URL of a sampled model in format `ext`; `download` asks for an attachment. */
export const modelUrl = (id, ext, download = false) => `/api/models/${enc(id)}.${ext}${download ? '?download=1' : ''}`;

/** Every run this server knows (running and finished), newest last. */
export const runs = () => request('GET', '/api/runs');

/** GET /api/status: the server's memory budget, what its runs and breeding sessions hold, runs going. */
export const status = () => request('GET', '/api/status');
/** Starts a run: `{scene, algorithm, seed, generations?, budget?}` → `{id, folder}`. */
export const startRun = (body) => request('POST', '/api/runs', body);
/** The run's snapshot: status, generation, stats, steering log, criteria, files. */
export const run = (id) => request('GET', `/api/runs/${enc(id)}`);
/** Pauses, resumes or stops a run (`action`: "pause" | "resume" | "stop"). */
export const control = (id, action) => request('POST', `/api/runs/${enc(id)}/${action}`);
/** Changes weights/targets of a running run: `{weights?, targets?}` → `{queued, generation}`. */
export const steer = (id, body) => request('POST', `/api/runs/${enc(id)}/steer`, body);
/** The URL of a file in a run's folder. */
export const runFileUrl = (id, name) => `/api/runs/${enc(id)}/files/${name.split('/').map(enc).join('/')}`;
/** The run's `run.json` as written in its folder. */
export const runJson = (id) => request('GET', runFileUrl(id, 'run.json'));

/**
 * Subscribes to a run's server-sent events (`generation`, `gallery`, `steering`, `status`);
 * `handlers` maps event names to callbacks taking the parsed data. Returns the EventSource.
 */
export function runEvents(id, handlers) {
  const source = new EventSource(`/api/runs/${enc(id)}/events`);
  for (const [name, fn] of Object.entries(handlers)) {
    if (name === 'error' || name === 'open') continue;
    source.addEventListener(name, (ev) => {
      let data = ev.data;
      try {
        data = JSON.parse(ev.data);
      } catch {
        /* plain text event */
      }
      fn(data);
    });
  }
  if (handlers.open) source.addEventListener('open', handlers.open);
  if (handlers.error) source.addEventListener('error', handlers.error);
  return source;
}

/** Starts interactive evolution: `{path, seed, size, mix}` → generation 0 with its individuals. */
export const startBreed = (body) => request('POST', '/api/breed', body);
/** Breeds the next generation from `{favourites: [index…], mix?}`. */
export const breedPick = (id, body) => request('POST', `/api/breed/${enc(id)}/pick`, body);
/** Writes the session's favourites and genomes into the output folder. */
export const breedSave = (id) => request('POST', `/api/breed/${enc(id)}/save`);
