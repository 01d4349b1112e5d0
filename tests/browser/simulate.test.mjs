// The Simulate tab of timed games (www/src/simulator.js): the controller program stepped against
// the plant, random runs, the concrete state shown in the state space, and the counter-play of
// an unrealizable spec replayed in the simulator.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { server, browser, useBrowser, newPage, shot, runAndWait } from './harness.mjs';

useBrowser();

const text = (page, selector) => page.textContent(selector).then((s) => s.trim());
/** Waits until the simulator has answered the last click. */
const settled = (page) => page.waitForSelector('#simulator[data-busy=false]');
const location = (page, unit) => text(page, `#sim-locations tr[data-unit=${unit}] td`);

async function openSimulator(page) {
  await page.click('[data-tab=simulate]');
  await page.waitForSelector('#sim-moves');
  await settled(page);
}

async function press(page, message) {
  await page.click(`#sim-moves button[data-message=${message}]`);
  await settled(page);
}

test('lamp: the controller follows one plan cycle step by step; back and reset', async () => {
  const page = await newPage(browser, `${server.url}#example/lamp`);
  assert.equal(await page.isVisible('[data-tab=simulate]'), true, 'a tab of the timed mode');
  assert.equal(await runAndWait(page), 'realizable');
  await openSimulator(page);
  assert.match(await text(page, '#sim-mode'), /controller program runs/);
  // The program waits for the button at its first command; the plant may only press.
  assert.match(await text(page, '#sim-program li.current'), /WAITUNTIL \(press\)/);
  assert.deepEqual(await page.locator('#sim-moves button').evaluateAll((bs) => bs.map((b) => b.dataset.message)), ['press']);
  assert.equal(await location(page, 'lamp'), 'off');
  const plan0 = await text(page, '#sim-plans td');
  await shot(page, '60-sim-lamp-start');

  // press → the controller turns the lamp on in the same instant; the plan takes its first step.
  await press(page, 'press');
  assert.match(await text(page, '#sim-sent'), /\?turn_on/);
  assert.equal(await location(page, 'lamp'), 'on');
  assert.equal(await location(page, 'button'), 'pressing');
  assert.equal(await text(page, '#sim-progress'), '1 plan step');
  assert.notEqual(await text(page, '#sim-plans td'), plan0, 'the plan moved on');
  assert.match(await text(page, '#sim-room'), /at most 0\.875/, 'the invariant c < 1 bounds the delay');
  // A delay beyond the invariant is refused and said so; one within it is taken.
  await page.fill('#sim-delay-value', '2');
  await page.click('#sim-delay');
  await settled(page);
  assert.match(await text(page, '#sim-note'), /at most 0\.875/);
  await page.fill('#sim-delay-value', '0.5');
  await page.click('#sim-delay');
  await settled(page);
  assert.equal(await text(page, '#sim-time'), 'time 0.5');
  assert.match(await text(page, '#sim-clocks'), /button\.c\s*0\.5/);
  await press(page, 'press_settled');
  await shot(page, '61-sim-lamp-on');

  // release → the controller turns it off; the plan completes its cycle.
  await press(page, 'release');
  assert.match(await text(page, '#sim-sent'), /\?turn_off/);
  assert.equal(await location(page, 'lamp'), 'off');
  assert.equal(await text(page, '#sim-progress'), '2 plan steps');
  assert.equal(await text(page, '#sim-plans td'), plan0, 'back at the plan’s first step: one cycle');
  const kinds = await page.locator('#sim-trace tbody tr').evaluateAll((rows) => rows.map((r) => r.dataset.kind));
  assert.deepEqual(kinds, ['reaction', 'request', 'delay', 'reaction', 'reaction', 'request']);
  assert.equal(await page.locator('#sim-trace tr.progress').count(), 2, 'the two plan steps are marked');
  assert.equal(await page.locator('#sim-failure').count(), 0);
  await shot(page, '62-sim-lamp-cycle');

  // Back: the release and the controller's answer are undone.
  await page.click('#sim-back');
  await settled(page);
  assert.equal(await location(page, 'lamp'), 'on');
  assert.equal(await location(page, 'button'), 'pressed');
  assert.equal(await page.locator('#sim-trace tbody tr').count(), 4);
  assert.equal(await text(page, '#sim-steps'), '3 steps');
  // Reset: the initial state, nothing in the trace.
  await page.click('#sim-reset');
  await settled(page);
  assert.equal(await text(page, '#sim-time'), 'time 0');
  assert.equal(await location(page, 'lamp'), 'off');
  assert.match(await text(page, '#sim-trace'), /Nothing has happened yet/);
  assert.equal(await page.isDisabled('#sim-back'), true);
  // Playing the controller too: the requests are moves, and a wrong one fails at once.
  await page.check('#sim-free');
  await settled(page);
  assert.match(await text(page, '#sim-mode'), /You play the controller too/);
  assert.equal(await page.locator('#sim-program').count(), 0, 'no program runs');
  await press(page, 'press');
  await page.fill('#sim-delay-value', '0.5');
  await page.click('#sim-delay');
  await settled(page);
  await press(page, 'press_settled');
  assert.equal(await page.getAttribute('#sim-failure', 'data-kind'), 'assertion');
  assert.match(await text(page, '#sim-failure'), /never lamp\.off and button\.pressed/);
  await shot(page, '69-sim-lamp-free-failure');
  await page.uncheck('#sim-free');
  await settled(page);
  assert.match(await text(page, '#sim-mode'), /controller program runs/);
  assert.deepEqual(page.errors, []);
  await page.context().close();
});

