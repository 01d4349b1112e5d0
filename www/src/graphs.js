// Graphs drawn by Graphviz (compiled to wasm, @viz-js/viz, in its own worker started on first
// use: www/src/graphviz-worker.js). The engines write the DOT of every drawing (src/dot.rs over
// petgraph: automata, state spaces, supervisors, Mealy machines); the page only lays it out and
// styles it by the classes the DOT carries.

import { h } from './dom.js';

/** The Graphviz worker and its calls waiting for an answer (id → { resolve, reject }). */
let worker = null;
let nextId = 1;
const pending = new Map();

/** A worker that cannot start, dies, or whose Graphviz aborted: fail what waits; the next call
 * starts a fresh one. */
function restart(reason) {
  for (const p of pending.values()) p.reject(new Error(reason));
  pending.clear();
  worker?.terminate();
  worker = null;
}

function call(dot) {
  if (!worker) {
    worker = new Worker(new URL('./graphviz-worker.js', import.meta.url), { type: 'module', name: 'graphviz' });
    worker.onmessage = ({ data }) => {
      const p = pending.get(data.id);
      pending.delete(data.id);
      if (data.ok) p?.resolve(data.svg);
      else p?.reject(new Error(data.error));
      if (data.poisoned) restart(data.error);
    };
    worker.onerror = (event) => {
      event.preventDefault();
      restart(event.message || 'the Graphviz worker failed');
    };
  }
  const id = nextId++;
  return new Promise((resolve, reject) => {
    pending.set(id, { resolve, reject });
    worker.postMessage({ id, dot });
  });
}

/** Starts the worker and loads Graphviz ahead of use, so that the first graph comes sooner
 * and the page works offline once loaded. */
export function preload() {
  call(null).catch(() => {});
}

/** Renders DOT into an SVG element (throws with Graphviz's message on failure). The layout runs
 * in the worker; only parsing its SVG text is left to the page. */
export async function render(dot) {
  const svg = await call(dot);
  return new DOMParser().parseFromString(svg, 'image/svg+xml').documentElement;
}

/** Appends the drawing of `dot` to `section`, or, when Graphviz fails, a line saying so about
 * `what`: a failed drawing never stops the ones after it. */
export async function drawInto(section, dot, what) {
  try {
    section.append(await render(dot));
  } catch (error) {
    section.append(h('p', { class: 'reason' }, `Graphviz could not draw ${what}: ${error.message ?? error}`));
  }
}
