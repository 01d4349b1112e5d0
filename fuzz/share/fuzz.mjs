// Fuzzes the page's share-link decoder, www/src/share.js itself, in Node (which has the same
// CompressionStream/DecompressionStream('deflate-raw') as the browser). Why not libFuzzer:
// docs/fuzzing.md, "The share target".
//
//   node fuzz/share/fuzz.mjs SECONDS
//
// Inputs are mutations of links encoded from every example (and of a few hostile links: a
// deflate bomb, junk after the data, text that is not UTF-8, a bad percent escape), mutated as
// link text and, after base64url decoding, as compressed bytes, so that mutations reach the
// inflater as well as the link syntax. An input that produces an outcome not seen before (kind,
// message up to numbers, size class) joins the corpus. The oracle, for every input:
//   - decodeShare settles within 5 s (no hang, whatever the data inflates to);
//   - it returns null exactly when the hash is not a share link;
//   - a result holds two strings, the text at most MAX_SPEC_BYTES of UTF-8, and encoding it
//     again decodes to the same result;
//   - anything else is a ShareError with a message (never a TypeError, DOMException or
//     URIError from the platform).
// The first violation is written to fuzz/artifacts/share/ and ends the run with status 1.
// At the end it prints executions, rate, outcomes and V8's block coverage of share.js.

import { decodeShare, encodeShare, MAX_SPEC_BYTES, ShareError } from '../../www/src/share.js';
import { Session } from 'node:inspector/promises';
import { createHash } from 'node:crypto';
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..');
const seconds = Number(process.argv[2] ?? 60);
// A share link: its header (version 1: the target; version 2: kind, name and target), then the data.
const SHARE_LINK = /^share\/(v1\/[^/]*|v2\/[^/]*\/[^/]*\/[^/]*)\/([A-Za-z0-9_-]*)$/;
const TARGETS = ['st', 'scl', 'codesys', 'il', 'stl', 'plcopen', 'program', 'explanation'];

// A deterministic xorshift, as src/rng.rs: a run is reproducible from its seed.
let state = BigInt(process.env.FUZZ_SEED ?? 1) * 0x9e3779b97f4a7c15n | 1n;
const MASK = (1n << 64n) - 1n;
function below(n) {
  state ^= state >> 12n;
  state ^= (state << 25n) & MASK;
  state ^= state >> 27n;
  return Number(((state * 0x2545f4914f6cdd1dn) & MASK) % BigInt(Math.max(1, n)));
}
const pick = (items) => items[below(items.length)];

const toBase64Url = (bytes) => Buffer.from(bytes).toString('base64url');
const fromBase64Url = (text) => new Uint8Array(Buffer.from(text, 'base64url'));

async function deflate(bytes) {
  const out = new Blob([bytes]).stream().pipeThrough(new CompressionStream('deflate-raw'));
  return new Uint8Array(await new Response(out).arrayBuffer());
}

async function seeds() {
  const links = [];
  const kinds = { tga: 'tga', sct: 'sct', ltl: 'ltl', tlsf: 'tlsf' };
  for (const dir of ['examples/timed', 'examples/sct', 'examples/ltl']) {
    for (const name of fs.readdirSync(path.join(root, dir)).sort()) {
      const text = fs.readFileSync(path.join(root, dir, name), 'utf8');
      const kind = kinds[path.extname(name).slice(1)] ?? 'tga';
      links.push(await encodeShare(text, pick(TARGETS), kind, path.basename(name, path.extname(name))));
    }
  }
  const packed = async (bytes) => toBase64Url(await deflate(bytes));
  const lamp = fs.readFileSync(path.join(root, 'examples/timed/lamp.tga'));
  links.push(`share/v1/st/${await packed(new Uint8Array(MAX_SPEC_BYTES * 4))}`); // a deflate bomb
  links.push(`share/v1/st/${await packed(new Uint8Array(MAX_SPEC_BYTES))}`); // exactly at the bound
  links.push(`share/v1/st/${await packed(lamp)}AAAA`); // junk after the data
  links.push(`share/v1/st/${await packed(new Uint8Array([0xff, 0xfe, 0xc3]))}`); // not UTF-8
  links.push(`share/v1/%E0%A4%A/${await packed(lamp)}`); // a bad percent escape
  links.push(`share/v1/st/${await packed(lamp)}`); // version 1, still read
  links.push(`share/v2/xyz/n/st/${await packed(lamp)}`, `share/v3/st/${await packed(lamp)}`, 'share/v1/st/', 'share/v1/st/A', 'example/lamp');
  return links;
}

/** One to four mutations of a link, as text or as compressed bytes. */
function mutate(link, corpus) {
  let out = link;
  for (let n = 1 + below(4); n > 0; n--) {
    const m = out.match(SHARE_LINK);
    const op = below(10);
    if (m && op < 5) {
      // Mutate the compressed bytes and encode them again.
      const bytes = Array.from(fromBase64Url(m[2]));
      const at = below(bytes.length + 1);
      switch (op) {
        case 0: if (bytes.length) bytes[at % bytes.length] ^= 1 << below(8); break;
        case 1: if (bytes.length) bytes[at % bytes.length] = below(256); break;
        case 2: bytes.splice(at, 0, below(256)); break;
        case 3: bytes.splice(at, 1 + below(8)); break;
        default: {
          const other = pick(corpus).match(SHARE_LINK);
          if (other) bytes.splice(at, bytes.length, ...fromBase64Url(other[2]).subarray(below(64)));
        }
      }
      out = `share/${m[1]}/${toBase64Url(Uint8Array.from(bytes))}`;
    } else {
      const chars = 'ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789-_/%.vé=+ ';
      // Mostly after `share/v1/`: a damaged prefix only makes a link that is no share link.
      const keep = m && below(8) > 0 ? 'share/v1/'.length : 0;
      const at = keep + below(out.length - keep + 1);
      switch (op) {
        case 5: out = out.slice(0, at) + pick(chars) + out.slice(at + 1); break;
        case 6: out = out.slice(0, at) + pick(chars) + out.slice(at); break;
        case 7: out = out.slice(0, at) + out.slice(at + 1 + below(8)); break;
        case 8: out = out.slice(0, at); break;
        default: out = out.slice(0, at) + `%${below(256).toString(16)}` + out.slice(at); break;
      }
    }
  }
  return out;
}

