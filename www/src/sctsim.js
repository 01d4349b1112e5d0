// Supervisory control: the stepper (the closed loop of plants and supervisors, event by event,
// as DESTool's animation) and the runtime-cycle simulator (the generated framework run cycle by
// cycle on signal values). Both positions are pure functions of what the user did — the events
// fired, the cycles run — so the page keeps only that and asks the engine for the view: back is
// dropping the last entry.
import { h, toast } from './dom.js';

const statusText = {
  enabled: () => 'enabled',
  enforced: (e) => `enforced by ${e.by}`,
  unexpected: (e) => `possible, but ${e.by} prohibits it (its plant assumptions break)`,
  disabled: (e) => `disabled by ${e.by}`,
  impossible: (e) => `impossible in plant ${e.plant}`,
  not_enforced: () => 'not enforced here',
};
const fireable = new Set(['enabled', 'enforced', 'unexpected']);

export class SctSimulator {
  /** `query(method, args)` asks the solver worker; the boxes are the two panels. */
  constructor({ query, stepBox, cyclesBox }) {
    this.query = query;
    this.stepBox = stepBox;
    this.cyclesBox = cyclesBox;
    this.reset();
  }

  /** A new synthesis (or none): both simulations start over; `why` says why they cannot run. */
  reset(ready = false, why = 'Run the project first: the stepper and the simulator use its supervisors.') {
    this.ready = ready;
    this.trace = [];
    this.cycles = [];
    this.next = { elapsed_ms: 100, inputs: {}, controller: {} };
    this.showImpossible = false;
    const none = why;
    this.stepBox.replaceChildren(h('p', { class: 'muted' }, none));
    this.cyclesBox.replaceChildren(h('p', { class: 'muted' }, none));
  }

  // ---- the stepper ----------------------------------------------------------------------

  async showStepper() {
    if (!this.ready) return;
    let view;
    try {
      view = await this.query('step', [this.trace]);
    } catch (error) {
      // A trace can only hold fireable events; keep the page usable whatever happened.
      this.trace.pop();
      return toast(`${error.message ?? error}`);
    }
    const row = (name, state, extra = null) => h('tr', {}, h('th', {}, name), h('td', { class: 'sct-state' }, state), extra ? h('td', { class: 'muted' }, extra) : null);
    const events = view.events.filter((e) => this.showImpossible || e.status !== 'impossible');
    const hidden = view.events.length - events.length;
    this.stepBox.replaceChildren(
      h('p', { class: 'muted' }, 'The plants and supervisors in closed loop, event by event. Click an event to fire it; controllable events a supervisor prohibits are disabled, enforceable events fire where a supervisor enforces them.'),
      h(
        'div',
        { class: 'sct-columns' },
        h(
          'section',
          {},
          h('h3', {}, 'Plants'),
          h('table', { class: 'report', id: 'step-plants' }, view.plants.map((p) => row(p.name, p.state))),
          h('h3', {}, 'Supervisors'),
          h(
            'table',
            { class: 'report', id: 'step-supervisors' },
            view.supervisors.map((s) => row(s.name, s.state, [s.prohibits.length ? `✕ ${s.prohibits.join(', ')}` : '', s.enforces ? ` ⇒ ${s.enforces}` : ''].join('').trim() || null)),
          ),
        ),
        h(
          'section',
          {},
          h('h3', {}, 'Events'),
          h(
            'ul',
            { class: 'sct-events', id: 'step-events' },
            events.map((e) =>
              h(
                'li',
                {},
                h(
                  'button',
                  {
                    class: `sct-event ${e.status} ev-${e.kind}`,
                    'data-event': e.name,
                    'data-status': e.status,
                    disabled: !fireable.has(e.status),
                    title: statusText[e.status](e),
                    onclick: () => this.fire(e.name),
                  },
                  e.name,
                ),
                h('span', { class: 'muted' }, ` ${e.kind} · ${statusText[e.status](e)}`),
              ),
            ),
          ),
          h('label', { class: 'muted' }, h('input', { type: 'checkbox', id: 'step-impossible', checked: this.showImpossible, onchange: (ev) => ((this.showImpossible = ev.target.checked), this.showStepper()) }), ` show the ${hidden || ''} events the plants rule out`.replace('  ', ' ')),
        ),
        h(
          'section',
          {},
          h('h3', {}, 'Trace'),
          h(
            'div',
            { class: 'toolbar' },
            h('button', { id: 'step-back', disabled: !this.trace.length, onclick: () => (this.trace.pop(), this.showStepper()) }, '◀ Back'),
            h('button', { id: 'step-reset', disabled: !this.trace.length, onclick: () => ((this.trace = []), this.showStepper()) }, 'Reset'),
          ),
          this.trace.length
            ? h(
                'ol',
                { class: 'sct-trace', id: 'step-trace' },
                this.trace.map((e, i) => h('li', {}, h('a', { href: '#', title: 'go back to after this event', onclick: (ev) => (ev.preventDefault(), (this.trace = this.trace.slice(0, i + 1)), this.showStepper()) }, e))),
              )
            : h('p', { class: 'muted', id: 'step-trace' }, 'Nothing fired yet: every automaton is in its initial state.'),
        ),
      ),
    );
  }

  fire(event) {
    this.trace.push(event);
    return this.showStepper();
  }

  // ---- the runtime-cycle simulator --------------------------------------------------------

