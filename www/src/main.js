// The playground page: wires the editor, the engine workers and the views together. The mode
// follows the open document: its kind (`tga`, `sct`, `ltl`, `tlsf`) picks the engine, the
// editor's language, the tabs and the views.
import examples from 'examples';
import { $, actionLink, h, toast, fmtInt, fmtMs } from './dom.js';
import { Engine } from './engine.js';
import { createEditor } from './editor.js';
import { encodeShare, decodeShare } from './share.js';
import { renderSummary } from './summary.js';
import { SpaceView } from './space.js';
import { ZoneView } from './zoneview.js';
import { drawInto, preload } from './graphs.js';
import { engineOf, engineLabel, kindLabel } from './languages.js';
import { templates } from './templates.js';
import { renderSctSummary, SctAutomataView } from './sctview.js';
import { addAssumption, drawMachine, renderLtlSummary } from './ltlview.js';
import { SctSimulator } from './sctsim.js';
import { Simulator } from './simulator.js';

/** Autosave: the current kind, and per kind the last document with where it came from. */
const STORAGE_KEY = 'plcsynth.playground.v2';
const OLD_STORAGE_KEY = 'plcsynth.playground.v1';
const byId = new Map(examples.map((e) => [e.id, e]));

const checker = new Engine('checker');
const solver = new Engine('solver');
const app = { running: false, kind: 'tga', name: 'spec', origin: '', result: null, automata: null, automataDrawn: false, meta: null, code: '', files: [], io: null };
app.engine = () => engineOf(app.kind);
window.plcsynth = app; // for the console and the browser tests
app.engines = { checker, solver };

// ---- editor, diagnostics list, autosave -------------------------------------------------

function showDiagnostics(list) {
  const box = $('#diagnostics');
  if (!list.length) return box.replaceChildren(h('div', { class: 'ok' }, '✓ no problems'));
  box.replaceChildren(
    ...list.map((d) =>
      h(
        'button',
        { class: 'diag', 'data-line': d.line, onclick: () => editor.goto(d.line, d.column) },
        h('span', { class: `diag-${d.severity}` }, d.severity), ` line ${d.line}:${d.column}  ${d.message}`,
        ...d.notes.map((n) => h('span', { class: 'muted' }, ` — ${n}`)),
      ),
    ),
  );
}

/** The autosaved documents: `{ current, docs: { [kind]: { text, name, origin, previous? } } }`. */
function loadSaved() {
  try {
    const saved = JSON.parse(localStorage.getItem(STORAGE_KEY) ?? 'null');
    if (saved?.docs) return saved;
    // The first version kept one timed-game document.
    const old = JSON.parse(localStorage.getItem(OLD_STORAGE_KEY) ?? 'null');
    if (old?.text) return { current: 'tga', docs: { tga: { text: old.text, name: old.name ?? 'spec', origin: '' } } };
  } catch {
    // unreadable: start afresh
  }
  return { current: 'tga', docs: {} };
}
const saved = loadSaved();

/** Autosave; a full or disabled localStorage only costs the autosave. */
function save() {
  saved.current = app.kind;
  saved.docs[app.kind] = { ...saved.docs[app.kind], text: editor.text, name: app.name, origin: app.origin };
  try {
    localStorage.setItem(STORAGE_KEY, JSON.stringify(saved));
  } catch {
    // nothing to do: the edit stays in the editor
  }
}

let saveTimer = 0;
const editor = createEditor($('#editor'), {
  doc: '',
  check: async (text) => (await checker.call('check', { kind: app.kind, source: text })).diagnostics,
  onDiagnostics: showDiagnostics,
  onChange: (text) => {
    // The link in the address bar stays: a reload finds this edit in the autosave, saved with
    // the link it came from, and reopens the edit rather than the link's text.
    if (!app.loading) showName(text);
    markStale(text);
    clearTimeout(saveTimer);
    saveTimer = setTimeout(save, 300);
  },
  onRun: () => run(),
});
app.getText = () => editor.text;
app.editorView = editor.view; // for the console and the browser tests

/** Marks the results on screen as belonging to another text than the editor's, or clears the
 * mark when the text is the one that was run again. */
function markStale(text) {
  const stale = Boolean(app.result) && text !== app.ranText;
  const summary = $('#summary');
  if ((summary.dataset.stale === 'true') === stale) return;
  summary.dataset.stale = String(stale);
  $('#stale-note')?.remove();
  if (stale) {
    summary.prepend(h('p', { class: 'stale', id: 'stale-note', role: 'status' }, 'The spec has changed since this run: these results are for the earlier text. Run again to update them.'));
  }
  $('#status').classList.toggle('stale', stale);
}

/** Whether the autosaved document of `kind` holds work of the user's own: an edited example or
 * link, or a text of their own. */
function isOwnWork(doc) {
  if (!doc?.text?.trim()) return false;
  const ex = byId.get(doc.name);
  if (ex && ex.source === doc.text) return false;
  return !Object.values(templates).includes(doc.text);
}

/**
 * Opens `text` as a document of `kind` named `name`, which came from `origin` (`example/<id>`,
 * a share link, or '' for the user's own). An edit of the same kind it replaces is kept, and a
 * toast offers it back.
 */
