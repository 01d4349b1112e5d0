// The playground in headless Chromium: `node --test tests/browser/` (after `make web`).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { server, browser, useBrowser, startServer, newPage, open, shot, editorText, setEditorText, runAndWait, readExample, record } from './harness.mjs';

useBrowser();

const number = async (page, selector) => Number((await page.textContent(selector)).replace(/[^0-9]/g, ''));

test('the lamp example runs: verdict, counts, automata, state space and zone', async () => {
  const page = await newPage(browser, null);
  const foreign = [];
  page.on('request', (r) => {
    if (!r.url().startsWith(server.url) && !/^(data|blob):/.test(r.url())) foreign.push(r.url());
  });
  await open(page, `${server.url}#example/lamp`);
  assert.equal(await editorText(page), readExample('lamp'));
  await shot(page, '01-lamp-editor');
  // Explore all: the whole game, so that the State space tab has lost states to show.
  await page.check('#exhaustive');
  assert.equal(await runAndWait(page), 'realizable');
  const visited = await number(page, '#stat-visited');
  const winning = await number(page, '#stat-winning');
  const removed = await number(page, '#stat-removed');
  assert.ok(visited > 0 && winning > 0 && winning <= visited, `visited ${visited}, winning ${winning}`);
  assert.match(await page.textContent('#status'), new RegExp(`realizable: ${visited} states visited, ${winning} winning, ${removed} removed`));
  // The thesis's lamp declares no scan time: the verdict says it assumes zero time.
  assert.match(await page.textContent('#zero-time-note'), /reacts in zero time/);
  await shot(page, '02-lamp-summary');

  await page.click('[data-tab=automata]');
  await page.waitForSelector('#automata section[data-name=button] svg');
  for (const cls of ['edge-request', 'edge-reaction', 'edge-plan']) {
    assert.ok((await page.locator(`#automata svg g.edge.${cls}`).count()) > 0, `no ${cls} edge drawn`);
  }
  assert.match(await page.textContent('#automata section[data-name=button]'), /c in \[0,1\)/);
  await shot(page, '03-lamp-automata');

  await page.click('[data-tab=space]');
  await page.waitForSelector('#space-graph svg g.state');
  assert.equal(await page.locator('#space-graph svg g.state').count(), visited, 'every state is drawn');
  assert.equal(await page.locator('#space-graph svg g.state.removed').count(), removed);
  assert.equal(await page.locator('#state-list li[data-id]').count(), visited);
  // The strategy: chosen requests are highlighted; the initial state waits for the button.
  assert.ok((await page.locator('#space-graph svg g.edge.chosen').count()) >= 2, 'the chosen requests are drawn');
  await page.click('#state-list li[data-id="0"]');
  await page.waitForFunction(() => /strategy: wait/.test(document.querySelector('#selected-bar').textContent));
  const chooser = page.locator('#space-graph svg g.state.winning').filter({ hasText: 'off, pressing' }).first();
  await chooser.click();
  await page.waitForFunction(() => /strategy: \?turn_on → s\d+/.test(document.querySelector('#selected-bar').textContent));
  // A removed state with a clock constraint: select it in the graph.
  const removedWithClock = page.locator('#state-list li.removed', { hasText: 'button.c' }).first();
  const id = Number(await removedWithClock.getAttribute('data-id'));
  await page.click(`#space-graph svg #st-${id}`);
  await page.waitForSelector(`#space-graph svg #st-${id}.selected`);
  // The bar is written after the graph marks the state: wait for it, then check it.
  await page.waitForFunction((id) => document.querySelector('#selected-bar').textContent.includes(`s${id} removed`), id);
  assert.match(await page.textContent('#selected-bar'), new RegExp(`s${id} removed — \\S`));
  await page.check('#fit-graph');
  const fitted = await page.$eval('#space-graph svg', (svg) => svg.getBoundingClientRect().width <= svg.parentElement.clientWidth + 1);
  assert.ok(fitted, 'fit width scales the graph into its box');
  await shot(page, '04-lamp-space');

  await page.click('#selected-bar a');
  await page.waitForSelector('#zone-title');
  assert.match(await page.textContent('#zone-title'), new RegExp(`State s${id} .* removed`));
  assert.match(await page.textContent('#zone-text'), /button\.c/);
  assert.ok((await page.locator('#zone-constraints li').count()) > 0);
  // The lamp has one clock, on both axes: its zone is drawn on the diagonal, as a segment.
  assert.equal(await page.locator('#zone svg.zone-plot line.zone-segment').count(), 1, 'the zone is drawn');
  await shot(page, '05-lamp-zone');
  // A winning state has no removal reason, and nothing stands in for it.
  await page.click('[data-tab=space]');
  await page.click('#state-list li[data-id="0"]');
  await page.waitForFunction(() => /s0 winning/.test(document.querySelector('#selected-bar').textContent));
  await page.click('#selected-bar a');
  await page.waitForFunction(() => /State s0 .* winning/.test(document.querySelector('#zone-title')?.textContent ?? ''));
  assert.doesNotMatch(await page.textContent('#zone'), /null|undefined/);

  // Code: Structured Text by default; Download gives `lamp.st` with the same text.
  await page.click('[data-tab=code]');
  assert.equal(await page.inputValue('#target'), 'st');
  await page.waitForFunction(() => document.querySelector('#code').textContent.includes('FUNCTION_BLOCK'));
  const st = await page.textContent('#code');
  assert.match(st, /FUNCTION_BLOCK lamp\b/);
  assert.match(st, /turn_on/);
  const [download] = await Promise.all([page.waitForEvent('download'), page.click('#download-code')]);
  assert.equal(download.suggestedFilename(), 'lamp.st');
  assert.equal(readFileSync(await download.path(), 'utf8'), st);
  await shot(page, '06-lamp-code-st');
  // The I/O table: the lamp's two signals, named after the messages, with CSV and SDF downloads.
  await page.waitForSelector('#io-box:not([hidden])');
  const rows = await page.$$eval('#io-table tbody tr', (trs) => trs.map((tr) => [...tr.cells].map((c) => c.textContent)));
  assert.deepEqual(rows, [
    ['%IX124.0', 'BOOL', 'press', 'input', 'press, NOT release'],
    ['%QX125.6', 'BOOL', 'turn_on', 'output', 'turn_on sets, turn_off resets'],
  ]);
  const [csv] = await Promise.all([page.waitForEvent('download'), page.click('#download-io-csv')]);
  assert.equal(csv.suggestedFilename(), 'lamp_io.csv');
  assert.match(readFileSync(await csv.path(), 'utf8'), /^address,type,symbol,direction,meaning\r\n%IX124\.0,BOOL,press,input,/);
  const [sdf] = await Promise.all([page.waitForEvent('download'), page.click('#download-io-sdf')]);
  assert.equal(sdf.suggestedFilename(), 'lamp_tags.sdf');
  assert.match(readFileSync(await sdf.path(), 'utf8'), /^"press","I 124\.0","BOOL",/);
  await shot(page, '06b-lamp-io-table');
  // Every target of the menu, each under its own file name and extension.
  const ids = await page.$$eval('#target optgroup[label=Controller] option', (os) => os.map((o) => o.value));
  assert.deepEqual(ids, ['program', 'st', 'twincat', 'codesys', 'scl', 'scl-1500', 'il', 'stl', 'plcopen', 'abb']);
  for (const [target, file, marker] of [
    ['program', 'lamp.txt', /DO \(turn_on\)/],
    ['codesys', 'lamp.st', /GVL_IO\.turn_on := ctrl\.turn_on/],
    ['scl', 'lamp.scl', /"turn_on" := ctrl\.turn_on/],
    ['scl-1500', 'lamp.scl', /S7_Optimized_Access/],
    ['il', 'lamp.il', /CAL ctrl/],
    ['stl', 'lamp.awl', /turn_on/],
    ['plcopen', 'lamp.xml', /<project/],
    ['space', 'lamp.states.txt', /^s0/],
  ]) {
    await page.selectOption('#target', target);
    await page.waitForSelector(`#code[data-target="${target}"][data-complete=true]`);
    assert.match(await page.textContent('#code'), marker);
    // One more click if no download comes: headless Chromium has now and then let this click pass
    // without a download (twice in about ten full runs, both times on the eighth download from
    // the page; its download limiter is the suspect, not proven). Two misses fail the test.
    const clickForDownload = () => Promise.all([page.waitForEvent('download'), page.click('#download-code')]);
    const [d] = await clickForDownload().catch(clickForDownload).catch(async (error) => {
      // Say what the page showed when no download came.
      const state = await page.evaluate(() => ({ toast: document.querySelector('#toast').textContent, code: window.plcsynth.code.length, files: window.plcsynth.files.map((f) => f.name), shown: document.querySelector('#code').dataset.target }));
      throw new Error(`no download for ${target}: ${JSON.stringify(state)}: ${error.message}`);
    });
    assert.equal(d.suggestedFilename(), file);
  }
  // TwinCAT: three files, one button (and one download) each.
  await page.selectOption('#target', 'twincat');
  await page.waitForSelector('#code-files:not([hidden]) button.file');
  const names = await page.$$eval('#code-files button.file', (bs) => bs.map((b) => b.textContent));
  assert.deepEqual(names, ['lamp.TcPOU', 'lamp_main.TcPOU', 'GVL_IO.TcGVL']);
  for (const name of names) {
    const [d] = await Promise.all([page.waitForEvent('download'), page.click(`#code-files button.file:text-is("${name}")`)]);
    assert.equal(d.suggestedFilename(), name);
    assert.match(readFileSync(await d.path(), 'utf8'), /^<\?xml[^]*<TcPlcObject Version="1\.1\.0\.1">/);
  }
  await shot(page, '06c-lamp-code-twincat');
  // The CODESYS I/O mapping list: offered for codesys and abb (whose Automation Builder takes the
  // same list), not for the other targets; its Variable column names what the code reads.
  assert.equal(await page.isVisible('#download-io-codesys'), false, 'no mapping list for twincat');
  // Both name the variable by its list (the abb file's configuration globals are `GVL_IO` too).
  for (const [target, variable] of [
    ['codesys', 'GVL_IO.press'],
    ['abb', 'GVL_IO.press'],
  ]) {
    await page.selectOption('#target', target);
    await page.waitForSelector(`#code[data-target="${target}"][data-complete=true]`);
    await page.waitForSelector('#download-io-codesys:not([hidden])');
    const [mapping] = await Promise.all([page.waitForEvent('download'), page.click('#download-io-codesys')]);
    assert.equal(mapping.suggestedFilename(), 'lamp_mapping.csv');
    const text = readFileSync(await mapping.path(), 'utf8');
    assert.match(text, /^Variable;Address;Type;Direction;Description\r\n/);
    assert.ok(text.split('\r\n').some((line) => line.startsWith(`${variable};%IX124.0;BOOL;input;`)), `${target}: ${text}`);
  }
  await shot(page, '06d-lamp-io-codesys');
  await page.selectOption('#target', 'st');
  await page.waitForSelector('#code[data-target="st"][data-complete=true]');
  assert.equal(await page.isVisible('#download-io-codesys'), false, 'no mapping list for st');
  assert.deepEqual(foreign, [], 'no request leaves the origin');
  assert.deepEqual(page.errors, []);
  await page.context().close();
});

