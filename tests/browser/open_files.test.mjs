// Opening files in headless Chromium: the Open file… picker and files dropped on the page; a
// Supremica module or libFAUDES generators imported as an editable .sct project that runs; a
// malformed module refused with a located diagnostic and the open document kept.
// `node --test tests/browser/` after `make web`.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { server, browser, useBrowser, newPage, shot, editorText, setEditorText, runAndWait, root } from './harness.mjs';

useBrowser();

const fixture = (name) => readFileSync(join(root, 'tests', 'fixtures', 'wmod', name));
const example = (path) => readFileSync(join(root, 'examples', path), 'utf8');

/** libFAUDES generators, every state marked: a machine, and a buffer after it. */
const MACHINE_GEN = `<Generator> "M1"
<Alphabet> load +C+ finish </Alphabet>
<States> idle working </States>
<TransRel>
idle load working
working finish idle
</TransRel>
<InitStates> idle </InitStates>
<MarkedStates> idle working </MarkedStates>
</Generator>
`;
const TAKER_GEN = `<Generator> "Taker"
<Alphabet> take +C+ </Alphabet>
<States> ready </States>
<TransRel> ready take ready </TransRel>
<InitStates> ready </InitStates>
<MarkedStates> ready </MarkedStates>
</Generator>
`;
const BUFFER_GEN = `<Generator> "Buffer"
<Alphabet> finish take +C+ </Alphabet>
<States> empty full </States>
<TransRel>
empty finish full
full take empty
</TransRel>
<InitStates> empty </InitStates>
<MarkedStates> empty full </MarkedStates>
</Generator>
`;

/** A module whose `<EventDecl>` is never closed: roxmltree stops at line 5, column 1. */
const BAD_WMOD = `<?xml version="1.0"?>
<Module xmlns="http://waters.sourceforge.net/xsd/module" Name="m">
<EventDeclList>
<EventDecl Kind="CONTROLLABLE" Name="a">
</EventDeclList>
</Module>
`;

const file = (name, content) => ({ name, mimeType: 'application/octet-stream', buffer: Buffer.from(content) });

/** Drops `files` on `selector` as the browser does: dragenter, dragover, drop with a DataTransfer. */
async function drop(page, files, selector = '.cm-content') {
  await page.evaluate(
    ({ files, selector }) => {
      const data = new DataTransfer();
      for (const f of files) data.items.add(new File([new Uint8Array(f.bytes)], f.name));
      const target = document.querySelector(selector);
      for (const type of ['dragenter', 'dragover', 'drop']) {
        target.dispatchEvent(new DragEvent(type, { dataTransfer: data, bubbles: true, cancelable: true }));
      }
    },
    { files: files.map((f) => ({ name: f.name, bytes: [...f.buffer] })), selector },
  );
}

const status = (page) => page.textContent('#status');