function openSpec(text, name, kind = 'tga', origin = '') {
  clearTimeout(saveTimer);
  // The open document first goes to the autosave (its last keystrokes may not be there yet).
  if (editor.text) save();
  const replaced = saved.docs[kind];
  if (isOwnWork(replaced) && replaced.text !== text) {
    saved.docs[kind] = { ...saved.docs[kind], previous: replaced };
    toast(`Your earlier ${kindLabel[kind]} text “${replaced.name}” was kept.`, 8000, { label: 'Restore it', run: () => openSpec(replaced.text, replaced.name, kind, replaced.origin) });
  }
  const switching = kind !== app.kind;
  app.kind = kind;
  app.name = name;
  app.origin = origin;
  app.loading = true;
  if (switching) setMode(kind);
  editor.text = text;
  app.loading = false;
  save();
  showName(text);
}

/** The open example's id and title, marked `(edited)` once the text differs from it. */
function showName(text) {
  const ex = byId.get(app.name);
  const edited = ex && ex.source !== text ? ' (edited)' : '';
  $('#spec-name').textContent = ex ? `${ex.id}${edited}: ${ex.title}` : app.name;
  // The header cuts a long name short with an ellipsis: the whole of it on hover.
  $('#spec-name').title = $('#spec-name').textContent;
}

/** Shows the tabs, settings and menus of the engine of `kind`, and forgets the last results. */
function setMode(kind) {
  const engine = engineOf(kind);
  document.body.dataset.mode = engine;
  $('#mode-badge').textContent = engineLabel[engine];
  document.querySelectorAll('[data-modes]').forEach((el) => (el.hidden = !el.dataset.modes.split(' ').includes(engine)));
  const automataTab = $('[data-tab=automata]');
  automataTab.textContent = automataTab.dataset[`label${engine[0].toUpperCase()}${engine.slice(1)}`] ?? 'Automata';
  editor.setKind(kind);
  clearResults('Press Run (or Ctrl+Enter) to synthesise a controller for the spec on the left.');
  if (app.targets) fillTargets(app.targets);
  if ($(`.tabs [data-tab=${currentTab}]`).hidden) showTab('summary');
}

/** Forgets the results on screen (another engine, or a new run). */
function clearResults(message) {
  app.result = null;
  app.ranText = null;
  app.automata = null;
  app.automataDrawn = false;
  app.meta = null;
  spaceView.reset(null);
  simulator.clear('Run a timed spec to simulate its controller against the plant.');
  sctAutomata.clear('The automata appear here once the spec compiles and runs.');
  sctSim.reset();
  $('#automata').replaceChildren(h('p', { class: 'muted' }, 'The automata appear here once the spec compiles and runs.'));
  $('#summary').replaceChildren(h('p', { class: 'muted' }, message));
  markStale(editor.text);
}

// ---- examples gallery -------------------------------------------------------------------

const galleryItem = (e) =>
  h(
    'li',
    {},
    h(
      'a',
      {
        href: `#example/${e.id}`,
        'data-example': e.id,
        onclick: (event) => {
          $('#gallery').close();
          // The address already names it (an edit keeps the link): no hashchange comes, so
          // open the example's own text here.
          if (location.hash === `#example/${e.id}`) {
            event.preventDefault();
            openSpec(e.source, e.id, e.kind, `example/${e.id}`);
          }
        },
      },
      h('span', { class: 'id' }, e.id),
      h('span', { class: 'title' }, ` ${e.title}`),
      e.kind === 'tlsf' ? h('span', { class: 'badge' }, 'TLSF') : null,
      e.expected ? h('span', { class: `badge ${e.expected}` }, e.expected) : null,
      h('span', { class: 'desc', title: e.description }, e.description),
    ),
  );
$('#gallery-list').replaceChildren(
  ...['timed', 'sct', 'ltl'].map((engine) =>
    h(
      'section',
      { class: 'gallery-section', 'data-engine': engine },
      h('h2', {}, engineLabel[engine]),
      h('ul', {}, examples.filter((e) => e.engine === engine).map(galleryItem)),
    ),
  ),
);
$('#examples-button').addEventListener('click', () => $('#gallery').showModal());

// ---- the "New" menu: an empty document of any kind ---------------------------------------

$('#new-list').replaceChildren(
  ...Object.keys(templates).map((kind) =>
    h(
      'li',
      {},
      h(
        'button',
        {
          'data-new': kind,
          onclick: () => {
            $('#new-menu').close();
            history.replaceState(null, '', location.pathname + location.search);
            openSpec(templates[kind], `untitled.${kind}`, kind, '');
          },
        },
        kindLabel[kind],
      ),
    ),
  ),
);
$('#new-button').addEventListener('click', () => $('#new-menu').showModal());

// ---- open a file: the picker and drag and drop ------------------------------------------

/** The document kind of each extension the page opens as it is; `.wmod` and `.gen` models are
 * imported as a `.sct` project (`importModel`, as `plcsynth import`). */
const OPEN_KINDS = { tga: 'tga', sct: 'sct', ltl: 'ltl', tlsf: 'tlsf' };
const IMPORTED = ['wmod', 'gen'];
const MAX_FILE_MB = 10;
const OPENABLE = 'a .tga (timed game), .sct (supervisory control), .ltl or .tlsf (LTL) document, or a Supremica .wmod or libFAUDES .gen model to import as .sct';
const extensionOf = (name) => (name.match(/\.([^./\\]+)$/)?.[1] ?? '').toLowerCase();