  async showCycles() {
    if (!this.ready) return;
    let run;
    try {
      run = await this.query('cycles', [this.cycles]);
    } catch (error) {
      this.cycles.pop();
      const why = error?.diagnostics ? error.diagnostics.map((d) => `line ${d.line}: ${d.message}`).join('; ') : (error.message ?? error);
      return this.cyclesBox.replaceChildren(h('p', { class: 'reason' }, `The framework cannot run: ${why}`));
    }
    if (!run) return this.cyclesBox.replaceChildren(h('p', { class: 'muted' }, 'No framework: synthesis did not complete.'));
    const last = run.cycles.at(-1) ?? run.initial;
    const inputs = run.initial.signals.filter((s) => s.kind === 'input');
    const outputs = run.initial.signals.filter((s) => s.kind === 'output');
    const field = (s, into, current) => {
      const value = this.next[into][s.symbol] ?? current;
      const set = (v) => (this.next[into][s.symbol] = v);
      return s.data_type === 'BOOL'
        ? h('label', { class: 'sct-signal' }, h('input', { type: 'checkbox', 'data-signal': s.symbol, 'data-into': into, checked: Boolean(value), onchange: (ev) => set(ev.target.checked ? 1 : 0) }), ` ${s.symbol}`)
        : h('label', { class: 'sct-signal' }, `${s.symbol} `, h('input', { type: 'number', 'data-signal': s.symbol, 'data-into': into, value: String(value), onchange: (ev) => set(Number(ev.target.value) || 0) }));
    };
    const signalNow = (symbol) => last.signals.find((s) => s.symbol === symbol)?.value ?? 0;
    const eventText = (e) => `${{ accepted: '✓', denied: '✗', occurred: '•', enforced: '⇒' }[e.what]} ${e.event} ${e.what}${e.by ? ` by ${e.by}` : ''}`;
    this.cyclesBox.replaceChildren(
      h('p', { class: 'muted' }, 'The generated runtime framework, run cycle by cycle (the code you download, in the reference interpreter): set the plant’s inputs and what the existing controller writes, then run a cycle. A denied event’s outputs are reset; an enforced event’s action runs.'),
      h(
        'div',
        { class: 'sct-columns' },
        h('section', {}, h('h3', {}, 'Plant inputs'), inputs.length ? inputs.map((s) => field(s, 'inputs', signalNow(s.symbol))) : h('p', { class: 'muted' }, 'none')),
        h('section', {}, h('h3', {}, 'The controller writes'), outputs.length ? outputs.map((s) => field(s, 'controller', this.cycles.at(-1)?.controller[s.symbol] ?? 0)) : h('p', { class: 'muted' }, 'none')),
        h(
          'section',
          {},
          h('h3', {}, 'Cycle'),
          h('label', {}, 'time since the last cycle ', h('input', { type: 'number', id: 'cycle-ms', min: '0', value: String(this.next.elapsed_ms), onchange: (ev) => (this.next.elapsed_ms = Math.max(0, Number(ev.target.value) || 0)) }), ' ms'),
          h(
            'div',
            { class: 'toolbar' },
            h('button', { id: 'cycle-run', class: 'primary', onclick: () => this.runCycle() }, '▶ Run a cycle'),
            h('button', { id: 'cycle-back', disabled: !this.cycles.length, onclick: () => (this.cycles.pop(), this.showCycles()) }, '◀ Back'),
            h('button', { id: 'cycle-reset', disabled: !this.cycles.length, onclick: () => ((this.cycles = []), (this.next = { elapsed_ms: this.next.elapsed_ms, inputs: {}, controller: {} }), this.showCycles()) }, 'Reset'),
          ),
        ),
      ),
      h(
        'table',
        { class: 'report', id: 'cycle-table' },
        h('thead', {}, h('tr', {}, ['cycle', 'time', 'events', 'supervisors', 'outputs to the plant', 'timers'].map((t) => h('th', {}, t)))),
        h(
          'tbody',
          {},
          [run.initial, ...run.cycles].map((c) =>
            h(
              'tr',
              { 'data-cycle': c.cycle },
              h('td', { class: 'num' }, c.cycle === 0 ? 'start' : String(c.cycle)),
              h('td', { class: 'num' }, `${c.time_ms} ms`),
              h('td', {}, c.events.length ? c.events.map((e) => h('div', { class: `sct-outcome ${e.what}` }, eventText(e))) : '—'),
              h('td', {}, c.supervisors.map((s) => h('div', {}, `${s.name}: `, h('strong', {}, s.state), s.prohibits.length ? h('span', { class: 'muted' }, ` ✕ ${s.prohibits.join(', ')}`) : ''))),
              h(
                'td',
                {},
                c.signals
                  .filter((s) => s.kind === 'output')
                  .map((s) => {
                    const reset = s.written !== null && s.written !== s.value;
                    return h('div', { class: reset ? 'sct-reset' : '', 'data-output': s.symbol, 'data-reset': String(reset) }, `${s.symbol} = ${s.value}`, reset ? h('span', { class: 'reason' }, ` (the controller wrote ${s.written}: changed by the framework)`) : '');
                  }),
              ),
              h('td', {}, c.timers.length ? c.timers.map((t) => h('div', {}, `${t.name}: ${t.expired ? 'expired' : t.running ? 'running' : 'idle'}`)) : '—'),
            ),
          ),
        ),
      ),
    );
  }

  runCycle() {
    // Inputs keep their values from cycle to cycle; the controller writes its outputs in every cycle.
    const previous = this.cycles.at(-1);
    this.cycles.push({
      elapsed_ms: this.next.elapsed_ms,
      inputs: { ...this.next.inputs },
      controller: { ...(previous?.controller ?? {}), ...this.next.controller },
    });
    this.next.inputs = {};
    this.next.controller = {};
    return this.showCycles();
  }
}
