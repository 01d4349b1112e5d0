// The playground's three modes in headless Chromium: supervisory control and LTL beside timed
// games, as a user meets them (gallery, run, verdict, drawings, code, share links, autosave,
// errors). `node --test tests/browser/` after `make web`.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { server, browser, useBrowser, newPage, open, shot, editorText, setEditorText, runAndWait, root } from './harness.mjs';

useBrowser();

const example = (path) => readFileSync(join(root, 'examples', path), 'utf8');

/** The text of a download started by `click`. */
async function downloaded(page, click) {
  const [download] = await Promise.all([page.waitForEvent('download'), click()]);
  const path = await download.path();
  return { name: download.suggestedFilename(), text: readFileSync(path, 'utf8') };
}

/** The link the Share button puts into the address bar. */
async function share(page) {
  await page.click('#share');
  await page.waitForFunction(() => location.hash.startsWith('#share/v2/'));
  return page.evaluate(() => location.href);
}

test('gallery: a section per engine, and an SCT example opens in its own mode', async () => {
  const page = await newPage(browser, server.url);
  await page.click('#examples-button');
  const sections = await page.locator('#gallery-list .gallery-section').evaluateAll((s) => s.map((x) => x.dataset.engine));
  assert.deepEqual(sections, ['timed', 'sct', 'ltl']);
  assert.ok((await page.locator('.gallery-section[data-engine=sct] a').count()) >= 10);
  assert.ok((await page.locator('.gallery-section[data-engine=ltl] a').count()) >= 20);
  await shot(page, '40-gallery-three-engines');
  await page.click('.gallery-section[data-engine=sct] a[data-example=tank_preemption]');
  await page.waitForFunction(() => document.body.dataset.mode === 'sct');
  assert.equal(await editorText(page), example('sct/tank_preemption.sct'));
  assert.equal(await page.textContent('#mode-badge'), 'Supervisory control');
  assert.equal(await page.isVisible('[data-tab=space]'), false, 'no state space in SCT mode');
  assert.equal(await page.isVisible('#sct-method'), true);
  assert.equal(await page.isVisible('#max-states'), false);
  // The editor highlights the .sct language: `event` is a heading-styled item keyword.
  assert.ok((await page.locator('.cm-content span', { hasText: /^event$/ }).count()) > 0);
  assert.deepEqual(page.errors, []);
});