/** A file the page cannot open: said in the status line and a toast, nothing else changes. */
function refuse(message) {
  setStatus(message, 'error');
  toast(message, 8000);
}

/** Opens what the user picked or dropped: one document, one module, or generators together. */
async function openFiles(list) {
  const files = [...list];
  if (!files.length) return;
  const unknown = files.find((f) => !(extensionOf(f.name) in OPEN_KINDS) && !IMPORTED.includes(extensionOf(f.name)));
  if (unknown) return refuse(`“${unknown.name}” is not a file the playground opens: choose ${OPENABLE}.`);
  const big = files.find((f) => f.size > MAX_FILE_MB * 1024 * 1024);
  if (big) return refuse(`“${big.name}” is ${(big.size / 1024 / 1024).toFixed(1)} MB: the playground opens files up to ${MAX_FILE_MB} MB.`);
  const gens = files.filter((f) => extensionOf(f.name) === 'gen');
  if (files.length > 1 && gens.length < files.length) {
    return refuse('Open one file at a time; only libFAUDES .gen generators are opened together (as one project).');
  }
  const [file] = files;
  const ext = extensionOf(file.name);
  if (ext === 'gen') return askRoles(gens);
  const bytes = new Uint8Array(await file.arrayBuffer());
  if (ext === 'wmod') return importModels([{ name: file.name, bytes, kind: 'plant' }]);
  let text;
  try {
    text = new TextDecoder('utf-8', { fatal: true }).decode(bytes);
  } catch {
    return refuse(`“${file.name}” is not UTF-8 text: the playground reads documents in UTF-8.`);
  }
  history.replaceState(null, '', location.pathname + location.search);
  openSpec(text, file.name, OPEN_KINDS[ext], '');
  setStatus(`Opened ${file.name}. Press Run or Ctrl+Enter.`);
}

/** The generators' dialog: each one a plant or a specification, and whether to ignore marking. */
let pendingGens = [];
function askRoles(gens) {
  pendingGens = gens;
  $('#import-roles').replaceChildren(
    ...gens.map((f, i) =>
      h(
        'li',
        {},
        h('span', { class: 'file' }, f.name),
        h(
          'select',
          { 'data-role': i, 'aria-label': `what ${f.name} is` },
          h('option', { value: 'plant' }, 'plant'),
          // A name that says so is preselected as a specification; the user sees and decides.
          h('option', { value: 'spec', selected: /spec/i.test(f.name) }, 'specification'),
        ),
      ),
    ),
  );
  $('#import-menu').showModal();
}
$('#import-go').addEventListener('click', async () => {
  $('#import-menu').close();
  const files = await Promise.all(
    pendingGens.map(async (f, i) => ({ name: f.name, bytes: new Uint8Array(await f.arrayBuffer()), kind: $(`[data-role="${i}"]`).value })),
  );
  importModels(files, $('#import-ignore-marking').checked);
});

/** Imports `files` (`{ name, bytes, kind }`) as a `.sct` project in the checker worker. On success
 * it opens as any document does (an edit of the open `.sct` document is kept and offered back);
 * on errors the open document stays and the located errors are listed under the editor. */
async function importModels(files, ignoreMarking = false) {
  const names = files.map((f) => f.name).join(', ');
  setStatus(`Importing ${names}…`, 'running');
  let imported;
  try {
    imported = await checker.call('import', { files, options: { ignoreMarking } });
  } catch (error) {
    if (!error?.diagnostics) return setStatus(`${names} cannot be imported: ${error?.message ?? error}`, 'error');
    showImportErrors(error, files, ignoreMarking);
    const n = error.diagnostics.length;
    return setStatus(`${names} ${files.length === 1 ? 'was' : 'were'} not imported: ${n} error${n === 1 ? '' : 's'} (listed under the editor). The open document is unchanged.`, 'error');
  }
  history.replaceState(null, '', location.pathname + location.search);
  openSpec(imported.text, imported.name, 'sct', '');
  setStatus(`Imported ${names} as the .sct project ${imported.name}: edit it, or press Run to synthesise its supervisors.`, 'done');
}

/** A refused import's diagnostics in the message list: each located in its own file, with the
 * source line and a caret; when unmarked states are the reason, a button imports again with
 * every state marked. The next check of the editor's text replaces the list. */
function showImportErrors(error, files, ignoreMarking) {
  $('#diagnostics').replaceChildren(
    h(
      'div',
      { class: 'import-head', id: 'import-errors' },
      `Not imported: ${files.map((f) => f.name).join(', ')} (the open document is unchanged)`,
      error.unmarked && !ignoreMarking
        ? h('button', { id: 'import-ignore-marking-again', title: 'import again, reading every state as marked', onclick: () => importModels(files, true) }, 'Ignore marking')
        : null,
    ),
    ...error.diagnostics.map((d) =>
      h(
        'div',
        { class: 'diag import-diag', 'data-file': d.file, 'data-line': d.line, 'data-column': d.column },
        h('span', { class: `diag-${d.severity}` }, d.severity), ` ${d.file} line ${d.line}:${d.column}  ${d.message}`,
        // The source line with a caret, and the notes (its first line repeats the message).
        h('pre', {}, d.rendered.split('\n').slice(1).join('\n').trimEnd()),
      ),
    ),
  );
}

$('#open-button').addEventListener('click', () => $('#open-file').click());
$('#open-file').addEventListener('change', (event) => {
  const files = [...event.target.files];
  event.target.value = ''; // the same file again is a new choice
  openFiles(files);
});

