// The engine's Web Worker: owns the wasm module and the current Session. Two instances run:
// one checks the editor text as you type, the other solves (and is terminated to cancel).
//
// Requests  {id, op, ...}: check {source} | run {source, options} | query {method, args}
// Replies   {id, ok: true, value} | {id, ok: false, error}; during `run` also
//           {id, progress: Stats} and {id, automata} as soon as the spec compiles.
//           `version` answers {version, targets}.
import init, { check, Session, targets, version } from '../pkg/plcsynth.js';

let session = null;
let lastConsoleError = '';
const consoleError = console.error.bind(console);
console.error = (...args) => {
  lastConsoleError = args.map(String).join(' ');
  consoleError(...args);
};

const ready = init({ module_or_path: new URL('../pkg/plcsynth_bg.wasm', import.meta.url) });

/** An engine error as text: a panic's message (printed by the hook) rather than `unreachable`. */
function describe(error) {
  if (error instanceof WebAssembly.RuntimeError) {
    const panic = lastConsoleError.match(/panicked at[\s\S]*/);
    return `internal error in the engine: ${panic ? panic[0] : error.message}`;
  }
  if (error instanceof Error) return error.message;
  if (typeof error === 'string') return error;
  return error;
}

const ops = {
  version: () => ({ version: version(), targets: targets() }),
  check: ({ source }) => check(source),
  run({ id, source, options }) {
    session?.free();
    session = null;
    const compiled = new Session(source);
    session = compiled;
    postMessage({ id, automata: compiled.automata(), warnings: compiled.warnings() });
    let last = 0;
    const started = performance.now();
    const summary = compiled.solve(options ?? {}, (stats) => {
      const now = performance.now();
      if (now - last > 50) {
        last = now;
        postMessage({ id, progress: stats, elapsed: now - started });
      }
      return true;
    });
    summary.ms = performance.now() - started;
    summary.explanation = compiled.explanation();
    summary.explanationText = compiled.explanationText() ?? null;
    return summary;
  },
  query({ method, args }) {
    if (!session) throw new Error('nothing solved yet');
    if (!['space', 'states', 'neighbourhood', 'state', 'dump', 'program', 'code', 'strategy'].includes(method)) throw new Error(`unknown query ${method}`);
    const started = performance.now();
    const value = session[method](...(args ?? []));
    // The engine's share of a code query, for the page's measurements.
    if (method === 'code' && value) {
      value.engineMs = performance.now() - started;
      value.postedAt = performance.timeOrigin + performance.now();
    }
    return value;
  },
};

onmessage = async ({ data }) => {
  const { id, op } = data;
  try {
    await ready;
    const value = ops[op](data);
    postMessage({ id, ok: true, value });
    if (op === 'run' && value?.verdict === 'realizable') {
      // Build the controller program while the user reads the verdict (0.4 s for round table
      // 8/8), so that the first code view shows at once; queries that come first go first.
      const solved = session;
      setTimeout(() => {
        try {
          if (session === solved) solved.program();
        } catch {
          // The code query will report it.
        }
      }, 0);
    }
  } catch (error) {
    const poisoned = error instanceof WebAssembly.RuntimeError;
    postMessage({ id, ok: false, error: describe(error), poisoned });
  }
};