test('SCT: run, report, supervisors drawn, framework code with its I/O table, share and reopen', async () => {
  const page = await newPage(browser, `${server.url}#example/tank_preemption`);
  assert.equal(await runAndWait(page), 'realizable');
  assert.match(await page.textContent('#verdict'), /1 supervisor synthesised/);
  assert.match(await page.textContent('#sct-report tr[data-supervisor="Safety.NoOverflow"]'), /closeInlNow/);
  assert.match(await page.textContent('#summary'), /As the example expects \(realizable\)/);
  await shot(page, '41-sct-summary');

  await page.click('[data-tab=automata]');
  await page.waitForSelector('#automata section[data-kind=supervisor] svg');
  assert.match(await page.textContent('#automata section[data-kind=supervisor]'), /⇒ Tank\.closeInlNow|⇒ closeInlNow/);
  assert.ok((await page.locator('#automata section[data-kind=plant] svg').count()) >= 1, 'the plant is drawn');
  assert.ok((await page.locator('#automata svg g.edge.ev-uncontrollable').count()) > 0, 'uncontrollable edges are classed');
  // The module picker narrows the drawings.
  await page.selectOption('#sct-module', 'Tank');
  await page.waitForFunction(() => [...document.querySelectorAll('#automata section.automaton')].every((s) => s.dataset.name.startsWith('Tank.')));
  await shot(page, '42-sct-automata');

  await page.click('[data-tab=code]');
  await page.selectOption('#target', 'st');
  await page.waitForSelector('#code[data-target=st]');
  assert.match(await page.textContent('#code'), /SyRF/);
  assert.equal(await page.isVisible('#io-box'), true);
  assert.match(await page.textContent('#io-table'), /Q_Inlet/);
  const file = await downloaded(page, () => page.click('#download-code'));
  assert.equal(file.name, 'SyRF.st', 'the framework under its own name');
  assert.match(file.text, /FUNCTION_BLOCK|PROGRAM/);
  assert.equal(await page.locator('#target option[value=program]').count(), 0, 'no intermediate program outside timed games');
  await shot(page, '43-sct-code');

  const link = await share(page);
  assert.match(link, /#share\/v2\/sct\/tank_preemption\/st\/[A-Za-z0-9_-]+$/);
  const fresh = await newPage(browser, link);
  assert.equal(await editorText(fresh), example('sct/tank_preemption.sct'));
  assert.equal(await fresh.evaluate(() => document.body.dataset.mode), 'sct');
  assert.match(await fresh.textContent('#spec-name'), /^tank_preemption: /, 'the link carries the name');
  assert.deepEqual([...page.errors, ...fresh.errors], []);
});

test('LTL: counter-strategy, an assumption added from the suggestions, the Mealy machine and code', async () => {
  const page = await newPage(browser, `${server.url}#example/arbiter_same_scan`);
  assert.equal(await page.evaluate(() => document.body.dataset.mode), 'ltl');
  assert.equal(await runAndWait(page), 'unrealizable');
  assert.match(await page.textContent('#counter-tree'), /s0/);
  await page.waitForSelector('#suggestions button.add-assumption');
  await shot(page, '44-ltl-unrealizable');
  await page.click('#suggestions li[data-suggestion="0"] button.add-assumption');
  await page.waitForFunction(() => /\nASSUME /.test(window.plcsynth.getText()));
  await page.waitForSelector('#verdict[data-verdict=realizable]', { timeout: 30000 });
  assert.match(await page.textContent('#summary'), /The example says it should be unrealizable|a controller of/);

  await page.click('[data-tab=automata]');
  assert.equal(await page.textContent('[data-tab=automata]'), 'Mealy machine');
  await page.waitForSelector('#automata section[data-name=machine] svg g.node');
  assert.ok((await page.locator('#automata svg g.edge').count()) >= 2);
  await shot(page, '45-ltl-mealy');

  await page.click('[data-tab=code]');
  await page.selectOption('#target', 'scl');
  await page.waitForSelector('#code[data-target=scl]');
  assert.match(await page.textContent('#code'), /FUNCTION_BLOCK/);
  const file = await downloaded(page, () => page.click('#download-code'));
  assert.equal(file.name, 'FB_arbiter_same_scan.scl', 'the function block under its name');
  await shot(page, '46-ltl-code');
  assert.deepEqual(page.errors, []);
});

test('TLSF: run, and a share link of it reopens in LTL mode', async () => {
  const page = await newPage(browser, `${server.url}#example/delay_line`);
  assert.equal(await runAndWait(page), 'realizable');
  const link = await share(page);
  assert.match(link, /#share\/v2\/tlsf\/delay_line\//);
  const fresh = await newPage(browser, link);
  assert.equal(await editorText(fresh), example('ltl/delay_line.tlsf'));
  assert.equal(await runAndWait(fresh), 'realizable');
  assert.deepEqual([...page.errors, ...fresh.errors], []);
});

test('LTL: the solver menu picks the solver, and the summary names the one that decided', async () => {
  const page = await newPage(browser, `${server.url}#example/mutex`);
  assert.equal(await page.isVisible('#ltl-solver'), true);
  assert.equal(await page.inputValue('#ltl-solver'), 'explicit', 'the reference solver by default');
  for (const solver of ['symbolic', 'antichain', 'bdd', 'gr1', 'explicit']) {
    await page.selectOption('#ltl-solver', solver);
    assert.equal(await runAndWait(page), 'realizable', solver);
    assert.match(await page.textContent('#ltl-solver-used'), new RegExp(`${solver} solver`));
    if (solver === 'gr1') {
      assert.match(await page.textContent('#ltl-summary'), /GR\(1\) game/);
      assert.match(await page.textContent('#circuit-text'), /^latch /, 'the controller as a circuit');
      await shot(page, '47c-ltl-gr1');
    }
  }
  await shot(page, '47b-ltl-solver');
  assert.deepEqual(page.errors, []);
});

test('a located error in each language, and no run result from a broken text', async () => {
  const page = await newPage(browser, server.url);
  const cases = [
    ['sct', 'tank_interlock', 'event a : controllable;\nplant P { alphabet a, nope; state A { } }\n', 2],
    ['ltl', 'arbiter', 'INPUT req\nOUTPUT grant\nALWAYS (req -> \n', 3],
    ['tlsf', 'delay_line', 'INFO {\n  TITLE: "x"\n}\nMAIN {\n  INPUTS { r; }\n  OUTPUTS { g; }\n  GUARANTEES { G (r <-> ; }\n}\n', 7],
    ['tga', 'lamp', 'plant {\n  automaton a {\n    nodes x y;\n  }\n}\n', 3],
  ];
  for (const [kind, id, broken, line] of cases) {
    await page.evaluate((id) => (location.hash = `#example/${id}`), id);
    await page.waitForFunction((kind) => window.plcsynth.kind === kind, kind);
    await setEditorText(page, broken);
    await page.waitForSelector(`#diagnostics .diag[data-line="${line}"]`, { timeout: 10000 });
    assert.match(await page.textContent('#diagnostics'), new RegExp(`error line ${line}:\\d+`), kind);
    assert.ok((await page.locator('.cm-lintRange-error').count()) > 0, `${kind}: a squiggle`);
    await shot(page, `47-error-${kind}`);
    await page.click('#run');
    await page.waitForSelector('#no-result');
    assert.match(await page.textContent('#status'), /error/);
  }
  assert.deepEqual(page.errors, []);
});

test('New: a document of each kind that runs; autosave per kind with an edit kept, and the tabs follow the arrow keys', async () => {
  const page = await newPage(browser, server.url);
  for (const [kind, verdict] of [['ltl', 'realizable'], ['tlsf', 'realizable'], ['sct', 'realizable'], ['tga', 'realizable']]) {
    await page.click('#new-button');
    await page.click(`#new-list [data-new=${kind}]`);
    await page.waitForFunction((kind) => window.plcsynth.kind === kind, kind);
    assert.equal(await runAndWait(page), verdict, kind);
  }
  // An edit of the new timed game survives opening an SCT example and a reload.
  await setEditorText(page, `${await editorText(page)}\n// my own change\n`);
  await page.waitForTimeout(400);
  await page.evaluate(() => (location.hash = '#example/crane'));
  await page.waitForFunction(() => window.plcsynth.kind === 'sct');
  await page.reload();
  await page.waitForSelector('body[data-engine=ready]');
  assert.equal(await editorText(page), example('sct/crane.sct'), 'the link opens its example');
  // Opening a timed example offers the earlier timed edit back.
  await page.evaluate(() => (location.hash = '#example/robot_arm'));
  await page.waitForSelector('#toast .toast-action');
  assert.match(await page.textContent('#toast'), /was kept/);
  await page.click('#toast .toast-action');
  await page.waitForFunction(() => window.plcsynth.getText().includes('// my own change'));

  // An edit of an example keeps the link; a reload reopens the edit, marked edited.
  await page.evaluate(() => (location.hash = '#example/heating_tank'));
  await page.waitForFunction(() => window.plcsynth.kind === 'sct' && window.plcsynth.name === 'heating_tank');
  await setEditorText(page, `${example('sct/heating_tank.sct')}// mine\n`);
  await page.waitForTimeout(400);
  assert.equal(await page.evaluate(() => location.hash), '#example/heating_tank');
  await page.reload();
  await page.waitForSelector('body[data-engine=ready]');
  assert.match(await editorText(page), /\/\/ mine\n$/);
  assert.match(await page.textContent('#spec-name'), /heating_tank \(edited\)/);

  // Tabs: Right moves to the next visible tab, End to the last.
  await page.click('[data-tab=summary]');
  await page.keyboard.press('ArrowRight');
  assert.equal(await page.getAttribute('[data-tab=automata]', 'aria-selected'), 'true');
  await page.keyboard.press('End');
  assert.equal(await page.getAttribute('[data-tab=code]', 'aria-selected'), 'true');
  assert.equal(await page.evaluate(() => document.activeElement.dataset.tab), 'code');
  assert.deepEqual(page.errors, []);
});

test('SCT stepper: fire events until a prohibited event is disabled, step back; a runtime cycle resets a denied output', async () => {
  const page = await newPage(browser, `${server.url}#example/tank_interlock`);
  await page.click('[data-tab=step]');
  assert.match(await page.textContent('#sct-stepper'), /Run the project first/);
  await page.click('[data-tab=summary]');
  assert.equal(await runAndWait(page), 'realizable');
  await page.click('[data-tab=step]');
  await page.waitForSelector('#step-events');
  // Figure 5.7: the interlock prohibits opening the inlet; closing it is enabled.
  assert.equal(await page.getAttribute('[data-event="Tank.openInlet"]', 'data-status'), 'disabled');
  assert.equal(await page.isDisabled('[data-event="Tank.openInlet"]'), true);
  assert.match(await page.getAttribute('[data-event="Tank.openInlet"]', 'title'), /disabled by Safety\.NoOverflow/);
  await page.click('[data-event="Tank.closeInlet"]');
  await page.waitForSelector('#step-trace li');
  assert.equal(await page.locator('#step-trace li').count(), 1);
  await shot(page, '48-sct-stepper');
  await page.click('#step-back');
  await page.waitForSelector('p#step-trace');

  // A runtime cycle in which the framework denies the controller's event and resets its output:
  // the controller opens the inlet, the interlock denies `openInlet` (`reset on denial`).
  await page.click('[data-tab=cycles]');
  await page.waitForSelector('#cycle-run');
  await page.check('input[data-into=controller][data-signal=Q_Inlet]');
  await page.click('#cycle-run');
  await page.waitForSelector('#cycle-table tr[data-cycle="1"]');
  assert.match(await page.textContent('#cycle-table tr[data-cycle="1"]'), /✗ Tank\.openInlet denied by Safety\.NoOverflow/);
  assert.equal(await page.getAttribute('#cycle-table tr[data-cycle="1"] [data-output=Q_Inlet]', 'data-reset'), 'true');
  assert.match(await page.textContent('#cycle-table tr[data-cycle="1"] [data-output=Q_Inlet]'), /Q_Inlet = 0 \(the controller wrote 1/);
  await shot(page, '50a-sct-cycle-denied');

  // Preemption: open, the alarm, and the supervisor enforces closing.
  await page.evaluate(() => (location.hash = '#example/tank_preemption'));
  await page.waitForFunction(() => window.plcsynth.name === 'tank_preemption');
  await page.click('[data-tab=summary]');
  assert.equal(await runAndWait(page), 'realizable');
  await page.click('[data-tab=step]');
  await page.click('[data-event="Tank.openInlet"]');
  await page.waitForSelector('[data-event="Tank.levelAlarm"][data-status=enabled]');
  await page.click('[data-event="Tank.levelAlarm"]');
  await page.waitForSelector('[data-event="Tank.closeInlNow"][data-status=enforced]');
  assert.match(await page.textContent('#step-plants'), /Tank\.Inlet\s*C/);
  await page.click('[data-event="Tank.closeInlNow"]');
  await page.waitForFunction(() => /Tank\.Inlet\s*A/.test(document.querySelector('#step-plants').textContent));
  await shot(page, '49-sct-stepper-enforced');

  // The cycle simulator on the generated framework: the controller opens, the alarm comes,
  // the framework enforces closing; a controller that still writes TRUE is overridden.
  await page.click('[data-tab=cycles]');
  await page.waitForSelector('#cycle-run');
  await page.check('input[data-into=controller][data-signal=Q_Inlet]');
  await page.click('#cycle-run');
  await page.waitForSelector('#cycle-table tr[data-cycle="1"]');
  assert.match(await page.textContent('#cycle-table tr[data-cycle="1"]'), /✓ Tank\.openInlet accepted/);
  await page.check('input[data-into=inputs][data-signal=I_LevelHigh]');
  await page.click('#cycle-run');
  await page.waitForSelector('#cycle-table tr[data-cycle="2"]');
  const second = await page.textContent('#cycle-table tr[data-cycle="2"]');
  assert.match(second, /⇒ Tank\.closeInlNow enforced/);
  assert.equal(await page.getAttribute('#cycle-table tr[data-cycle="2"] [data-output=Q_Inlet]', 'data-reset'), 'true');
  await shot(page, '50-sct-cycles');
  await page.click('#cycle-back');
  await page.waitForFunction(() => !document.querySelector('#cycle-table tr[data-cycle="2"]'));
  assert.deepEqual(page.errors, []);
});

test('a damaged share link of any form says what is wrong, never "Failed to fetch"', async () => {
  const page = await newPage(browser, `${server.url}#example/delay_line`);
  const good = await share(page);
  const data = good.split('/').at(-1);
  const broken = [
    good.slice(0, -7), // cut off
    good.replace(/\/[A-Za-z0-9_-]+$/, '/!!!'), // not base64url
    good.replace('/v2/tlsf/', '/v2/xyz/'), // an unknown kind
    good.replace('/v2/', '/v9/'), // an unknown version
    `${server.url}#share/v2/tlsf/a%E0%A4%A/st/${data}`, // a bad percent escape
    `${server.url}#share/v2/tlsf`, // no data at all
    `${server.url}#share/v1/st/${data.slice(0, 20)}`,
  ];
  // The first opens a fresh page (the start reads the link); the others follow in that page as
  // a pasted link would (a hash change reads it with the same code), each with the toast cleared.
  const fresh = await newPage(browser, broken[0]);
  for (const [i, link] of broken.entries()) {
    if (i > 0) {
      await fresh.evaluate((hash) => {
        const toast = document.querySelector('#toast');
        toast.hidden = true;
        toast.replaceChildren();
        location.hash = hash;
      }, link.slice(link.indexOf('#')));
    }
    await fresh.waitForSelector('#toast:not([hidden])');
    const text = await fresh.textContent('#toast');
    assert.match(text, /This share link cannot be read: /, link);
    assert.doesNotMatch(text, /Failed to fetch/i, link);
    assert.deepEqual(fresh.errors, [], link);
  }
  await fresh.context().close();
});

test('completion offers the names the document declares, in each language', async () => {
  const page = await newPage(browser, server.url);
  for (const [id, prefix, name] of [['tank_preemption', 'closeI', 'closeInlNow'], ['arbiter', 'gra', 'grant1'], ['delay_line', 'GUAR', 'GUARANTEES'], ['lamp', 'turn_o', 'turn_off']]) {
    await page.evaluate((id) => (location.hash = `#example/${id}`), id);
    await page.waitForFunction((id) => window.plcsynth.name === id, id);
    await page.click('.cm-content');
    await page.keyboard.press('Control+End');
    await page.keyboard.insertText(`\n${prefix}`);
    await page.keyboard.press('Control+Space');
    await page.waitForSelector('.cm-tooltip-autocomplete');
    const offered = await page.locator('.cm-tooltip-autocomplete li').allTextContents();
    assert.ok(offered.some((o) => o.startsWith(name)), `${id}: ${name} not in ${offered.join(', ')}`);
    await page.keyboard.press('Escape');
  }
  await shot(page, '51-completion');
  assert.deepEqual(page.errors, []);
});
