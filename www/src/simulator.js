// The Simulate tab of timed games: the synthesised controller program stepped against the plant
// automata (the engine's closed-loop simulator, `Simulation` in src/program/simulate.rs), like
// UPPAAL's simulator. The engine keeps the simulation (every step is a query to the worker);
// this module only shows a `SimState` and sends the user's choices: a plant reaction, a delay, a
// random step or N of them, a step back, a reset. For an unrealizable spec there is no program:
// the simulation is free (the user, or the replay of the counter-play, picks the requests too).
import { $, actionLink, h, fmtInt } from './dom.js';

/** A time in time units, without trailing zeros. */
const t = (v) => (Number.isInteger(v) ? String(v) : v.toFixed(3).replace(/0+$/, ''));

export class Simulator {
  /**
   * `query(method, args)` asks the solving worker's session; `onLocate(id)` shows a state of the
   * explored space; `onTab()` brings this tab to the front (for the replay).
   */
  constructor(root, { query, onLocate, onTab }) {
    this.root = root;
    this.query = query;
    this.onLocate = onLocate;
    this.onTab = onTab;
    this.state = null;
    this.listing = null;
    this.busy = false;
    const button = (id, label, title, onclick) => h('button', { id, title, onclick: () => this.act(onclick) }, label);
    this.toolbar = h(
      'div',
      { class: 'toolbar sim-toolbar' },
      button('sim-reset', '⟲ Reset', 'start again from the initial state (with this seed)', () => this.start()),
      button('sim-back', '◀ Back', 'take the last step back', () => this.query('simBack', [])),
      button('sim-random', 'Random step', 'one plant step chosen at random (a reaction or a delay)', () => this.query('simRandom', [1])),
      h('span', { class: 'sim-group' },
        button('sim-run', 'Run', 'random plant steps until a failure or N steps', () => this.query('simRandom', [Math.max(1, Math.floor(Number($('#sim-n', this.root).value) || 1))])),
        h('input', { id: 'sim-n', type: 'number', min: 1, step: 1, value: 50, 'aria-label': 'number of random steps' }), ' steps'),
      h('span', { class: 'sim-group' },
        button('sim-delay', 'Wait', 'let time pass (rounded to eighths of a time unit); the controller may act meanwhile', () => this.query('simDelay', [Number($('#sim-delay-value', this.root).value)])),
        h('input', { id: 'sim-delay-value', type: 'number', min: 0.125, step: 0.125, value: 0.5, 'aria-label': 'delay in time units' }), h('span', { id: 'sim-room', class: 'muted' })),
      h('label', { class: 'muted', title: 'drives the random steps and the sensor (guard) inputs' }, 'seed ', h('input', { id: 'sim-seed', type: 'number', min: 0, step: 1, value: 1 })),
      h('label', { class: 'muted', title: 'without the controller program: you pick the requests too (starts again)' },
        h('input', { id: 'sim-free', type: 'checkbox', onchange: () => this.act(() => this.start()) }), ' play the controller'),
      h('button', { id: 'sim-locate', title: 'select the explored state that holds this concrete state', onclick: () => this.locate() }, 'Show in state space'),
    );
    this.clear('Run a timed spec to simulate its controller against the plant.');
  }

  /** Forgets the simulation (a new run or another document). */
  clear(message) {
    this.state = null;
    this.listing = null;
    this.result = null;
    this.root.replaceChildren(h('p', { class: 'muted', id: 'sim-empty' }, message));
  }

  /** A new result: the simulation starts when the tab is opened. */
  load(result) {
    this.clear('Open this tab again to start the simulation.');
    this.result = result;
  }

  /** The tab was opened: start once per result. */
  async open() {
    if (!this.result || this.state || this.busy) return;
    const verdict = this.result.verdict;
    if (verdict === 'budget_exceeded' || verdict === 'cancelled') {
      this.root.replaceChildren(h('p', { class: 'muted', id: 'sim-empty' }, 'The search did not decide: no controller program to simulate (run it with a larger budget).'));
      return;
    }
    await this.act(() => this.start());
  }

