// Loads a wasm-bindgen `--target web` package in Node and solves one example of each engine: a
// sanity check run after wasm-opt (an old binaryen can emit a module that fails at
// instantiation).
// Usage: node scripts/check-wasm.mjs DIR
import { readFileSync } from 'node:fs';
import { resolve } from 'node:path';
import { pathToFileURL } from 'node:url';

const dir = resolve(process.argv[2]);
const m = await import(pathToFileURL(`${dir}/plcsynth.js`).href);
m.initSync({ module: readFileSync(`${dir}/plcsynth_bg.wasm`) });
const example = (path) => readFileSync(new URL(`../examples/${path}`, import.meta.url), 'utf8');
const verdict = new m.TimedSession(example('timed/lamp.tga')).solve({}, () => true).verdict;
if (verdict !== 'realizable') throw new Error(`lamp: expected realizable, got ${verdict}`);
const sct = new m.SctSession(example('sct/tank_preemption.sct'), {}).solve({}, () => true);
if (sct.supervisors.length !== 1 || !sct.supervisors[0].realizable) throw new Error('tank_preemption: expected one realizable supervisor');
const ltl = new m.LtlSession(example('ltl/arbiter.ltl'), 'ltl').solve({}, () => true).verdict;
if (ltl !== 'realizable') throw new Error(`arbiter: expected realizable, got ${ltl}`);
