// Bundles the playground with esbuild: www/src/main.js (page), www/src/worker.js (engine) and
// www/src/graphviz-worker.js (Graphviz layouts) into www/dist, with every example of every
// engine (examples/timed/*.tga, examples/sct/*.sct, examples/ltl/*.ltl and *.tlsf) embedded as
// the virtual module `examples`; copies the Markdown docs (docs/*.md: this playground's guide
// and the language references) as they are into www/dist/docs, for the page's Docs link.
import * as esbuild from 'esbuild';
import { copyFileSync, mkdirSync, readdirSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { basename, dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const www = dirname(fileURLToPath(import.meta.url));
const examplesRoot = join(www, '..', 'examples');
/** The example folders, in the gallery's order, with the document kinds they hold. */
const engines = [
  { engine: 'timed', dir: 'timed', kinds: ['tga'] },
  { engine: 'sct', dir: 'sct', kinds: ['sct'] },
  { engine: 'ltl', dir: 'ltl', kinds: ['ltl', 'tlsf'] },
];
const docsDir = join(www, '..', 'docs');

/** Title, description and expected verdict from the leading `//` lines of an example. */
export function describeExample(id, source) {
  const header = [];
  for (const line of source.split('\n')) {
    if (!line.startsWith('//')) break;
    header.push(line.replace(/^\/\/\s?/, ''));
  }
  const text = header.join(' ').replace(/\s+/g, ' ').trim();
  const sentence = (text.match(/^.*?[.!?](\s|$)/) || [text])[0].trim();
  const title = sentence.split(/[:(]/)[0].trim() || id;
  let expected = (text.match(/Expected:\s*(realizable|unrealizable)/i) || [])[1]?.toLowerCase() ?? null;
  // A supervisory-control example describes its supervisors ("Expected result: …"): every one of
  // them exists unless it says otherwise.
  const result = text.match(/Expected result:(.*)/i)?.[1];
  if (!expected && result) expected = /unrealizable|not realizable|no supervisor/i.test(result) ? 'unrealizable' : 'realizable';
  return { id, title, description: sentence, expected };
}

function loadExamples() {
  const all = [];
  for (const { engine, dir, kinds } of engines) {
    const folder = join(examplesRoot, dir);
    const files = readdirSync(folder)
      .map((f) => ({ f, kind: kinds.find((k) => f.endsWith(`.${k}`)) }))
      .filter(({ kind }) => kind)
      .sort((a, b) => a.f.localeCompare(b.f, 'en', { numeric: true }));
    for (const { f, kind } of files) {
      const id = basename(f, `.${kind}`);
      const source = readFileSync(join(folder, f), 'utf8');
      all.push({ ...describeExample(id, source), engine, kind, source });
    }
  }
  // `#example/<id>` names an example of any engine: ids must be unique across folders.
  const seen = new Map();
  for (const e of all) {
    if (seen.has(e.id)) throw new Error(`examples/${seen.get(e.id)}/${e.id} and examples/${e.engine}/${e.id}: an example id must be unique`);
    seen.set(e.id, e.engine);
  }
  return all;
}

const examplesPlugin = {
  name: 'examples',
  setup(build) {
    build.onResolve({ filter: /^examples$/ }, () => ({ path: 'examples', namespace: 'examples' }));
    build.onLoad({ filter: /.*/, namespace: 'examples' }, () => ({
      contents: `export default ${JSON.stringify(loadExamples())};`,
      loader: 'js',
      watchFiles: engines.flatMap(({ dir }) => readdirSync(join(examplesRoot, dir)).map((f) => join(examplesRoot, dir, f))),
    }));
  },
};

rmSync(join(www, 'dist'), { recursive: true, force: true });
const result = await esbuild.build({
  entryPoints: { main: join(www, 'src', 'main.js'), worker: join(www, 'src', 'worker.js'), 'graphviz-worker': join(www, 'src', 'graphviz-worker.js') },
  outdir: join(www, 'dist'),
  bundle: true,
  splitting: true,
  format: 'esm',
  minify: true,
  sourcemap: true,
  target: 'es2022',
  plugins: [examplesPlugin],
  metafile: true,
  logLevel: 'warning',
});
// The docs as they are: Markdown is plain text a browser shows as such.
const docs = readdirSync(docsDir).filter((f) => f.endsWith('.md'));
mkdirSync(join(www, 'dist', 'docs'));
for (const f of docs) copyFileSync(join(docsDir, f), join(www, 'dist', 'docs', f));
// The bundles a first start needs, and the docs, for the service worker (www/sw.js) to fetch on
// install.
const bundles = Object.keys(result.metafile.outputs)
  .filter((f) => f.endsWith('.js'))
  .map((f) => basename(f));
writeFileSync(join(www, 'dist', 'assets.json'), JSON.stringify([...bundles, ...docs.map((f) => `docs/${f}`)]));
const sizes = Object.entries(result.metafile.outputs)
  .filter(([f]) => f.endsWith('.js'))
  .map(([f, o]) => `${basename(f)} ${(o.bytes / 1024).toFixed(0)} KiB`);
console.error(`build: www/dist: ${sizes.join(', ')}`);
