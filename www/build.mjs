// Bundles the playground with esbuild: www/src/main.js (page), www/src/worker.js (engine) and
// www/src/graphviz-worker.js (Graphviz layouts) into www/dist, with every examples/timed/*.tga
// embedded as the virtual module `examples`; copies the Markdown docs (docs/*.md: this
// playground's guide and the language references) as they are into www/dist/docs, for the
// page's Docs link.
import * as esbuild from 'esbuild';
import { copyFileSync, mkdirSync, readdirSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { basename, dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const www = dirname(fileURLToPath(import.meta.url));
const examplesDir = join(www, '..', 'examples', 'timed');
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
  const expected = (text.match(/Expected:\s*(realizable|unrealizable)/i) || [])[1]?.toLowerCase() ?? null;
  return { id, title, description: sentence, expected };
}

function loadExamples() {
  return readdirSync(examplesDir)
    .filter((f) => f.endsWith('.tga'))
    .map((f) => basename(f, '.tga'))
    .sort((a, b) => a.localeCompare(b, 'en', { numeric: true }))
    .map((id) => {
      const source = readFileSync(join(examplesDir, `${id}.tga`), 'utf8');
      return { ...describeExample(id, source), source };
    });
}

const examplesPlugin = {
  name: 'examples',
  setup(build) {
    build.onResolve({ filter: /^examples$/ }, () => ({ path: 'examples', namespace: 'examples' }));
    build.onLoad({ filter: /.*/, namespace: 'examples' }, () => ({
      contents: `export default ${JSON.stringify(loadExamples())};`,
      loader: 'js',
      watchFiles: readdirSync(examplesDir).map((f) => join(examplesDir, f)),
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