function withTimeout(promise, ms) {
  let timer;
  const timeout = new Promise((_, reject) => {
    timer = setTimeout(() => reject(new Error(`no answer within ${ms} ms (a hang)`)), ms);
  });
  return Promise.race([promise, timeout]).finally(() => clearTimeout(timer));
}

/** Checks one link; returns the outcome's signature, or throws a description of the failure. */
async function check(link) {
  let result;
  try {
    result = await withTimeout(decodeShare(link), 5000);
  } catch (error) {
    if (!(error instanceof ShareError) || !error.message) {
      throw new Error(`not a ShareError: ${error?.name}: ${error?.message ?? error}`);
    }
    return `error:${error.message}`;
  }
  if (result === null) {
    if (SHARE_LINK.test(link)) throw new Error('a share link decoded to null');
    return 'null';
  }
  if (!SHARE_LINK.test(link)) throw new Error('a result from something that is not a share link');
  if (typeof result.spec !== 'string' || typeof result.target !== 'string') throw new Error('not two strings');
  const size = new TextEncoder().encode(result.spec).length;
  if (size > MAX_SPEC_BYTES) throw new Error(`a ${size}-byte specification passed the bound`);
  const again = await decodeShare(await encodeShare(result.spec, result.target, result.kind, result.name));
  if (['spec', 'target', 'kind', 'name'].some((k) => again[k] !== result[k])) throw new Error('encoding again changed the result');
  return `ok:${Math.floor(Math.log2(size + 1))}`;
}

/** V8's block coverage of share.js: covered and total blocks, and the uncovered source. */
function blockCoverage(coverage) {
  const file = path.join(root, 'www/src/share.js');
  const source = fs.readFileSync(file, 'utf8');
  const script = coverage.result.find((s) => s.url.endsWith('/www/src/share.js'));
  if (!script) return { covered: 0, total: 0, uncovered: ['share.js was not instrumented'] };
  let covered = 0;
  let total = 0;
  const uncovered = [];
  for (const fn of script.functions) {
    for (const r of fn.ranges) {
      total += 1;
      if (r.count > 0) covered += 1;
      else uncovered.push(`${fn.functionName || '(module)'}: ${source.slice(r.startOffset, r.endOffset).split('\n')[0]}`);
    }
  }
  return { covered, total, uncovered };
}

const session = new Session();
session.connect();
await session.post('Profiler.enable');
await session.post('Profiler.startPreciseCoverage', { callCount: true, detailed: true });

// Probes checked once, not mutated (each is a megabyte of text).
const probes = [`share/v1/st/${'A'.repeat(2 * MAX_SPEC_BYTES)}`];
for (const link of probes) {
  const outcome = await check(link);
  if (!outcome.startsWith('error:')) throw new Error(`an oversized link was accepted: ${outcome}`);
}
try {
  await encodeShare('x'.repeat(MAX_SPEC_BYTES + 1), 'st');
  throw new Error('a specification past the bound was encoded');
} catch (error) {
  if (!(error instanceof ShareError)) throw error;
}

const corpus = await seeds();
const seen = new Set();
const outcomes = new Map();
let executions = 0;
const start = performance.now();
const deadline = start + seconds * 1000;
let failure = null;
for (let i = 0; !failure && performance.now() < deadline; i++) {
  const link = i < corpus.length ? corpus[i] : mutate(pick(corpus), corpus);
  try {
    const outcome = await check(link);
    executions += 1;
    const kind = outcome.replace(/\d+/g, 'N');
    outcomes.set(kind, (outcomes.get(kind) ?? 0) + 1);
    // New: an error kind or a size class of result not seen before (not every version number).
    const signature = outcome.startsWith('ok:') ? outcome : kind;
    if (!seen.has(signature)) {
      seen.add(signature);
      if (i >= corpus.length) corpus.push(link);
    }
  } catch (error) {
    executions += 1;
    failure = { link, error };
  }
}
const elapsed = (performance.now() - start) / 1000;
const coverage = blockCoverage(await session.post('Profiler.takePreciseCoverage'));
session.disconnect();

console.log(`share: ${executions} executions in ${elapsed.toFixed(0)} s (${(executions / elapsed).toFixed(0)} exec/s), corpus ${corpus.length}`);
for (const [kind, count] of [...outcomes].sort((a, b) => b[1] - a[1])) console.log(`  ${count}\t${kind}`);
console.log(`  share.js block coverage: ${coverage.covered}/${coverage.total}`);
for (const u of coverage.uncovered) console.log(`    not reached: ${u}`);
if (failure) {
  const dir = path.join(root, 'fuzz/artifacts/share');
  fs.mkdirSync(dir, { recursive: true });
  const file = path.join(dir, `crash-${createHash('sha1').update(failure.link).digest('hex')}`);
  fs.writeFileSync(file, failure.link);
  console.log(`FAILURE: ${failure.error.message}\n  input saved to ${file}`);
  process.exit(1);
}
