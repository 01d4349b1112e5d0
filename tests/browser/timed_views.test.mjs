// The timed-game views after a teacher's review: pan and zoom of the state-space graph, the
// legends, point and segment zones, keyboard access to states, the header at 800 px, the
// docs link, and Graphviz off the main thread. `node --test tests/browser/` (after `make web`).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { server, browser, useBrowser, newPage, open, shot, runAndWait, root, record } from './harness.mjs';

useBrowser();

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

test('state-space graph: the selected state is in view; zoom with buttons and Ctrl+wheel, pan by dragging, fit', async () => {
  const page = await newPage(browser, `${server.url}#example/robot_arm`);
  assert.equal(await runAndWait(page), 'realizable');
  // robot_arm draws about 2 000 × 2 100 px at 100 %; its initial state sits near the right edge.
  await page.click('[data-tab=space]');
  await page.waitForSelector('#space-graph svg g.state.selected');
  await page.waitForFunction(() => document.querySelector('#space-graph').dataset.zoom);
  assert.equal(await page.isChecked('#fit-graph'), false, 'too big to fit legibly');
  assert.equal(await outOfView(page, '#space-graph svg g.state.selected'), 0, 'the initial state is in view when the tab opens');
  await shot(page, '20-space-selected-in-view');

  // Scrollbars: the box scrolls both ways at 100 %.
  const sizes = await page.$eval('#space-graph', (b) => ({ sw: b.scrollWidth, cw: b.clientWidth, sh: b.scrollHeight, ch: b.clientHeight, overflow: getComputedStyle(b).overflow }));
  assert.ok(sizes.sw > sizes.cw && sizes.sh > sizes.ch, JSON.stringify(sizes));
  assert.equal(sizes.overflow, 'auto');

  // Buttons: + and − by a factor 1.25; the level is shown on the reset button.
  const w100 = await svgWidth(page);
  await page.click('#zoom-in');
  assert.ok(Math.abs((await svgWidth(page)) / w100 - 1.25) < 0.01, 'zoom in by 1.25');
  assert.equal(await page.textContent('#zoom-reset'), '125%');
  await page.click('#zoom-out');
  await page.click('#zoom-out');
  assert.ok(Math.abs((await svgWidth(page)) / w100 - 0.8) < 0.01, 'zoom out by 1.25');
  await page.click('#zoom-reset');
  assert.ok(Math.abs((await svgWidth(page)) / w100 - 1) < 0.01, 'back to 100 %');
  assert.equal(await page.textContent('#zoom-reset'), '100%');

  // Ctrl+wheel zooms the graph (not the page), about the pointer.
  const box = await page.locator('#space-graph').boundingBox();
  await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
  await page.keyboard.down('Control');
  await page.mouse.wheel(0, -300);
  await page.keyboard.up('Control');
  await page.waitForFunction((w) => document.querySelector('#space-graph svg').getBoundingClientRect().width > w * 1.1, w100);
  await page.keyboard.down('Control');
  await page.mouse.wheel(0, 300);
  await page.keyboard.up('Control');
  await page.waitForFunction((w) => Math.abs(document.querySelector('#space-graph svg').getBoundingClientRect().width - w) < 2, w100);
  // A plain wheel still scrolls.
  const before = await scroll(page);
  await page.mouse.wheel(0, 200);
  await page.waitForFunction((t) => document.querySelector('#space-graph').scrollTop !== t, before.top);

  // Dragging pans, also when it starts on a state, and that state is not selected by the drag.
  const selected = await page.getAttribute('#space-graph svg g.state.selected', 'id');
  // A state scrolled to the middle of the box with room to pan 200 px left and 160 px down.
  const other = await page.evaluate(() => {
    const box = document.querySelector('#space-graph');
    for (const g of document.querySelectorAll('#space-graph svg g.state:not(.selected)')) {
      const [b, r] = [box.getBoundingClientRect(), g.getBoundingClientRect()];
      box.scrollLeft += r.left + r.width / 2 - (b.left + b.width / 2);
      box.scrollTop += r.top + r.height / 2 - (b.top + b.height / 2);
      if (box.scrollLeft < 200 || box.scrollTop > box.scrollHeight - box.clientHeight - 160) continue;
      const c = g.getBoundingClientRect();
      return { id: g.id, x: c.left + c.width / 2, y: c.top + c.height / 2 };
    }
    return null;
  });
  assert.ok(other, 'a state to start the drag on');
  const start = await scroll(page);
  await page.mouse.move(other.x, other.y);
  await page.mouse.down();
  // Rightwards and upwards: the view moves left (the initial state is near the right edge) and down.
  await page.mouse.move(other.x + 100, other.y - 80, { steps: 5 });
  await page.mouse.move(other.x + 200, other.y - 160, { steps: 5 });
  await page.mouse.up();
  const end = await scroll(page);
  assert.ok(Math.abs(start.left - end.left - 200) <= 2 && Math.abs(end.top - start.top - 160) <= 2, `panned ${JSON.stringify([start, end])}`);
  await page.waitForTimeout(100);
  assert.equal(await page.getAttribute('#space-graph svg g.state.selected', 'id'), selected, 'a drag is not a click');
  assert.equal(await page.$eval('#space-graph', (b) => getComputedStyle(b).cursor), 'grab');

  // Selecting a state that is off-screen from the list scrolls the graph to it.
  const far = await page.evaluate(() => {
    const box = document.querySelector('#space-graph').getBoundingClientRect();
    const g = [...document.querySelectorAll('#space-graph svg g.state')].find((g) => g.getBoundingClientRect().left > box.right + 300 || g.getBoundingClientRect().top > box.bottom + 300);
    return g && g.id.replace('st-', '');
  });
  assert.ok(far, 'a state out of view');
  await page.click(`#state-list li[data-id="${far}"]`);
  await page.waitForSelector(`#space-graph svg #st-${far}.selected`);
  await page.waitForFunction((id) => document.querySelector('#selected-bar').textContent.includes(`s${id} `), far);
  assert.equal(await outOfView(page, `#space-graph svg #st-${far}`), 0, 'the state selected in the list is scrolled into view');
  await shot(page, '21-space-zoom-pan');

  // Fit: the whole graph in its box; zooming turns fit off.
  await page.check('#fit-graph');
  assert.equal(await outOfView(page, '#space-graph svg'), 0, 'fit shows the whole graph');
  await shot(page, '22-space-fit');
  await page.click('#zoom-in');
  assert.equal(await page.isChecked('#fit-graph'), false);
  assert.deepEqual(page.errors, []);
  await page.context().close();
});