test('a spec with a scan time shows the verdict on the PLC, and a too slow scan the counter-play', async () => {
  const page = await newPage(browser, `${server.url}#example/lamp_scan`);
  assert.equal(await runAndWait(page), 'realizable');
  await page.waitForSelector('#scan-verdict');
  assert.equal(await page.getAttribute('#scan-verdict', 'data-verdict'), 'realizable');
  assert.match(await page.textContent('#scan-verdict'), /Implementable at 10 ms/);
  // How slow the PLC may be: the bound search's neighbours (a change read a scan late and
  // switched within the next one: 2T < 30 ms).
  assert.match(await page.textContent('#scan-bound'), /implementable at 14 ms, not at 15 ms/);
  // The code follows the scan game's strategy: one read, one decision, one write per scan.
  assert.match(await page.textContent('#scan-code-from'), /Code from the scan strategy: \d+ nodes, one decision per scan/);
  await shot(page, '07a-scan-implementable');
  // Its code was run against the plant at 10 ms before it is shown.
  await page.click('[data-tab=code]');
  await page.selectOption('#target', 'stl');
  await page.waitForSelector('#code[data-target="stl"][data-complete=true]');
  assert.equal(await page.getAttribute('#code-note', 'data-realtime'), 'held');
  assert.match(await page.textContent('#code-note'), /Generated from the program of the scan game’s strategy: one read, one decision, one write per scan/);
  assert.match(await page.textContent('#code-note'), /Checked at 10 ms: 20 runs of 2[ ,.]?000 scans/);
  assert.match(await page.textContent('#code'), /ORGANIZATION_BLOCK/);
  await shot(page, '07d-scan-strategy-code');
  await page.click('[data-tab=summary]');
  // At 20 ms the button may settle before the lamp follows: the scan game's counter-play.
  await setEditorText(page, readExample('lamp_scan').replace('scan 10 ms;', 'scan 20 ms;'));
  assert.equal(await runAndWait(page), 'realizable');
  await page.waitForFunction(() => document.querySelector('#scan-verdict')?.dataset.verdict === 'unrealizable');
  assert.match(await page.textContent('#scan-verdict'), /Not implementable at 20 ms/);
  assert.equal(await page.getAttribute('#scan-bound', 'data-works'), '14');
  assert.match(await page.textContent('#scan-explanation'), /plc\.read/);
  assert.match(await page.textContent('#scan-explanation'), /✗/);
  await shot(page, '07b-scan-not-implementable');
  assert.deepEqual(page.errors, []);
  await page.context().close();
});

