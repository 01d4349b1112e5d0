// The engines' Web Worker: owns the wasm module and the current session of one engine. Two
// instances run: one checks the editor text as you type, the other solves (and is terminated to
// cancel).
//
// Requests  {id, op, ...}: check {kind, source} | import {files, options} | run {kind, source, options}
//           | query {method, args}
// Replies   {id, ok: true, value} | {id, ok: false, error}; during `run` also
//           {id, progress, elapsed} (at most every 50 ms, timed by the engine) and
//           {id, compiled: {automata, warnings}} as soon as the spec compiles.
//           `version` answers {version, targets}.
// `kind` is the document kind: `tga` (timed games), `sct` (supervisory control), `ltl` or `tlsf`.
import { engineOf } from './kinds.js';
import init, { check, importModel, LtlSession, SctSession, TimedSession, targets, version } from '../pkg/plcsynth.js';

let session = null;
let engine = null;
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

/** Per engine: how a run compiles and solves, and which queries its session answers. */
const engines = {
  timed: {
    run(id, source, options, progress) {
      const s = new TimedSession(source);
      postMessage({ id, compiled: { automata: s.automata(), warnings: s.warnings() } });
      return [s, () => {
        const summary = s.solve(options, progress);
        summary.explanation = s.explanation();
        summary.explanationText = s.explanationText() ?? null;
        summary.counterPlay = s.counterPlay();
        return summary;
      }];
    },
    queries: ['space', 'states', 'neighbourhood', 'state', 'dump', 'program', 'code', 'strategy',
      // The simulator (www/src/simulator.js): each returns a SimState, simLocate state ids.
      'counterPlay', 'simStart', 'simReplay', 'simState', 'simStep', 'simDelay', 'simRandom', 'simBack', 'simLocate'],
    code: (s, target, name, created) => s.code(target, name, created),
  },
  sct: {
    run(id, source, options, progress) {
      const s = new SctSession(source, options);
      postMessage({ id, compiled: { automata: s.models(), warnings: s.warnings() } });
      return [s, () => s.solve(options, progress)];
    },
    queries: ['supervisors', 'models', 'events', 'step', 'cycles', 'code'],
    code: (s, target, name, created) => s.code(target, '', '', { createdUnix: created }),
  },
  ltl: {
    run(id, source, options, progress, kind) {
      const s = new LtlSession(source, kind);
      postMessage({ id, compiled: { automata: [], warnings: s.warnings() } });
      return [s, () => s.solve(options, progress)];
    },
    queries: ['signals', 'code'],
    code: (s, target, name, created) => s.code(target, name ? `FB_${name}` : '', { createdUnix: created }),
  },
};

const ops = {
  version: () => ({ version: version(), targets: targets() }),
  check: ({ kind, source }) => check(kind ?? 'tga', source),
  // A Supremica module or libFAUDES generators as a `.sct` project (`plcsynth import`).
  import: ({ files, options }) => importModel(files, options ?? {}),
  run({ id, kind, source, options }) {
    session?.free();
    session = null;
    engine = engines[engineOf(kind)];
    // The engine calls back at most every `progressMs` (its own clock): post each call.
    const progress = (value, elapsed) => {
      postMessage({ id, progress: value, elapsed });
      return true;
    };
    const [compiled, solve] = engine.run(id, source, options ?? {}, progress, kind);
    session = compiled;
    const started = performance.now();
    const summary = solve();
    summary.ms ??= performance.now() - started;
    return summary;
  },
  query({ method, args }) {
    if (!session) throw new Error('nothing solved yet');
    if (!engine.queries.includes(method)) throw new Error(`unknown query ${method}`);
    const started = performance.now();
    const value = method === 'code' ? engine.code(session, ...(args ?? [])) : session[method](...(args ?? []));
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
    if (op === 'run' && value?.verdict === 'realizable' && engine === engines.timed) {
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
