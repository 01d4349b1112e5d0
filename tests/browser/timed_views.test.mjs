// The timed-game views after a teacher's review: pan and zoom of the state-space graph, the
// legends, point and segment zones, keyboard access to states, the header at 800 px, the
// docs link, and Graphviz off the main thread. `node --test tests/browser/` (after `make web`).
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { startServer, launch, newPage, open, shot, runAndWait, root } from './harness.mjs';

let server;
let browser;
before(async () => {
  server = await startServer();
  browser = await launch();
});
after(async () => {
  await browser?.close();
  server?.stop();
});

/** The part of `selector` outside the visible area of its graph box, in pixels (0: in view). */
const outOfView = (page, selector) =>
  page.$eval(selector, (el) => {
    const box = el.closest('.graph-box');
    const b = box.getBoundingClientRect();
    const [left, top] = [b.left + box.clientLeft, b.top + box.clientTop];
    const [right, bottom] = [left + box.clientWidth, top + box.clientHeight];
    const r = el.getBoundingClientRect();
    return Math.max(0, left - r.left) + Math.max(0, r.right - right) + Math.max(0, top - r.top) + Math.max(0, r.bottom - bottom);
  });

const svgWidth = (page) => page.$eval('#space-graph svg', (svg) => svg.getBoundingClientRect().width);
const scroll = (page) => page.$eval('#space-graph', (b) => ({ left: b.scrollLeft, top: b.scrollTop }));

test('Graphviz lays out in a worker: drawing the 26 automata of round_table_8 makes no main-thread task over 50 ms', async () => {
  const page = await newPage(browser, `${server.url}#example/round_table_8`);
  // A budget of 500 states ends the run at once; the automata come from compiling.
  await page.fill('#max-states', '500');
  assert.equal(await runAndWait(page), 'budget_exceeded');
  const count = await page.evaluate(() => window.plcsynth.automata.length);
  assert.ok(count >= 20, `${count} automata`);
  await page.evaluate(() => {
    window.longTasks = [];
    new PerformanceObserver((list) => window.longTasks.push(...list.getEntries().map((e) => Math.round(e.duration)))).observe({ type: 'longtask' });
  });
  await page.click('[data-tab=automata]');
  await page.waitForFunction((n) => document.querySelectorAll('#automata section.automaton svg').length === n, count, { timeout: 60000 });
  // Long tasks are reported after they end: give the last one time to arrive.
  await page.waitForTimeout(300);
  const longTasks = await page.evaluate(() => window.longTasks);
  assert.deepEqual(longTasks, [], 'no main-thread task over 50 ms while drawing');
  assert.ok((await page.locator('#automata svg g.edge.edge-request').count()) > 0);
  await shot(page, '32-rt8-automata');
  assert.deepEqual(page.errors, []);
  await page.context().close();
});
