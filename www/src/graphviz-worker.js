// Graphviz's Web Worker: lays out DOT and answers with SVG text. A layout of a large automaton
// or state space takes from tens to hundreds of milliseconds (round table 8/8's 26 automata
// froze the page for 565 ms when drawn on the main thread); here the page stays responsive.
// The page parses the SVG text (DOMParser is not available in workers).
//
// Requests {id, dot} (a `dot` of null only loads Graphviz); replies {id, ok: true, svg} or
// {id, ok: false, error, poisoned}. One layout at a time, in the order asked.
import { instance } from '@viz-js/viz';

const viz = instance();

onmessage = async ({ data }) => {
  const { id, dot } = data;
  try {
    const v = await viz;
    postMessage({ id, ok: true, svg: dot === null ? null : v.renderString(dot, { format: 'svg' }) });
  } catch (error) {
    // An abort inside Graphviz (out of memory on a huge graph) leaves its module unusable: the
    // page then replaces this worker.
    postMessage({ id, ok: false, error: error?.message ?? String(error), poisoned: error instanceof WebAssembly.RuntimeError });
  }
};