test('legends: state kinds, D and T edges, % guards and sink dots in the State space tab; the Automata legend', async () => {
  const page = await newPage(browser, `${server.url}#example/gripper_guard`);
  assert.equal(await runAndWait(page), 'realizable');
  await page.click('[data-tab=space]');
  await page.waitForSelector('#space-graph svg g.state');
  // Compact: the swatches are on one line; the key opens on request.
  const legend = page.locator('[data-panel=space] #space-legend');
  assert.equal(await legend.count(), 1);
  assert.equal(await page.isVisible('#space-legend dl'), false, 'collapsed at first');
  await page.click('#space-legend summary');
  const text = await page.innerText('#space-legend');
  for (const [what, pattern] of [
    ['entry', /entry\b[^.]*reached by a message[^.]*may act at once/],
    ['waiting', /waiting\b[^.]*only the plant and time/],
    ['interval', /interval\b[^.]*reached by a delay[^.]*act, or wait/],
    ['guard state', /guard\b[^.]*state guard/],
    ['D', /D\b[^.]*time passes/],
    ['T', /T\b[^.]*timeout[^.]*invariant/],
    ['%', /%[^.]*guard/],
    ['sink dot', /dot[^.]*(leads nowhere|no state)/],
    ['zeno', /zeno/i],
  ]) {
    assert.match(text, pattern, `the legend explains ${what}`);
  }
  assert.equal(await page.isVisible('#space-legend dl'), true);
  // Every kind of state and edge in this graph has its swatch.
  for (const cls of ['l-guard', 'l-timeout', 'l-sink', 'l-delay', 'l-win', 'l-lose', 'l-initial', 'l-selected']) {
    assert.equal(await page.locator(`#space-legend summary .${cls}`).count(), 1, `swatch ${cls}`);
  }
  await shot(page, '23-space-legend');

  await page.click('[data-tab=automata]');
  await page.waitForSelector('#automata svg');
  const automata = await page.textContent('#automata .legend');
  for (const pattern of [/\?request/, /!reaction/, /\$plan step/, /initial/, /failed/, /invariant/, /reset/, /instant/]) assert.match(automata, pattern);
  await shot(page, '24-automata-legend');
  assert.deepEqual(page.errors, []);
  await page.context().close();
});