  start() {
    const seed = Math.max(0, Math.floor(Number($('#sim-seed', this.toolbar).value) || 0));
    return this.query('simStart', [seed, { free: $('#sim-free', this.toolbar).checked }]);
  }

  /** Plays the counter-play of an unrealizable spec in a free simulation. */
  async replay() {
    // Busy from here on, so that opening the tab does not start a simulation of its own.
    const replayed = this.act(() => this.query('simReplay', []));
    this.onTab();
    await replayed;
  }

  /** Runs one engine call that returns a `SimState`, and shows it; an error goes to the note. */
  async act(call) {
    if (this.busy) return;
    this.busy = true;
    this.root.dataset.busy = 'true';
    try {
      this.show(await call());
    } catch (error) {
      this.note(String(error?.message ?? error), 'error');
    } finally {
      this.busy = false;
      this.root.dataset.busy = 'false';
    }
  }

  note(text, kind = '') {
    const el = $('#sim-note', this.root);
    if (!el) return;
    el.textContent = text;
    el.className = `sim-note ${kind}`;
  }

  async locate() {
    try {
      const ids = await this.query('simLocate', []);
      if (!ids.length) return this.note('No explored state holds this concrete state (the search stopped before reaching it).', 'error');
      this.note(`The concrete state lies in s${ids[0]}${ids.length > 1 ? ` (and ${ids.slice(1, 6).map((i) => `s${i}`).join(', ')}${ids.length > 6 ? ', …' : ''})` : ''}.`);
      await this.onLocate(ids[0]);
    } catch (error) {
      this.note(String(error?.message ?? error), 'error');
    }
  }

  show(state) {
    if (state.listing !== undefined && state.listing !== null) this.listing = state.listing;
    if (state.mode === 'free') this.listing = null;
    this.state = state;
    const free = state.mode === 'free';
    const ended = Boolean(state.failure) || state.stuck;
    const headline = state.replay
      ? h('p', { class: 'muted', id: 'sim-mode' }, 'Replaying the counter-play: no controller exists, so the plant’s winning line is played with the controller choices it assumes (', h('strong', {}, 'free mode'), ': you pick requests too). Step back to see it unfold.')
      : free && $('#sim-free', this.toolbar).checked
        ? h('p', { class: 'muted', id: 'sim-mode' }, 'You play the controller too (free mode): pick its requests as well as the plant’s reactions, and see what fails.')
        : free
        ? h('p', { class: 'muted', id: 'sim-mode' }, 'No controller program (the spec is not realizable): free mode, you pick the controller’s requests as well as the plant’s reactions.')
        : h('p', { class: 'muted', id: 'sim-mode' }, 'The controller program runs in zero time after every plant step (the scan model of Peter 2005, 6.3); you play the plant.');
    const failure = state.failure || state.stuck
      ? h('div', { class: 'sim-failure', id: 'sim-failure', role: 'alert', 'data-kind': state.failure?.kind ?? 'stuck' },
          state.failure ? `✗ ${state.failure_text}.` : '■ The plant can neither move nor wait (an exceptional timeout, not the controller’s fault).',
          h('span', { class: 'sim-stopped' }, ' The simulation has stopped: step back or reset.'))
      : null;
    const parts = [
      this.toolbar,
      h('div', { class: 'sim-status' },
        h('span', { id: 'sim-time' }, `time ${t(state.time)}`), ' · ',
        h('span', { id: 'sim-steps' }, `${fmtInt(state.history)} step${state.history === 1 ? '' : 's'}`), ' · ',
        h('span', { id: 'sim-progress' }, `${fmtInt(state.progress)} plan step${state.progress === 1 ? '' : 's'}`), ' · ',
        h('span', {}, `${fmtInt(state.requests)} request${state.requests === 1 ? '' : 's'} sent`),
        h('span', { id: 'sim-note', class: 'sim-note' })),
      headline,
      failure,
      state.replay ? this.replayLine(state.replay) : null,
      h('div', { class: 'sim-body' },
        h('div', { class: 'sim-col sim-now' }, this.moves(state, ended), this.plant(state)),
        free ? null : h('div', { class: 'sim-col sim-program-col' }, h('h4', {}, 'Program'), this.program(state)),
        h('div', { class: 'sim-col sim-trace-col' }, h('h4', {}, 'Trace'), h('div', { class: 'sim-trace-box' }, this.trace(state)))),
    ];
    this.root.replaceChildren(...parts.filter(Boolean));
    $('#sim-back', this.root).disabled = state.history === 0;
    for (const id of ['#sim-random', '#sim-run', '#sim-delay']) $(id, this.root).disabled = ended;
    $('#sim-delay', this.root).disabled = ended || !state.can_delay;
    $('#sim-room', this.root).textContent = state.can_delay ? ` (at most ${state.max_delay === null ? '∞' : t(state.max_delay)})` : ' (no time may pass now)';
    $('#sim-seed', this.root).value = state.seed;
    // Free without a program whatever the box says; the box is for realizable specs.
    $('#sim-free', this.root).checked = free && !state.replay && $('#sim-free', this.root).checked;
    $('#sim-free', this.root).disabled = free && !$('#sim-free', this.root).checked;
    this.root.querySelector('.sim-program li.current')?.scrollIntoView({ block: 'nearest' });
    const trace = this.root.querySelector('.sim-trace-box');
    if (trace) trace.scrollTop = trace.scrollHeight;
  }