// Files dropped anywhere on the page open (CodeMirror would paste their text into the
// document): listened for in the capture phase, before the editor sees them. Text dragged
// within the editor is left to it.
const draggingFiles = (event) => [...(event.dataTransfer?.types ?? [])].includes('Files');
for (const type of ['dragenter', 'dragover']) {
  window.addEventListener(
    type,
    (event) => {
      if (!draggingFiles(event)) return;
      event.preventDefault();
      event.stopPropagation();
      event.dataTransfer.dropEffect = 'copy';
      document.body.dataset.dropping = 'true';
    },
    true,
  );
}
window.addEventListener('dragleave', (event) => {
  if (!event.relatedTarget) delete document.body.dataset.dropping;
}, true);
window.addEventListener(
  'drop',
  (event) => {
    delete document.body.dataset.dropping;
    if (!draggingFiles(event)) return;
    event.preventDefault();
    event.stopPropagation();
    openFiles(event.dataTransfer.files);
  },
  true,
);

// ---- routing: #example/<id>, #share/v1/<target>/<data> ------------------------------------

/** Opens what the address names; an autosaved edit of the same link is opened instead of the
 * link's own text, so that a reload keeps the edit. */
function openRouted(text, name, kind, origin) {
  const doc = saved.docs[kind];
  if (doc?.origin === origin && doc.text !== text && doc.text) return openSpec(doc.text, doc.name, kind, origin);
  return openSpec(text, name, kind, origin);
}

async function route() {
  let hash = location.hash.slice(1);
  try {
    hash = decodeURIComponent(hash);
  } catch {
    // A bad percent escape: route the text as it is (decodeShare reports a broken share link).
  }
  if (hash.startsWith('example/')) {
    const ex = byId.get(hash.slice(8));
    if (ex) {
      openRouted(ex.source, ex.id, ex.kind, hash);
      return true;
    }
    toast(`No example called "${hash.slice(8)}".`);
  } else if (hash.startsWith('share/')) {
    try {
      const shared = await decodeShare(location.hash.slice(1));
      if (shared) {
        openRouted(shared.spec, shared.name || 'shared spec', shared.kind, location.hash.slice(1));
        setTarget(shared.target);
        return true;
      }
    } catch (error) {
      toast(`This share link cannot be read: ${error.message ?? error}`);
    }
  }
  return false;
}
window.addEventListener('hashchange', route);

// ---- tabs -------------------------------------------------------------------------------

let currentTab = 'summary';
function showTab(name) {
  currentTab = name;
  document.querySelectorAll('.tabs [role=tab]').forEach((b) => {
    b.setAttribute('aria-selected', String(b.dataset.tab === name));
    // One tab stop for the bar; the arrow keys move within it.
    b.tabIndex = b.dataset.tab === name ? 0 : -1;
  });
  document.querySelectorAll('.panel').forEach((p) => (p.hidden = p.dataset.panel !== name));
  if (name === 'automata') drawAutomata();
  if (name === 'code') refreshCode();
  if (name === 'step') sctSim.showStepper();
  if (name === 'cycles') sctSim.showCycles();
  if (name === 'simulate') simulator.open();
}
document.querySelectorAll('.tabs [role=tab]').forEach((b) => b.addEventListener('click', () => showTab(b.dataset.tab)));
// The WAI-ARIA tabs pattern: Left/Right move to the neighbouring tab, Home/End to the ends.
$('.tabs').addEventListener('keydown', (event) => {
  const tabs = [...document.querySelectorAll('.tabs [role=tab]')].filter((b) => !b.hidden);
  const at = tabs.findIndex((b) => b.dataset.tab === currentTab);
  const next = { ArrowRight: at + 1, ArrowLeft: at - 1, Home: 0, End: tabs.length - 1 }[event.key];
  if (next === undefined) return;
  event.preventDefault();
  const tab = tabs[(next + tabs.length) % tabs.length];
  showTab(tab.dataset.tab);
  tab.focus();
});

// ---- automata ---------------------------------------------------------------------------

const sctAutomata = new SctAutomataView($('#automata'));
const sctSim = new SctSimulator({ query: (method, args) => query(method, args), stepBox: $('#sct-stepper'), cyclesBox: $('#sct-cycles') });

async function drawAutomata() {
  if (app.engine() === 'sct') return sctAutomata.draw();
  if (app.engine() === 'ltl') {
    if (app.automataDrawn) return;
    app.automataDrawn = true;
    return drawMachine($('#automata'), app.result);
  }
  if (!app.automata || app.automataDrawn) return;
  app.automataDrawn = true;
  const list = app.automata;
  const box = $('#automata');
  box.replaceChildren(
    h(
      'div',
      { class: 'legend' },
      h('span', { class: 'l-request' }, '?request (controller)'),
      h('span', { class: 'l-reaction' }, '!reaction (plant)'),
      h('span', { class: 'l-plan' }, '$plan step'),
      h('span', { class: 'l-init' }, '→ initial location'),
      h('span', { class: 'l-location' }, 'location: name, then its invariant (clock in interval)'),
      h('span', { class: 'l-failed' }, 'failed: the plan has failed'),
      h('span', { class: 'l-text' }, 'edge: message, guard, reset{clocks}; (instant): taken before any time passes'),
    ),
  );
  for (const a of list) {
    const section = h('section', { class: 'automaton', 'data-name': a.name }, h('h3', {}, a.name, ' ', h('span', { class: 'muted' }, a.kind)));
    box.append(section);
    await drawInto(section, a.dot, a.name);
    if (app.automata !== list) return;
  }
}