test('zone plot: a point zone is drawn as a dot, a one-dimensional zone as a segment, each labelled', async () => {
  // two_machines starts with both plan clocks at 0: a point.
  const page = await newPage(browser, `${server.url}#example/two_machines`);
  assert.equal(await runAndWait(page), 'realizable');
  await page.click('[data-tab=space]');
  await page.waitForSelector('#state-list li[data-id="0"]');
  await page.click('#state-list li[data-id="0"]');
  await page.waitForFunction(() => /s0 winning/.test(document.querySelector('#selected-bar').textContent));
  await page.click('#selected-bar a');
  await page.waitForSelector('#zone svg.zone-plot');
  assert.match(await page.textContent('#zone-text'), /plan1\.timeout = 0 ∧ plan2\.timeout = 0/);
  assert.equal(await page.locator('#zone svg circle.zone-point').count(), 1, 'a dot for the point');
  assert.equal(await page.textContent('#zone svg .zone-label'), '(0, 0)');
  const dot = await page.$eval('#zone svg circle.zone-point', (c) => {
    const r = c.getBoundingClientRect();
    return { w: r.width, fill: getComputedStyle(c).fill };
  });
  assert.ok(dot.w >= 6, `the dot is visible: ${JSON.stringify(dot)}`);
  await shot(page, '25-zone-point');
  // Another clock on the y axis: still the point (plan1.timeout = 0, the other one unbounded: a ray).
  await page.selectOption('#zone-y', { label: 'A.c' });
  assert.equal(await page.locator('#zone svg line.zone-segment').count(), 1, 'a segment for a one-dimensional projection');
  assert.match(await page.textContent('#zone svg .zone-label'), /^plan1\.timeout = 0$/);
  assert.equal(await page.getAttribute('#zone svg line.zone-segment', 'class'), 'zone zone-segment unbounded');
  await shot(page, '26-zone-segment');
  // A two-dimensional zone is still a polygon.
  await page.click('[data-tab=space]');
  const wide = page.locator('#state-list li.winning', { hasText: 'A.c' }).first();
  const id = await wide.getAttribute('data-id');
  await wide.click();
  await page.waitForFunction((id) => document.querySelector('#selected-bar').textContent.includes(`s${id} `), id);
  await page.click('#selected-bar a');
  await page.waitForFunction((id) => document.querySelector('#zone-title')?.textContent.includes(`s${id} `), id);
  const shapes = await page.$$eval('#zone svg .zone', (els) => els.map((e) => e.tagName));
  assert.equal(shapes.length, 1, `one shape: ${shapes}`);
  assert.deepEqual(page.errors, []);
  await page.context().close();
});