  /** The moves on offer: one button each (reactions first, then, free, the requests). */
  moves(state, ended) {
    const button = (m) =>
      h('button', { class: `sim-move ${m.kind}`, 'data-message': m.message, 'data-index': m.index, disabled: ended, onclick: () => this.act(() => this.query('simStep', [m.index])) },
        m.text, m.instant ? h('span', { class: 'badge' }, 'instant') : null);
    const reactions = state.moves.filter((m) => m.kind === 'reaction');
    const requests = state.moves.filter((m) => m.kind === 'request');
    return h('section', { id: 'sim-moves' },
      h('h4', {}, 'Next plant reaction'),
      reactions.length ? h('div', { class: 'sim-moves' }, reactions.map(button)) : h('p', { class: 'muted' }, ended ? '—' : 'none enabled now: let time pass'),
      state.mode === 'free' ? [h('h4', {}, 'Controller request'), requests.length ? h('div', { class: 'sim-moves' }, requests.map(button)) : h('p', { class: 'muted' }, '—')] : null,
      state.mode === 'free' ? null : state.sent.length ? h('p', { id: 'sim-sent' }, 'The controller sent ', state.sent.flatMap((m, i) => [i ? ', ' : '', h('strong', {}, `?${m}`)]), ' after the last step.') : h('p', { id: 'sim-sent', class: 'muted' }, 'No request after the last step.'),
    );
  }

  /** Locations, clocks (and the controller's timers), plans and sensor inputs. */
  plant(state) {
    const row = (...cells) => h('tr', {}, cells.map((c) => h('td', {}, c)));
    return [
      h('h4', {}, 'Plant'),
      h('table', { class: 'sim-table', id: 'sim-locations' }, state.locations.map((l) => h('tr', { 'data-unit': l.unit }, h('th', {}, l.unit), h('td', {}, l.location)))),
      state.clocks.length
        ? [h('h4', {}, 'Clocks'),
           h('table', { class: 'sim-table', id: 'sim-clocks' },
             h('tr', {}, h('th', {}, ''), h('th', {}, 'plant'), state.mode === 'program' ? h('th', { title: 'the controller’s timer of the clock, reset by its commands' }, 'timer') : null),
             state.clocks.map((c) => h('tr', {}, h('th', {}, c.name), h('td', {}, t(c.value)), c.timer === null ? null : h('td', {}, t(c.timer)))))]
        : null,
      state.plans.length
        ? [h('h4', {}, 'Plans'),
           h('table', { class: 'sim-table', id: 'sim-plans' }, state.plans.map((p) =>
             h('tr', { 'data-plan': p.name, class: p.failed ? 'failed' : '' }, h('th', {}, p.name), h('td', {}, `${p.location} `, h('span', { class: 'muted' }, p.failed ? '(failed)' : `(step ${p.index + 1} of ${p.count})`)))))]
        : null,
      state.guards.length
        ? [h('h4', {}, 'Sensor inputs'), h('table', { class: 'sim-table' }, state.guards.map((g) => row(g.name, g.value ? 'true' : 'false')))]
        : null,
    ].flat();
  }