// ---- state space and zone ----------------------------------------------------------------

/** A query to the worker; the last 20 with their round-trip times are kept in `app.queries`
 * (for the console and the browser tests' measurements). */
const query = async (method, args) => {
  const started = performance.now();
  try {
    return await solver.call('query', { method, args });
  } finally {
    app.queries = [...(app.queries ?? []).slice(-19), { method, ms: Math.round(performance.now() - started) }];
  }
};
const zoneView = new ZoneView($('#zone'));
const spaceView = new SpaceView({
  query,
  onSelect: async (id) => {
    const state = await query('state', [id]);
    zoneView.show(state, app.meta);
    const plan = spaceView.strategy?.get(id);
    const doing = !spaceView.strategy || !state.winning ? '' : !plan ? ' · not reached by the strategy' : plan.choice === 'wait' ? ' · strategy: wait' : ` · strategy: ${plan.label} → s${plan.to}`;
    $('#selected-bar').replaceChildren(
      h('strong', {}, `s${id}`), ` ${state.winning ? 'winning' : 'removed'}`,
      state.reason ? h('span', { class: 'reason' }, ` — ${state.reason}`) : '',
      h('span', { id: 'selected-strategy' }, doing),
      ` · zone: ${state.zone} · `,
      actionLink('show the zone', () => showTab('zone'), { id: 'show-zone' }),
    );
  },
});

// ---- simulator ----------------------------------------------------------------------------

/** Selects state `id` in the State space tab (from the summary, the explanation, the simulator). */
async function showState(id) {
  showTab('space');
  await spaceReady;
  await spaceView.select(id);
}

const simulator = new Simulator($('#simulator'), {
  query,
  onLocate: showState,
  onTab: () => showTab('simulate'),
});
app.simulator = simulator;

// ---- code pane ----------------------------------------------------------------------------

const DUMP_LINES = 4000;
// A document's own extension is not part of the stem (`lamp.tga` downloads as `lamp.st`).
const fileStem = () => app.name.replace(/\.(tga|sct|ltl|tlsf)$/i, '').replace(/[^A-Za-z0-9_-]+/g, '_');

/** Fills the target menu from the engine's list: for timed games the intermediate program, every
 * PLC target and the text views; for the other engines every PLC target. */
function fillTargets(list) {
  app.targets = list;
  const select = $('#target');
  const previous = select.value;
  const option = (value, label) => h('option', { value }, label);
  const timed = app.engine() === 'timed';
  const plc = list.filter((t) => timed || t.id !== 'program');
  const controller = { timed: 'Controller', sct: 'Runtime framework (Göbe 2019, 6.3)', ltl: 'Controller function block' }[app.engine()];
  select.replaceChildren(
    h('optgroup', { label: controller }, plc.map((t) => option(t.id, t.multi_file ? t.label : `${t.label} (.${t.extension})`))),
    timed ? h('optgroup', { label: 'Analysis (text)' }, option('space', 'State space dump (.txt)'), option('explanation', 'Explanation (.txt)')) : null,
  );
  select.value = app.pendingTarget ?? previous;
  if (!select.value) select.value = 'st';
  app.pendingTarget = null;
}

function setTarget(target) {
  const select = $('#target');
  if ([...select.options].some((o) => o.value === target)) select.value = target;
  else app.pendingTarget = target;
}

/** Downloads `text` as `name`. */
function download(name, text, type = 'text/plain') {
  const a = h('a', { href: URL.createObjectURL(new Blob([text], { type })), download: name });
  a.click();
  // The browser fetches the blob after the click returns; on a busy machine that took over a
  // second, and a URL revoked by then gave no download at all. A minute is ample.
  setTimeout(() => URL.revokeObjectURL(a.href), 60_000);
}

/** Lines shown at once; the rest follows in chunks between frames, so that the first screen of
 * a large program (round table 8/8: about 55 000 lines) appears at once and the page stays
 * responsive. A newer render cancels an older one. */
const FIRST_LINES = 300;
const CHUNK_LINES = 4000;
let renderToken = 0;

/** The index after the `n`-th line break from `from` (or the end). */
function afterLines(text, from, n) {
  let at = from;
  for (let i = 0; i < n; i++) {
    const next = text.indexOf('\n', at);
    if (next < 0) return text.length;
    at = next + 1;
  }
  return at;
}

function renderCode(text, started) {
  const token = ++renderToken;
  const pre = $('#code');
  let at = afterLines(text, 0, FIRST_LINES);
  pre.textContent = text.slice(0, at);
  window.plcsynth.codeTimings = { ...window.plcsynth.codeTimings, firstScreenMs: performance.now() - started, doneMs: null };
  pre.dataset.complete = at >= text.length ? 'true' : 'false';
  const more = () => {
    if (token !== renderToken) return;
    const end = afterLines(text, at, CHUNK_LINES);
    pre.append(text.slice(at, end));
    at = end;
    if (at < text.length) setTimeout(more, 0);
    else {
      pre.dataset.complete = 'true';
      window.plcsynth.codeTimings.doneMs = performance.now() - started;
    }
  };
  if (at < text.length) setTimeout(more, 0);
  else window.plcsynth.codeTimings.doneMs = performance.now() - started;
}