test('keyboard: states in the list and in the graph are reached with Tab and selected with Enter or Space', async () => {
  const page = await newPage(browser, `${server.url}#example/lamp`);
  assert.equal(await runAndWait(page), 'realizable');
  await page.click('[data-tab=space]');
  await page.waitForSelector('#space-graph svg g.state');
  await page.focus('#state-search');
  const active = () => page.evaluate(() => {
    const el = document.activeElement;
    return { list: el.closest('#state-list') ? el.dataset.id : null, graph: el.matches('#space-graph g.state') ? el.id : null, label: el.getAttribute('aria-label') };
  });
  let at = await active();
  for (let i = 0; i < 15 && at.list == null; i++) {
    await page.keyboard.press('Tab');
    at = await active();
  }
  assert.equal(at.list, '0', 'Tab reaches the first state of the list');
  await page.keyboard.press('Tab');
  at = await active();
  assert.equal(at.list, '1', 'Tab moves to the next state');
  assert.match(at.label, /^s1 (winning|removed)/);
  await page.keyboard.press('Enter');
  await page.waitForFunction(() => /^s1 /.test(document.querySelector('#selected-bar').textContent));
  assert.equal(await page.getAttribute('#state-list li[data-id="1"]', 'aria-selected'), 'true');
  assert.equal(await page.getAttribute('#state-list', 'role'), 'listbox');
  await shot(page, '27-keyboard-list');

  // From the last state of the list Tab goes on into the graph.
  await page.focus('#state-list li[data-id]:last-of-type');
  for (let i = 0; i < 5 && at.graph == null; i++) {
    await page.keyboard.press('Tab');
    at = await active();
  }
  assert.ok(at.graph, 'Tab reaches a state of the graph');
  assert.match(at.label, /^s\d+ (winning|removed), (entry|waiting|interval|guard) state/);
  await page.keyboard.press('Tab');
  at = await active();
  const id = at.graph.replace('st-', '');
  await page.keyboard.press(' ');
  await page.waitForSelector(`#space-graph svg #st-${id}.selected`);
  await page.waitForFunction((id) => document.querySelector('#selected-bar').textContent.startsWith(`s${id} `), id);
  assert.equal(await page.getAttribute(`#space-graph svg #st-${id}`, 'role'), 'button');
  assert.equal(await page.evaluate(() => document.activeElement.id), `st-${id}`, 'the focus stays on the state');
  await shot(page, '28-keyboard-graph');
  assert.deepEqual(page.errors, []);
  await page.context().close();
});

test('keyboard: in a large space the focus stays on the selected state when the neighbourhood is redrawn', async () => {
  const page = await newPage(browser, `${server.url}#example/two_machines`);
  // Explore all: a space of thousands of states, drawn as neighbourhoods.
  await page.check('#exhaustive');
  assert.equal(await runAndWait(page), 'realizable');
  await page.click('[data-tab=space]');
  await page.waitForSelector('#space-graph svg g.state.selected');
  await page.focus('#space-graph svg g.state.selected');
  await page.keyboard.press('Tab');
  const id = await page.evaluate(() => document.activeElement.id);
  assert.match(id, /^st-\d+$/);
  await page.keyboard.press('Enter');
  await page.waitForSelector(`#space-graph svg #${id}.selected`);
  await page.waitForFunction((id) => document.activeElement?.id === id, id);
  assert.deepEqual(page.errors, []);
  await page.context().close();
});

test('header at 800 × 800: Run, Cancel, Share and Docs are inside the window and clickable; 1280 unchanged', async () => {
  const page = await newPage(browser, null);
  await page.setViewportSize({ width: 800, height: 800 });
  await open(page, `${server.url}#example/round_table_8`);
  const inside = async (selector) => {
    const b = await page.locator(selector).boundingBox();
    assert.ok(b && b.x >= 0 && b.y >= 0 && b.x + b.width <= 800 && b.y + b.height <= 800, `${selector} at ${JSON.stringify(b)}`);
    // Nothing covers its middle.
    const hit = await page.evaluate(([s, x, y]) => document.elementFromPoint(x, y)?.closest(s) != null, [selector, b.x + b.width / 2, b.y + b.height / 2]);
    assert.ok(hit, `${selector} is not covered`);
  };
  for (const s of ['#run', '#cancel', '#share', '#docs-link', '#examples-button', '#open-button', '#max-states', '#exhaustive']) await inside(s);
  assert.ok(await page.evaluate(() => document.documentElement.scrollWidth <= 800), 'no horizontal scrolling');
  await shot(page, '29-header-800');
  // The whole game takes seconds: long enough to cancel.
  await page.check('#exhaustive');
  await page.click('#run');
  await page.waitForSelector('#cancel:not([disabled])');
  await inside('#cancel');
  await page.click('#cancel');
  await page.waitForSelector('#status[data-kind=cancelled]');
  await page.click('[data-tab=space]');
  await shot(page, '30-space-800');
  // At 1280 the header is one line, as before.
  await page.setViewportSize({ width: 1280, height: 800 });
  const tops = await page.$$eval('.bar > *', (els) => els.filter((e) => e.offsetParent).map((e) => e.getBoundingClientRect().top + e.getBoundingClientRect().height / 2));
  assert.ok(Math.max(...tops) - Math.min(...tops) < 6, `one line at 1280: ${tops}`);
  await page.click('[data-tab=summary]');
  await shot(page, '31-header-1280');
  assert.deepEqual(page.errors, []);
  await page.context().close();
});