  /** The program's listing with the current command marked. */
  program(state) {
    if (!this.listing) return h('p', { class: 'muted' }, 'No program.');
    return h('ol', { class: 'sim-program', id: 'sim-program', start: 0 },
      this.listing.map((text, i) => h('li', { 'data-pc': i, class: i === state.pc ? 'current' : '', 'aria-current': i === state.pc ? 'step' : null }, text)));
  }

  /** The trace as a message sequence chart: plant on the left, controller on the right. */
  trace(state) {
    if (!state.events.length) return h('p', { class: 'muted', id: 'sim-trace' }, 'Nothing has happened yet.');
    const lane = (e) => {
      if (e.kind === 'reaction') return [h('td', { class: 'lane plant' }, e.text), h('td', { class: 'arrow' }, '──▶'), h('td', {})];
      if (e.kind === 'request') return [h('td', {}), h('td', { class: 'arrow' }, '◀──'), h('td', { class: 'lane controller' }, e.text)];
      return [h('td', { colspan: 3, class: `lane ${e.kind}` }, e.kind === 'failure' ? `✗ ${e.text}` : e.text)];
    };
    return h('table', { class: 'sim-trace', id: 'sim-trace' },
      h('colgroup', {}, h('col', { class: 'time' }), h('col', {}), h('col', { class: 'arrow' }), h('col', {})),
      h('thead', {}, h('tr', {}, h('th', {}, 'time'), h('th', {}, 'plant'), h('th', {}), h('th', {}, 'controller'))),
      h('tbody', {}, state.events.map((e) => h('tr', { class: `ev-${e.kind}${e.progress ? ' progress' : ''}`, 'data-kind': e.kind, 'data-step': e.step, title: e.progress ? 'a plan took a step' : null },
        h('td', { class: 'time' }, t(e.time)), lane(e)))));
  }

  /** The counter-play being replayed, and where the replay stopped if it could not finish. */
  replayLine(replay) {
    return h('details', { class: 'sim-replay', id: 'sim-replay' },
      h('summary', {}, `The counter-play: ${replay.line.moves.length} moves into “${replay.line.end}”`),
      counterPlayList(replay.line),
      replay.stopped ? h('p', { class: 'reason' }, `The replay stopped early: ${replay.stopped}`) : null);
  }
}

/** A counter-play as a numbered list of moves ending in its failure (also the Summary's). */
export function counterPlayList(play, onState) {
  const who = (m) => {
    if (m.mover === 'wait') return ['controller ', h('strong', {}, 'waits'), h('span', { class: 'muted' }, ` (best of ${m.choices} choices)`)];
    if (m.mover === 'controller') return ['controller ', h('strong', {}, m.label), m.choices > 1 ? h('span', { class: 'muted' }, ` (best of ${m.choices} choices)`) : null];
    return [/^[!]/.test(m.label) ? 'plant ' : '', h('strong', {}, m.label)];
  };
  const link = (id) => (onState && id !== 4294967295 ? [' ', actionLink(`→ s${id}`, () => onState(id), { class: 'state-link', 'data-state': id })] : null);
  return h('ol', { class: 'counter-play', id: onState ? 'counter-play' : null },
    play.moves.map((m) => h('li', { class: `mover-${m.mover}` }, who(m), link(m.to))),
    h('li', { class: 'violation' }, `✗ ${play.end}`));
}