/** The I/O table under the target menu, with its CSV, SDF and CODESYS mapping downloads. */
function renderIo(generated) {
  const box = $('#io-box');
  const rows = generated?.io ?? [];
  app.io = rows.length ? generated : null;
  box.hidden = rows.length === 0;
  if (!rows.length) return;
  $('#io-count').textContent = `${rows.length} signal${rows.length === 1 ? '' : 's'}`;
  $('#io-table tbody').replaceChildren(
    ...rows.map((r) => h('tr', {}, h('td', {}, r.address || '—'), h('td', {}, r.type), h('td', {}, r.symbol), h('td', {}, r.direction), h('td', {}, r.meaning))),
  );
  $('#download-io-sdf').hidden = !generated.io_sdf;
  // The mapping list of CODESYS's device editor, which ABB's Automation Builder shares.
  $('#download-io-codesys').hidden = !generated.io_codesys || !['codesys', 'abb'].includes(generated.target);
}

/** One button per file of a multi-file target (TwinCAT). */
function renderFiles(files) {
  const bar = $('#code-files');
  bar.hidden = files.length < 2;
  bar.replaceChildren(
    ...(files.length < 2 ? [] : [h('span', { class: 'muted' }, `${files.length} files:`), ...files.map((f) => h('button', { class: 'file', onclick: () => download(f.name, f.text) }, f.name))]),
  );
}

async function refreshCode() {
  const started = performance.now();
  const target = $('#target').value;
  const note = $('#code-note');
  note.dataset.realtime = '';
  app.code = '';
  app.extension = 'txt';
  app.suffix = '';
  app.files = [];
  renderToken++;
  // Emptied first: restyling a pane that still holds tens of thousands of lines costs hundreds
  // of milliseconds. `data-target` and `data-complete` say what it shows (the tests wait on them).
  $('#code').textContent = '';
  $('#code').dataset.target = '';
  $('#code').dataset.complete = 'false';
  // Timings describe the text being shown: none until this one is (a test waiting on them must
  // not take the last text's).
  window.plcsynth.codeTimings = null;
  renderIo(null);
  renderFiles([]);
  if (!app.result) {
    $('#code').textContent = '';
    note.textContent = 'Run the spec first.';
    return;
  }
  let cap = Infinity;
  if (target === 'explanation') {
    app.code = app.result.explanationText ?? '';
    app.suffix = '.explanation';
    note.textContent = app.code ? '' : 'No explanation: the spec is not unrealizable.';
  } else if (target === 'space') {
    app.code = await query('dump', []);
    app.suffix = '.states';
    cap = DUMP_LINES;
    note.textContent = 'Every explored state with its status, then its edges.';
  } else {
    let generated;
    note.textContent = 'Generating…';
    try {
      generated = await query('code', [target, fileStem(), Date.now() / 1000]);
    } catch (error) {
      if (!error?.diagnostics) throw error;
      // A time constant or a tag this target cannot hold: located in the spec, like any input error.
      showDiagnostics(error.diagnostics);
      $('#code').textContent = '';
      note.textContent = `No ${target} code: ${error.diagnostics[0]?.message ?? 'the spec does not fit this target'} (see the diagnostics).`;
      return;
    }
    if ($('#target').value !== target) return;
    const arrived = performance.timeOrigin + performance.now();
    window.plcsynth.codeTimings = { target, queryMs: performance.now() - started, engineMs: generated?.engineMs, transitMs: generated ? arrived - generated.postedAt : null, sentAfterMs: generated ? generated.postedAt - (performance.timeOrigin + started) : null };
    const realtime = generated?.realtime;
    if (realtime?.failure) {
      // The code failed a run against the plant at the declared scan time: no code, the trace.
      app.code = `${realtime.failure}\n\n${realtime.trace.join('\n')}\n`;
      app.suffix = '.realtime';
      note.textContent = `No code: it fails at ${realtime.scan_ms} ms in a real-time run against the plant, although the scan game says implementable (${realtime.why}). The trace:`;
      note.dataset.realtime = 'failed';
    } else if (generated) {
      const files = generated.files;
      app.code = files.length === 1 ? files[0].text : files.map((f) => `==> ${f.name} <==\n${f.text}`).join('');
      app.extension = generated.extension;
      app.files = generated.files;
      renderIo(generated);
      renderFiles(generated.files);
      note.textContent = {
        timed: app.result?.scan?.code_from?.startsWith('the scan strategy')
          ? (target === 'program' ? 'The program of the scan game’s strategy: each scan reads the inputs, takes one decision and writes.' : 'Generated from the program of the scan game’s strategy: one read, one decision, one write per scan.')
          : (target === 'program' ? 'The optimised controller program (Peter 2005, chapter 6).' : 'Generated from the optimised controller program.'),
        sct: 'The runtime framework: it detects the events, asks every supervisor, resets denied outputs and executes enforced events around the existing controller (FB “Controller”).',
        ltl: 'The controller as a function block: call it once per scan.',
      }[app.engine()];
      if (realtime) note.textContent += ` Checked at ${realtime.scan_ms} ms: ${realtime.runs} runs of ${fmtInt(realtime.scans_per_run)} scans against the plant, timed adversarially, no failure.`;
      note.dataset.realtime = realtime ? 'held' : '';
    } else {
      note.textContent = app.engine() === 'sct' ? `No framework: ${verdictPhrase(app.result.verdict)}.` : `No controller: ${verdictPhrase(app.result.verdict)}.`;
    }
  }
  if ($('#target').value !== target) return;
  $('#code').dataset.target = target;
  if (cap < Infinity) {
    const lines = app.code.split('\n');
    if (lines.length > cap) {
      renderCode(`${lines.slice(0, cap).join('\n')}\n… ${fmtInt(lines.length - cap)} more lines: use Download`, started);
      return;
    }
  }
  renderCode(app.code, started);
}
$('#target').addEventListener('change', refreshCode);
$('#copy-code').addEventListener('click', async () => {
  try {
    await navigator.clipboard.writeText(app.code);
    toast('Copied.');
  } catch {
    toast('The browser refused the clipboard; use Download.');
  }
});
$('#download-code').addEventListener('click', () => {
  if (!app.code) return toast(app.result ? `Nothing to download: ${$('#code-note').textContent}` : 'Nothing to download yet: run the spec first.');
  // A target's files under their own names (one download each for TwinCAT's three).
  if (app.files.length) app.files.forEach((f) => download(f.name, f.text));
  else download(`${fileStem()}${app.suffix}.${app.extension}`, app.code);
});
$('#download-io-csv').addEventListener('click', () => app.io && download(`${fileStem()}_io.csv`, app.io.io_csv, 'text/csv'));
$('#download-io-sdf').addEventListener('click', () => app.io && download(`${fileStem()}_tags.sdf`, app.io.io_sdf));
$('#download-io-codesys').addEventListener('click', () => app.io && download(`${fileStem()}_mapping.csv`, app.io.io_codesys, 'text/csv'));

