// Loads a wasm-bindgen `--target web` package in Node and solves the lamp example: a sanity
// check run after wasm-opt (an old binaryen can emit a module that fails at instantiation).
// Usage: node scripts/check-wasm.mjs DIR
import { readFileSync } from 'node:fs';
import { resolve } from 'node:path';
import { pathToFileURL } from 'node:url';

const dir = resolve(process.argv[2]);
const m = await import(pathToFileURL(`${dir}/plcsynth.js`).href);
m.initSync({ module: readFileSync(`${dir}/plcsynth_bg.wasm`) });
const source = readFileSync(new URL('../examples/timed/lamp.tga', import.meta.url), 'utf8');
const verdict = new m.Session(source).solve({}, () => true).verdict;
if (verdict !== 'realizable') throw new Error(`lamp: expected realizable, got ${verdict}`);