test('robot arm: 50 random steps without failure, and the state shown in the state space is winning', async () => {
  const page = await newPage(browser, `${server.url}#example/robot_arm`);
  assert.equal(await runAndWait(page), 'realizable');
  await openSimulator(page);
  await page.fill('#sim-n', '50');
  await page.click('#sim-run');
  await settled(page);
  assert.equal(await text(page, '#sim-steps'), '50 steps');
  assert.equal(await page.locator('#sim-failure').count(), 0, 'no failure');
  assert.ok(Number((await text(page, '#sim-progress')).split(' ')[0]) > 0, 'the plans progressed');
  assert.ok((await page.locator('#sim-trace tr[data-kind=request]').count()) > 0, 'the controller acted');
  await shot(page, '63-sim-robot-arm-random');

  await page.click('#sim-locate');
  await page.waitForSelector('[data-tab=space][aria-selected=true]');
  await page.waitForSelector('#space-graph svg g.state.selected');
  await page.waitForFunction(() => /^s\d+ winning/.test(document.querySelector('#selected-bar').textContent));
  await shot(page, '64-sim-robot-arm-in-space');
  // Back in the simulator, the note names the state.
  await page.click('[data-tab=simulate]');
  assert.match(await text(page, '#sim-note'), /lies in s\d+/);
  assert.deepEqual(page.errors, []);
  await page.context().close();
});

test('two robots in 13 s: the counter-play is listed, the tree folded, and the replay ends in the violation', async () => {
  const page = await newPage(browser, `${server.url}#example/two_robots_13`);
  assert.equal(await runAndWait(page), 'unrealizable');
  const heading = await text(page, '#summary h3');
  const depth = Number(heading.match(/within (\d+) moves/)[1]);
  assert.equal(await page.locator('#counter-play li').count(), depth + 1, 'one line per move and the failure');
  assert.match(await text(page, '#counter-play li.violation'), /✗ plan1 fails/);
  assert.match(await text(page, '#counter-play'), /controller \?a_go/);
  // The whole tree is there, folded.
  assert.equal(await page.getAttribute('#explanation-tree', 'open'), null);
  assert.equal(await page.isVisible('#explanation'), false);
  assert.ok((await page.locator('#explanation .step').count()) > 100);
  await shot(page, '65-two-robots-counter-play');
  await page.click('#explanation-tree > summary');
  assert.equal(await page.isVisible('#explanation'), true);
  await shot(page, '68-two-robots-tree-unfolded');
  await page.click('#explanation-tree > summary');

  await page.click('#replay-counter-play');
  await page.waitForSelector('[data-tab=simulate][aria-selected=true]');
  await page.waitForSelector('#sim-failure');
  await settled(page);
  assert.equal(await page.getAttribute('#sim-failure', 'data-kind'), 'plan_failed');
  assert.match(await text(page, '#sim-failure'), /plan1 failed: a timeout clock exceeded its bound/);
  assert.match(await text(page, '#sim-mode'), /Replaying the counter-play/);
  assert.equal(await page.locator('#sim-replay .reason').count(), 0, 'the whole line was replayed');
  // Both sides were played: arm A went, the press processed, arm B delivered too late.
  const trace = await text(page, '#sim-trace');
  for (const m of ['?a_go', '!a_arrived', '?process', '!processed', '?b_deliver']) assert.ok(trace.includes(m), `${m} in the trace`);
  assert.ok(Number((await text(page, '#sim-time')).split(' ')[1]) > 13, 'past the 13 s of the plan');
  assert.equal(await page.isDisabled('#sim-random'), true, 'a failure stops the simulation');
  await shot(page, '66-two-robots-replay');
  await page.locator('#sim-trace tbody tr').last().scrollIntoViewIfNeeded();
  await shot(page, '67-two-robots-replay-trace');
  // One step back, and the failure is gone.
  await page.click('#sim-back');
  await settled(page);
  assert.equal(await page.locator('#sim-failure').count(), 0);
  assert.deepEqual(page.errors, []);
  await page.context().close();
});