// ---- share ------------------------------------------------------------------------------

$('#share').addEventListener('click', async () => {
  let hash;
  try {
    hash = await encodeShare(editor.text, $('#target').value, app.kind, app.name);
  } catch (error) {
    return toast(`This specification cannot be shared: ${error.message ?? error}`);
  }
  history.replaceState(null, '', `#${hash}`);
  // The document now comes from this link: a reload reopens it (with later edits).
  app.origin = hash;
  save();
  try {
    await navigator.clipboard.writeText(location.href);
    toast('Link copied to the clipboard.');
  } catch {
    toast('The link is in the address bar (the browser refused the clipboard).');
  }
});

// ---- run and cancel ---------------------------------------------------------------------

/** What a verdict says of the spec, as the end of a sentence. */
function verdictPhrase(verdict) {
  return (
    {
      realizable: 'the spec is realizable',
      unrealizable: 'the spec is unrealizable',
      budget_exceeded: 'the search exceeded its budget before deciding',
      cancelled: 'the search was cancelled before deciding',
      unknown: 'the verdict is unknown (no player won within the bound)',
      error: 'synthesis found errors in the project',
    }[verdict] ?? `the verdict is ${verdict}`
  );
}

function setStatus(text, kind = '') {
  const el = $('#status');
  el.textContent = text;
  el.className = `status ${kind}`;
  el.dataset.kind = kind;
}

function setRunning(on) {
  app.running = on;
  $('#run').disabled = on;
  $('#cancel').disabled = !on;
}