test('code that fails a real-time run at the declared scan time is not offered', async () => {
  // The watchdog (tests/fixtures) is implementable at 250 ms, but its scan strategy decides by
  // how long it has waited, which no input shows: its code follows the zero-time strategy with
  // the scans' latency and sends a request the plant refuses. The page shows the failing run,
  // not the code.
  const page = await newPage(browser, `${server.url}#example/gripper_guard`);
  const watchdog = readFileSync(new URL('../fixtures/timed/watchdog.tga', import.meta.url), 'utf8');
  await setEditorText(page, `scan 250 ms;\n${watchdog}`);
  assert.equal(await runAndWait(page), 'realizable');
  await page.waitForFunction(() => document.querySelector('#scan-verdict')?.dataset.verdict === 'realizable');
  assert.match(await page.textContent('#scan-code-from'), /Code from the zero-time strategy, checked in real time: .*clocks, which the PLC does not read/);
  await page.click('[data-tab=code]');
  await page.selectOption('#target', 'stl');
  await page.waitForSelector('#code[data-target="stl"][data-complete=true]');
  assert.equal(await page.getAttribute('#code-note', 'data-realtime'), 'failed');
  assert.match(await page.textContent('#code-note'), /No code: it fails at 250 ms in a real-time run/);
  assert.match(await page.textContent('#code'), /RequestRefused/);
  assert.doesNotMatch(await page.textContent('#code'), /ORGANIZATION_BLOCK/);
  await shot(page, '07c-scan-code-fails-in-real-time');
  assert.deepEqual(page.errors, []);
  await page.context().close();
});

