// Graphs drawn by Graphviz (compiled to wasm, @viz-js/viz, in its own worker started on first
// use: www/src/graphviz-worker.js). The engines write the DOT of automata, supervisors and Mealy
// machines (src/dot.rs); the state-space views are assembled here from the engine's SpaceView,
// with the page's selection and strategy.

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

const q = (s) => `"${String(s).replace(/\\/g, '\\\\').replace(/"/g, '\\"').replace(/\n/g, '\\n')}"`;

/** Location names joined in lines of about `width` characters, at most three lines. */
function wrap(names, width) {
  const lines = [''];
  for (const n of names) {
    const last = lines.length - 1;
    if (lines[last] && lines[last].length + n.length + 2 > width) lines.push(n);
    else lines[last] += lines[last] ? `, ${n}` : n;
  }
  if (lines.length > 3) return `${lines.slice(0, 3).join('\n')}…`;
  return lines.join('\n');
}

const kindClass = { request: 'edge-request', reaction: 'edge-reaction', guard: 'edge-guard', delay: 'edge-delay', timeout: 'edge-timeout' };
const kindSigil = { request: '?', reaction: '!', guard: '%', delay: 'D', timeout: 'T' };

/**
 * A state-space (or neighbourhood) graph. Winning and removed states are coloured; the requests
 * the strategy chooses (`strategy`: Map state → { choice, to, label }) are highlighted.
 */
export function spaceDot(view, { selected = null, strategy = null, maxLabel = 30 } = {}) {
  const lines = [
    'digraph space {',
    '  graph [rankdir=TB, bgcolor="transparent", nodesep=0.25, ranksep=0.35, fontname="sans-serif"];',
    '  node [shape=box, style="rounded,filled", fontname="Courier", fontsize=10, margin="0.08,0.03", class="mono"];',
    '  edge [fontname="Courier", fontsize=8, arrowsize=0.6];',
  ];
  for (const s of view.states) {
    const loc = wrap(s.locations, maxLabel);
    const cls = ['state', s.winning ? 'winning' : 'removed', s.id === view.initial ? 'initial' : '', s.id === selected ? 'selected' : '']
      .filter(Boolean)
      .join(' ');
    const plan = strategy?.get(s.id);
    const doing = plan ? (plan.choice === 'wait' ? '; strategy: wait' : `; strategy: ${plan.label}`) : '';
    const tip = s.winning ? `s${s.id}: winning${doing}` : `s${s.id}: removed: ${s.reason ?? ''}`;
    lines.push(`  s${s.id} [id=${q(`st-${s.id}`)}, label=${q(`s${s.id} ${s.kind}\n${loc}`)}, class=${q(cls)}, tooltip=${q(tip)}];`);
  }
  let dangling = 0;
  for (const e of view.edges) {
    const plan = strategy?.get(e.from);
    const chosen = plan?.choice === 'request' && plan.to === e.to && plan.label === e.label;
    const cls = `${kindClass[e.kind] ?? ''}${chosen ? ' chosen' : ''}${e.zeno ? ' zeno' : ''}`;
    const label = e.kind === 'delay' ? 'D' : e.label.length > 28 ? `${e.label.slice(0, 27)}…` : e.label;
    let to = `s${e.to}`;
    if (e.to === null) {
      to = `x${dangling++}`;
      lines.push(`  ${to} [shape=point, width=0.06, class="dangling", label=""];`);
    }
    const style = e.kind === 'reaction' ? 'dashed' : e.kind === 'delay' || e.kind === 'timeout' ? 'dotted' : 'solid';
    lines.push(`  s${e.from} -> ${to} [label=${q(label)}, class=${q(cls)}, style=${style}, tooltip=${q(`${kindSigil[e.kind]} ${e.label}`)}];`);
  }
  lines.push('}');
  return lines.join('\n');
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