let spaceReady = Promise.resolve();
async function run() {
  if (app.running) return;
  setRunning(true);
  const started = performance.now();
  const source = editor.text;
  const kind = app.kind;
  const engine = app.engine();
  const maxStates = Math.max(10, Number($('#max-states').value) || 1000000);
  app.result = null;
  app.ranText = source;
  markStale(source);
  app.automata = null;
  app.automataDrawn = false;
  app.meta = null;
  spaceView.reset(null);
  sctSim.reset();
  simulator.clear('Running…');
  $('#summary').replaceChildren(h('p', { class: 'muted' }, 'Running…'));
  setStatus('Compiling…', 'running');
  const options = {
    timed: { maxStates, progressInterval: 256, exhaustive: $('#exhaustive').checked },
    sct: { method: $('#sct-method').value, compose: $('#sct-compose').checked },
    // A GR(1) controller comes as a circuit too, and its code from the circuit.
    ltl: { suggest: $('#ltl-suggest').checked, solver: $('#ltl-solver').value, circuit: $('#ltl-solver').value === 'gr1' },
  }[engine];
  const progressText = {
    timed: (p) => `Exploring… ${fmtInt(p.visited)} states visited, ${fmtInt(p.removed)} removed`,
    sct: (p) => `Synthesising… ${fmtInt(p.built)} product states built`,
    ltl: (p) =>
      p.nodes > 0
        ? `Solving… k = ${p.k}, ${fmtInt(p.nodes)} BDD nodes`
        : `Solving… k = ${p.k}, ${fmtInt(p.positions)} game positions`,
  }[engine];
  try {
    const summary = await solver.call(
      'run',
      { kind, source, options },
      {
        onCompiled: (automata) => {
          app.automata = automata;
          if (engine === 'sct') sctAutomata.load(automata);
          setStatus({ timed: 'Exploring…', sct: 'Synthesising…', ltl: 'Solving…' }[engine], 'running');
          if (currentTab === 'automata') drawAutomata();
        },
        onProgress: (progress, elapsed) => setStatus(`${progressText(progress)} (${fmtMs(elapsed)})`, 'running'),
      },
    );
    const ms = performance.now() - started;
    const ex = byId.get(app.name);
    const expected = ex && ex.source === source ? ex.expected : null;
    app.result = summary;
    if (engine === 'timed') {
      renderSummary($('#summary'), {
        summary,
        ms,
        expected,
        maxStates,
        onState: showState,
        onReplay: () => simulator.replay(),
      });
      setStatus(`${summary.verdict.replace('_', ' ')}: ${fmtInt(summary.stats.visited)} states visited, ${fmtInt(summary.stats.winning)} winning, ${fmtInt(summary.stats.removed)} removed in ${fmtMs(summary.ms)}`, 'done');
    } else if (engine === 'sct') {
      renderSctSummary($('#summary'), { summary, ms, expected, onLocate: (line, column) => editor.goto(line, column) });
      const n = summary.supervisors.length;
      setStatus(`${verdictPhrase(summary.verdict).replace(/^the spec is /, '')}: ${n} supervisor${n === 1 ? '' : 's'}, ${fmtInt(summary.supervisors.reduce((a, x) => a + x.states, 0))} states in ${fmtMs(summary.ms)}`, 'done');
    } else {
      renderLtlSummary($('#summary'), { summary, ms, expected, onAddAssumption: (list) => addAssumptions(kind, list) });
      setStatus(`${summary.summary} (${fmtMs(summary.ms)})`, 'done');
    }
    // Edited while it ran: the results are for the text that was run.
    markStale(editor.text);
    setRunning(false);
    if (engine === 'sct' && !summary.stop) sctAutomata.load(app.automata, await query('supervisors', []));
    if (engine === 'sct') {
      // Both simulations need every supervisor to exist.
      sctSim.reset(summary.verdict === 'realizable', `Nothing to simulate: ${verdictPhrase(summary.verdict)}.`);
      if (currentTab === 'step') sctSim.showStepper();
      if (currentTab === 'cycles') sctSim.showCycles();
    }
    if (currentTab === 'automata') drawAutomata();
    if (engine === 'timed') {
      app.meta = await query('space', [1]);
      const strategy = summary.verdict === 'realizable' ? await query('strategy', []) : null;
      spaceReady = spaceView.load(app.meta, strategy);
      simulator.load(summary);
      if (currentTab === 'simulate') simulator.open();
      await spaceReady;
    }
    if (currentTab === 'code') refreshCode();
  } catch (error) {
    setRunning(false);
    // The summary says that this run has no result, instead of "Running…".
    const noResult = (text) => $('#summary').replaceChildren(h('p', { class: 'muted', id: 'no-result' }, text));
    if (error === 'cancelled') {
      setStatus('Cancelled: the engine was stopped and restarted.', 'cancelled');
      noResult('Cancelled: no result. Run again to solve the spec.');
    } else if (error && error.diagnostics) {
      const n = error.diagnostics.filter((d) => d.severity === 'error').length;
      setStatus(`The spec has ${n} error${n === 1 ? '' : 's'}: see the editor.`, 'error');
      noResult(`No result: the spec has ${n} error${n === 1 ? '' : 's'} (see the editor).`);
      showDiagnostics(error.diagnostics);
    } else {
      setStatus(`Error: ${error?.message ?? error}`, 'error');
      noResult(`No result: ${error?.message ?? error}`);
    }
  } finally {
    app.lastRunMs = performance.now() - started;
  }
}

/** Adds suggested assumptions to the open LTL specification and runs it again. */
function addAssumptions(kind, list) {
  if (app.kind !== kind) return;
  let text = editor.text;
  try {
    for (const a of list) text = addAssumption(text, kind, a);
  } catch (error) {
    return toast(`The assumption cannot be added: ${error.message ?? error}`);
  }
  app.loading = true;
  editor.text = text;
  app.loading = false;
  save();
  showName(text);
  toast(`Added ${list.map((a) => `ASSUME ${a}`).join(' and ')}; running again.`);
  run();
}

$('#run').addEventListener('click', () => run());
$('#cancel').addEventListener('click', () => {
  solver.cancel();
});

// ---- start ------------------------------------------------------------------------------

window.addEventListener('error', (e) => setStatus(`Error: ${e.message}`, 'error'));
window.addEventListener('unhandledrejection', (e) => {
  e.preventDefault();
  if (e.reason !== 'cancelled') setStatus(`Error: ${e.reason?.message ?? e.reason}`, 'error');
});

(async () => {
  app.kind = saved.docs[saved.current] ? saved.current : 'tga';
  setMode(app.kind);
  if (!(await route())) {
    const doc = saved.docs[app.kind];
    if (doc?.text) openSpec(doc.text, doc.name ?? 'spec', app.kind, doc.origin ?? '');
    else openSpec(byId.get('lamp')?.source ?? '', 'lamp', 'tga', 'example/lamp');
  }
  try {
    const { version, targets } = await solver.call('version');
    fillTargets(targets);
    setStatus(`Ready: plcsynth ${version}. Press Run or Ctrl+Enter.`);
    document.body.dataset.engine = 'ready';
    app.interactiveMs = performance.now();
    setTimeout(preload, 500);
    // Offline start on later visits (www/sw.js); not on file:// or where the browser refuses.
    navigator.serviceWorker?.register('sw.js').catch(() => {});
  } catch (error) {
    setStatus(`The engine could not start: ${error}`, 'error');
  }
})();