test('an edit after a run marks the results as stale until the next run', async () => {
  const page = await newPage(browser, `${server.url}#example/lamp`);
  assert.equal(await runAndWait(page), 'realizable');
  assert.match(await page.textContent('#summary'), /As the example expects \(realizable\)/);
  assert.equal(await page.locator('#stale-note').count(), 0);
  await page.click('.cm-content');
  await page.keyboard.press('Control+End');
  await page.keyboard.insertText('\n// an edit\n');
  await page.waitForSelector('#stale-note');
  assert.equal(await page.getAttribute('#summary', 'data-stale'), 'true');
  assert.match(await page.textContent('#stale-note'), /changed since this run/);
  await shot(page, '07d-stale-results');
  assert.equal(await runAndWait(page), 'realizable');
  assert.equal(await page.locator('#stale-note').count(), 0);
  assert.equal(await page.getAttribute('#summary', 'data-stale'), 'false');
  assert.deepEqual(page.errors, []);
  await page.context().close();
});

test('an unrealizable spec shows the explanation', async () => {
  const page = await newPage(browser, `${server.url}#example/lamp_naive`);
  await page.click('.cm-content');
  await page.keyboard.press('Control+Enter');
  await page.waitForSelector('#verdict');
  assert.equal(await page.getAttribute('#verdict', 'data-verdict'), 'unrealizable');
  const text = await page.textContent('#explanation');
  assert.match(text, /✗/);
  assert.match(await page.textContent('#summary'), /As the example expects \(unrealizable\)/);
  await shot(page, '07-unrealizable-explanation');
  // A state in the explanation opens in the state space, with its removal reason.
  // The keyboard reaches it (a real link) and Enter follows it, as does "show the zone".
  const link = page.locator('#explanation .state-link').last();
  const id = await link.getAttribute('data-state');
  assert.equal(await link.evaluate((a) => a.tabIndex), 0, 'a state link is a Tab stop');
  await link.focus();
  await page.keyboard.press('Enter');
  await page.waitForSelector(`#space-graph svg #st-${id}.selected`);
  // The bar fills in when the engine has answered for the state.
  await page.waitForFunction((id) => new RegExp(`s${id} removed — `).test(document.querySelector('#selected-bar').textContent), id);
  assert.equal(await page.evaluate(() => location.hash), '#example/lamp_naive', 'following it does not navigate');
  await page.focus('#show-zone');
  await page.keyboard.press('Enter');
  await page.waitForSelector('[data-tab=zone][aria-selected=true]');
  await page.click('[data-tab=space]');
  await page.click('[data-tab=code]');
  await page.waitForFunction(() => /No controller: the spec is unrealizable/.test(document.querySelector('#code-note').textContent));
  assert.equal(await page.textContent('#code'), '');
  // Download says why there is nothing, not "run the spec first".
  await page.click('#download-code');
  await page.waitForFunction(() => /Nothing to download: No controller: the spec is unrealizable/.test(document.querySelector('#toast').textContent));
  assert.deepEqual(page.errors, []);
  await page.context().close();
});