test('Open file: a Supremica module through the picker becomes an editable .sct project that synthesises, an edit kept', async () => {
  const page = await newPage(browser, server.url);
  // An edit of a .sct document of the user's own: opening the module must not lose it.
  await page.click('#new-button');
  await page.click('#new-list [data-new=sct]');
  await page.waitForFunction(() => window.plcsynth.kind === 'sct');
  await setEditorText(page, `${await editorText(page)}\n// my own change\n`);
  await page.waitForTimeout(400);
  await page.setInputFiles('#open-file', join(root, 'tests', 'fixtures', 'wmod', 'machine_buffer.wmod'));
  await page.waitForFunction(() => window.plcsynth.name === 'machine_buffer.sct');
  const text = await editorText(page);
  assert.match(text, /^\/\/ Imported by the plcsynth playground from `machine_buffer\.wmod`\./);
  assert.match(text, /plant Machine \{\n {2}alphabet load, finish;\n {2}state idle initial \{ load -> working; \}/);
  assert.match(text, /spec Buffer \{\n {2}state empty initial \{ finish -> full; forbid take; \}/);
  assert.equal(await page.evaluate(() => document.body.dataset.mode), 'sct');
  assert.equal(await page.textContent('#spec-name'), 'machine_buffer.sct');
  assert.match(await status(page), /Imported machine_buffer\.wmod as the \.sct project machine_buffer\.sct/);
  // The earlier edit is offered back, and comes back on request; then the module once more.
  assert.match(await page.textContent('#toast'), /was kept/);
  await page.click('#toast .toast-action');
  await page.waitForFunction(() => window.plcsynth.getText().includes('// my own change'));
  await page.setInputFiles('#open-file', join(root, 'tests', 'fixtures', 'wmod', 'machine_buffer.wmod'));
  await page.waitForFunction(() => window.plcsynth.name === 'machine_buffer.sct');
  // The converted text checks clean in the editor, and synthesis finds the buffer's supervisor.
  await page.waitForSelector('#diagnostics .ok');
  assert.equal(await runAndWait(page), 'realizable');
  assert.match(await page.textContent('#verdict'), /1 supervisor synthesised/);
  assert.ok(await page.locator('#sct-report tr[data-supervisor="Buffer"]').count(), 'a supervisor for Buffer');
  await shot(page, '70-open-wmod-imported');
  assert.deepEqual(page.errors, []);
});

test('Open file: a dropped module with unmarked states is refused, located; Ignore marking imports it', async () => {
  const page = await newPage(browser, `${server.url}#example/lamp`);
  const lamp = await editorText(page);
  await drop(page, [file('small_factory.wmod', fixture('small_factory.wmod'))]);
  await page.waitForSelector('#import-errors');
  // Located in the module (windows-1252, as Supremica writes it), with its source line.
  const first = page.locator('#diagnostics .import-diag').first();
  assert.equal(await first.getAttribute('data-file'), 'small_factory.wmod');
  assert.equal(await first.getAttribute('data-line'), '43');
  assert.equal(await first.getAttribute('data-column'), '19');
  assert.match(await first.textContent(), /error small_factory\.wmod line 43:19 {2}state `W` of `M1` is not marked/);
  assert.match(await first.locator('pre').textContent(), /^43 \| <SimpleNode Name="W">\n {3}\| {19}\^\n {3}= note: .*`Ignore marking` reads every state as marked$/);
  assert.match(await status(page), /small_factory\.wmod was not imported: \d+ errors? .*The open document is unchanged\./);
  // Nothing changed: the timed game is still open, and the drop did not paste the file into it.
  assert.equal(await editorText(page), lamp);
  assert.equal(await page.evaluate(() => window.plcsynth.kind), 'tga');
  await shot(page, '71-open-wmod-unmarked-located');
  await page.click('#import-ignore-marking-again');
  await page.waitForFunction(() => window.plcsynth.name === 'small_factory.sct');
  const text = await editorText(page);
  assert.match(text, /\/\/ Marking ignored \(Ignore marking\): every state is read as marked\./);
  assert.match(text, /spec Repair \{/);
  assert.equal(await runAndWait(page), 'realizable');
  assert.match(await page.textContent('#verdict'), /2 supervisors synthesised/);
  await shot(page, '72-open-wmod-marking-ignored-run');
  assert.deepEqual(page.errors, []);
});

test('Open file: a dropped module opens as .sct too, and a dropped .ltl or .tga opens in its own mode', async () => {
  const page = await newPage(browser, `${server.url}#example/lamp`);
  await drop(page, [file('machine_buffer.wmod', fixture('machine_buffer.wmod'))], 'main');
  await page.waitForFunction(() => window.plcsynth.name === 'machine_buffer.sct');
  assert.match(await editorText(page), /spec Buffer \{/);
  assert.doesNotMatch(await editorText(page), /<Module/, 'the module is converted, not pasted');
  assert.equal(await runAndWait(page), 'realizable');
  // The kind follows the extension.
  await drop(page, [file('mine.ltl', example('ltl/arbiter.ltl'))]);
  await page.waitForFunction(() => window.plcsynth.kind === 'ltl');
  assert.equal(await editorText(page), example('ltl/arbiter.ltl'));
  assert.equal(await page.textContent('#spec-name'), 'mine.ltl');
  assert.equal(await page.textContent('#mode-badge'), 'LTL synthesis');
  await drop(page, [file('my_lamp.tga', example('timed/lamp.tga'))]);
  await page.waitForFunction(() => window.plcsynth.kind === 'tga' && window.plcsynth.name === 'my_lamp.tga');
  assert.equal(await runAndWait(page), 'realizable');
  // An unknown extension, and two files that are not generators: a readable refusal, no change.
  await drop(page, [file('notes.txt', 'hello')]);
  await page.waitForFunction(() => /“notes\.txt” is not a file the playground opens/.test(document.querySelector('#status').textContent));
  assert.match(await status(page), /\.tga \(timed game\), \.sct \(supervisory control\), \.ltl or \.tlsf \(LTL\)/);
  await page.setInputFiles('#open-file', [file('a.tga', example('timed/lamp.tga')), file('b.sct', 'x')]);
  await page.waitForFunction(() => /Open one file at a time/.test(document.querySelector('#status').textContent));
  assert.equal(await page.evaluate(() => window.plcsynth.name), 'my_lamp.tga');
  assert.deepEqual(page.errors, []);
});

test('Open file: libFAUDES generators through the picker and by drop, each a plant or a specification', async () => {
  const page = await newPage(browser, server.url);
  await page.setInputFiles('#open-file', [file('machine.gen', MACHINE_GEN), file('taker.gen', TAKER_GEN), file('buffer_spec.gen', BUFFER_GEN)]);
  await page.waitForSelector('#import-menu[open]');
  // A name that says `spec` is preselected as a specification; the others are plants.
  const roles = await page.locator('#import-roles select').evaluateAll((s) => s.map((x) => x.value));
  assert.deepEqual(roles, ['plant', 'plant', 'spec']);
  await shot(page, '73-open-gen-roles');
  await page.click('#import-go');
  await page.waitForFunction(() => window.plcsynth.name === 'machine.sct');
  let text = await editorText(page);
  assert.match(text, /^\/\/ Imported by the plcsynth playground from `machine\.gen`, `taker\.gen`, `buffer_spec\.gen`\./);
  assert.match(text, /plant machine \{/);
  assert.match(text, /spec buffer_spec \{\n {2}state empty initial \{ finish -> full; forbid take; \}/);
  assert.equal(await runAndWait(page), 'realizable');
  assert.ok(await page.locator('#sct-report tr[data-supervisor="buffer_spec"]').count(), 'a supervisor for buffer_spec');
  await shot(page, '74-open-gen-run');

  // Dropped: the same dialog; here the user says which one is the specification.
  await drop(page, [file('m.gen', MACHINE_GEN), file('t.gen', TAKER_GEN), file('b.gen', BUFFER_GEN)]);
  await page.waitForSelector('#import-menu[open]');
  await page.selectOption('#import-roles select[data-role="2"]', 'spec');
  await page.click('#import-go');
  await page.waitForFunction(() => window.plcsynth.name === 'm.sct');
  text = await editorText(page);
  assert.match(text, /plant m \{/);
  assert.match(text, /spec b \{/);
  assert.equal(await runAndWait(page), 'realizable');
  assert.deepEqual(page.errors, []);
});

test('Open file: a malformed module gets a located diagnostic, and the open document stays', async () => {
  const page = await newPage(browser, `${server.url}#example/tank_preemption`);
  const before = await editorText(page);
  await page.setInputFiles('#open-file', file('bad.wmod', BAD_WMOD));
  await page.waitForSelector('#import-errors');
  const d = page.locator('#diagnostics .import-diag').first();
  assert.equal(await d.getAttribute('data-line'), '5');
  assert.equal(await d.getAttribute('data-column'), '1');
  assert.match(await d.textContent(), /error bad\.wmod line 5:1 {2}malformed XML/);
  assert.match(await d.locator('pre').textContent(), /^5 \| <\/EventDeclList>\n {2}\| \^/);
  assert.equal(await page.locator('#import-ignore-marking-again').count(), 0, 'marking is not the problem');
  assert.match(await status(page), /bad\.wmod was not imported: 1 error/);
  assert.equal(await editorText(page), before);
  assert.equal(await page.evaluate(() => window.plcsynth.name), 'tank_preemption');
  await shot(page, '75-open-wmod-malformed');
  // A generator's mistake is located the same way, in its own file.
  await page.setInputFiles('#open-file', file('broken.gen', MACHINE_GEN.replace('working finish idle', 'working finish nowhere')));
  await page.waitForSelector('#import-menu[open]');
  await page.click('#import-go');
  await page.waitForFunction(() => document.querySelector('#diagnostics .import-diag')?.dataset.file === 'broken.gen');
  assert.equal(await page.locator('#diagnostics .import-diag').first().getAttribute('data-line'), '6');
  assert.equal(await editorText(page), before);
  assert.deepEqual(page.errors, []);
});