test('a Docs link in the header opens the playground guide, shipped with the page with the language references', async () => {
  const page = await newPage(browser, server.url);
  assert.equal(await page.getAttribute('#docs-link', 'href'), 'dist/docs/playground.md');
  const docs = await page.evaluate(async () => {
    const get = async (name) => {
      const r = await fetch(`dist/docs/${name}`);
      return { status: r.status, text: await r.text() };
    };
    return { playground: await get('playground.md'), timed: await get('timed-language.md') };
  });
  assert.equal(docs.playground.status, 200);
  assert.equal(docs.playground.text, readFileSync(join(root, 'docs', 'playground.md'), 'utf8'));
  assert.equal(docs.timed.status, 200);
  assert.equal(docs.timed.text, readFileSync(join(root, 'docs', 'timed-language.md'), 'utf8'));
  const [tab] = await Promise.all([page.context().waitForEvent('page'), page.click('#docs-link')]);
  await tab.waitForLoadState();
  assert.match(await tab.textContent('body'), /# The browser playground/);
  await tab.close();
  assert.deepEqual(page.errors, []);
  await page.context().close();
});

test('Graphviz lays out in a worker: every automaton of round_table_8 is laid out by the graphviz worker, not the page', async () => {
  const page = await newPage(browser);
  // Count the DOT texts the page hands to each named worker: every drawing must go through
  // the Graphviz worker. (How long the page's own tasks take is measured and reported, never
  // asserted: the machines are shared and noisy.)
  await page.addInitScript(() => {
    window.dotsPosted = {};
    const Native = window.Worker;
    window.Worker = class extends Native {
      constructor(url, options) {
        super(url, options);
        const name = options?.name ?? String(url);
        const post = this.postMessage.bind(this);
        this.postMessage = (message, ...rest) => {
          if (typeof message?.dot === 'string') (window.dotsPosted[name] ??= []).push(message.dot);
          return post(message, ...rest);
        };
      }
    };
  });
  await open(page, `${server.url}#example/round_table_8`);
  // A budget of 100 states ends the run at once; the automata come from compiling.
  await page.fill('#max-states', '100');
  assert.equal(await runAndWait(page), 'budget_exceeded');
  const count = await page.evaluate(() => window.plcsynth.automata.length);
  assert.ok(count >= 20, `${count} automata`);
  await page.evaluate(() => {
    window.longTasks = [];
    new PerformanceObserver((list) => window.longTasks.push(...list.getEntries().map((e) => Math.round(e.duration)))).observe({ type: 'longtask' });
  });
  await page.click('[data-tab=automata]');
  await page.waitForFunction((n) => document.querySelectorAll('#automata section.automaton svg').length === n, count, { timeout: 60000 });
  const posted = await page.evaluate(() => {
    const byGraphviz = new Set(window.dotsPosted.graphviz ?? []);
    return {
      missing: window.plcsynth.automata.filter((a) => !byGraphviz.has(a.dot)).map((a) => a.name),
      elsewhere: Object.keys(window.dotsPosted).filter((name) => name !== 'graphviz'),
    };
  });
  assert.deepEqual(posted.missing, [], 'every automaton is laid out by the graphviz worker');
  assert.deepEqual(posted.elsewhere, [], 'DOT goes to no other worker');
  // Long tasks are reported after they end: give the last one time to arrive.
  await page.waitForTimeout(300);
  const longTasks = await page.evaluate(() => window.longTasks);
  await record('rt8_automata_drawing', { automata: count, main_thread_tasks_over_50ms: longTasks });
  console.log(`# measurements: drawing ${count} automata, main-thread tasks over 50 ms: ${JSON.stringify(longTasks)}`);
  assert.ok((await page.locator('#automata svg g.edge.edge-request').count()) > 0);
  await shot(page, '32-rt8-automata');
  assert.deepEqual(page.errors, []);
  await page.context().close();
});