test('share: the link restores the spec and the target in a fresh page', async () => {
  const page = await newPage(browser, `${server.url}#example/robot_arm`, { permissions: ['clipboard-read', 'clipboard-write'] });
  const spec = `${readExample('robot_arm')}\n// shared with ünïcode → ✓\n`;
  await setEditorText(page, spec);
  await page.click('[data-tab=code]');
  await page.selectOption('#target', 'explanation');
  await page.click('#share');
  await page.waitForFunction(() => location.hash.startsWith('#share/v2/'));
  const link = await page.evaluate(() => navigator.clipboard.readText());
  assert.equal(link, await page.evaluate(() => location.href));
  assert.match(link, /#share\/v2\/tga\/robot_arm\/explanation\/[A-Za-z0-9_-]+$/);
  assert.ok(link.length < spec.length, 'the spec is compressed');
  await page.context().close();

  const fresh = await newPage(browser, link);
  assert.equal(await editorText(fresh), spec);
  // The link carries the name: shown (edited, since the text differs from the example).
  assert.match(await fresh.textContent('#spec-name'), /^robot_arm \(edited\)/);
  await fresh.click('[data-tab=code]');
  assert.equal(await fresh.inputValue('#target'), 'explanation');
  await shot(fresh, '08-shared-link');
  assert.deepEqual(fresh.errors, []);
  await fresh.context().close();

  // A link of the first version (timed games, no kind or name) still opens.
  const v1 = link.replace(/#share\/v2\/tga\/robot_arm\//, '#share/v1/');
  const old = await newPage(browser, v1);
  assert.equal(await editorText(old), spec);
  assert.match(await old.textContent('#spec-name'), /^shared spec/);
  assert.deepEqual(old.errors, []);
  await old.context().close();
});

test('a syntax error is shown at its line, in the editor and the list; Run reports it', async () => {
  const page = await newPage(browser, `${server.url}#example/lamp`);
  await setEditorText(page, 'plant {\n  automaton a {\n    nodes x y;\n    x -> y ?go;\n  }\n}\n');
  await page.waitForSelector('#diagnostics button.diag', { timeout: 5000 });
  const first = page.locator('#diagnostics button.diag').first();
  assert.equal(await first.getAttribute('data-line'), '3');
  assert.match(await first.textContent(), /error line 3:/);
  await page.waitForSelector('.cm-lintRange-error');
  // The squiggle is on line 3 of the editor.
  const squiggleLine = await page.evaluate(() => {
    const range = document.querySelector('.cm-lintRange-error');
    const lines = [...document.querySelectorAll('.cm-content .cm-line')];
    return lines.findIndex((l) => l.contains(range)) + 1;
  });
  assert.equal(squiggleLine, 3);
  assert.ok((await page.locator('.cm-gutter-lint .cm-lint-marker-error').count()) > 0, 'gutter marker');
  await shot(page, '09-syntax-error');
  await page.click('#run');
  await page.waitForSelector('#status[data-kind=error]');
  assert.match(await page.textContent('#status'), /error/);
  assert.match(await page.textContent('#summary'), /No result: the spec has \d+ errors? \(see the editor\)/);
  assert.deepEqual(page.errors, []);
  await page.context().close();
});

test('round_table_8 can be cancelled: the UI stays responsive, the worker restarts, a second run works', async () => {
  const page = await newPage(browser, `${server.url}#example/round_table_8`);
  await page.evaluate(() => {
    window.longTasks = [];
    new PerformanceObserver((list) => window.longTasks.push(...list.getEntries().map((e) => e.duration))).observe({ type: 'longtask' });
  });
  const generation = await page.evaluate(() => window.plcsynth.engines.solver.generation);
  // The whole game ('explore all', the reference) of RT 8/8 takes seconds here: cancel well
  // before it could finish.
  await page.check('#exhaustive');
  await page.click('#run');
  await page.waitForFunction(() => /Exploring… [1-9]/.test(document.querySelector('#status').textContent), null, { timeout: 20000 });
  const progress = await page.textContent('#status');
  await shot(page, '10-rt8-running');
  // Responsive while the search runs: the editor takes input at once.
  const t0 = Date.now();
  await page.click('.cm-content');
  await page.keyboard.press('Control+End');
  await page.keyboard.insertText('\n// typing during a search\n');
  assert.match(await editorText(page), /typing during a search/);
  const typingMs = Date.now() - t0;
  await page.click('#cancel');
  await page.waitForSelector('#status[data-kind=cancelled]', { timeout: 2000 });
  assert.equal(await page.evaluate(() => window.plcsynth.engines.solver.generation), generation + 1, 'a new worker');
  assert.equal(await page.isDisabled('#run'), false);
  assert.equal(await page.isDisabled('#cancel'), true);
  const longTasks = await page.evaluate(() => window.longTasks);
  await record('rt8_search_long_tasks_ms', { count: longTasks.length, max: Math.max(0, ...longTasks), progress, typingMs });
  await shot(page, '11-rt8-cancelled');

  await open(page, `${server.url}#example/lamp`);
  await page.evaluate(() => {
    location.hash = '#example/lamp_naive';
  });
  await page.waitForFunction(() => window.plcsynth.name === 'lamp_naive');
  assert.equal(await runAndWait(page), 'unrealizable', 'the restarted worker solves');
  assert.deepEqual(page.errors, []);
  await page.context().close();
});

test('cancel in the same page restarts the worker without a reload', async () => {
  const page = await newPage(browser, `${server.url}#example/round_table_8`);
  await page.check('#exhaustive');
  await page.click('#run');
  await page.waitForFunction(() => /Exploring…/.test(document.querySelector('#status').textContent), null, { timeout: 20000 });
  await page.click('#cancel');
  await page.waitForSelector('#status[data-kind=cancelled]', { timeout: 2000 });
  assert.match(await page.textContent('#summary'), /Cancelled: no result/);
  assert.doesNotMatch(await page.textContent('#summary'), /Running/);
  await setEditorText(page, readExample('lamp'));
  assert.equal(await runAndWait(page), 'realizable');
  assert.deepEqual(page.errors, []);
  await page.context().close();
});

test('a budget-exceeded run shows the message and the statistics so far', async () => {
  const page = await newPage(browser, `${server.url}#example/round_table_8`);
  // The strategy-directed search stores 286 states for RT 8/8.
  await page.fill('#max-states', '100');
  assert.equal(await runAndWait(page), 'budget_exceeded');
  assert.match(await page.textContent('#summary'), /more than 100 states/);
  assert.ok((await number(page, '#stat-visited')) >= 100);
  await shot(page, '15-budget-exceeded');
  await page.click('[data-tab=code]');
  await page.waitForFunction(() => /No controller: the search exceeded its budget before deciding\./.test(document.querySelector('#code-note').textContent));
  assert.deepEqual(page.errors, []);
  await page.context().close();
});

test('dark theme follows the system setting', async () => {
  const page = await newPage(browser, null);
  await page.emulateMedia({ colorScheme: 'dark' });
  await open(page, `${server.url}#example/two_robots_14`);
  assert.equal(await runAndWait(page), 'realizable');
  const bg = await page.evaluate(() => getComputedStyle(document.body).backgroundColor);
  assert.equal(bg, 'rgb(22, 24, 29)');
  await page.click('[data-tab=space]');
  await page.waitForSelector('#space-graph svg g.state');
  await page.locator('#state-list li[data-id]').nth(3).click();
  await page.click('#selected-bar a');
  await page.waitForSelector('#zone svg.zone-plot');
  // Two different clocks on the axes; switching one redraws the polygon.
  const [x, y] = [await page.inputValue('#zone-x'), await page.inputValue('#zone-y')];
  assert.notEqual(x, y);
  const before = await page.getAttribute('#zone svg.zone-plot', 'aria-label');
  const other = await page.locator('#zone-y option').evaluateAll((os, [x, y]) => os.map((o) => o.value).find((v) => v !== x && v !== y), [x, y]);
  await page.selectOption('#zone-y', other);
  assert.notEqual(await page.getAttribute('#zone svg.zone-plot', 'aria-label'), before);
  await shot(page, '16-dark-zone');
  await page.click('[data-tab=automata]');
  await page.waitForSelector('#automata svg');
  await shot(page, '17-dark-automata');
  assert.deepEqual(page.errors, []);
  await page.context().close();
});

test('a reload keeps the edit (localStorage autosave)', async () => {
  const page = await newPage(browser, `${server.url}#example/gripper_guard`);
  await page.click('.cm-content');
  await page.keyboard.press('Control+End');
  await page.keyboard.insertText('\n// my edit survives a reload\n');
  await page.waitForTimeout(600);
  // The link stays in the address bar: the reload finds the edit saved with it.
  assert.equal(await page.evaluate(() => location.hash), '#example/gripper_guard');
  await page.reload();
  await page.waitForSelector('body[data-engine=ready]');
  assert.match(await editorText(page), /gripper[\s\S]*my edit survives a reload\n$/);
  assert.match(await page.textContent('#spec-name'), /^gripper_guard \(edited\)/);
  assert.deepEqual(page.errors, []);
  await page.context().close();
});

test('examples gallery lists every example and opens one', async () => {
  const page = await newPage(browser, server.url);
  await page.click('#examples-button');
  const items = page.locator('#gallery-list a');
  assert.ok((await items.count()) >= 17);
  await shot(page, '12-gallery');
  await page.click('#gallery-list a[data-example=two_robots_14]');
  await page.waitForFunction(() => window.plcsynth.name === 'two_robots_14');
  assert.equal(await editorText(page), readExample('two_robots_14'));
  assert.deepEqual(page.errors, []);
  await page.context().close();
});

test('after one visit the page starts and solves with the server gone (service worker)', async () => {
  // An own server (and so an own origin), because this test stops it.
  const own = await startServer();
  const page = await newPage(browser, `${own.url}#example/lamp`, { serviceWorkers: true });
  await page.waitForFunction(() => navigator.serviceWorker?.controller != null, null, { timeout: 20000 });
  own.stop();
  for (let i = 0; ; i++) {
    const gone = await fetch(own.url).then(() => false, () => true);
    if (gone) break;
    assert.ok(i < 50, 'the static server did not stop');
    await new Promise((r) => setTimeout(r, 100));
  }
  await page.reload();
  await page.waitForSelector('body[data-engine=ready]', { timeout: 20000 });
  assert.equal(await editorText(page), readExample('lamp'));
  assert.equal(await runAndWait(page), 'realizable');
  // Graphviz is a lazily loaded bundle: it was fetched on install, so it draws offline too.
  await page.click('[data-tab=automata]');
  await page.waitForSelector('#automata section[data-name=button] svg');
  await shot(page, '12-offline-after-reload');
  assert.deepEqual(page.errors, []);
  await page.context().close();
});
