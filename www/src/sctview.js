// Supervisory control in the page: the synthesis report (Summary tab) and the drawings of plant
// models, specifications and supervisors per module (Automata tab).
import { h, fmtInt, fmtMs } from './dom.js';
import { drawInto } from './graphs.js';

/** The verdicts of `sct::Verdict`, in words. */
const verdictText = {
  realizable: (n) => `Realizable: ${n} supervisor${n === 1 ? '' : 's'} synthesised, each with a non-empty behaviour`,
  unrealizable: () => 'Unrealizable: a specification has no supervisor (its initial state is lost)',
  budget_exceeded: () => 'Budget exceeded: synthesis stopped before every specification was synthesised',
  cancelled: () => 'Cancelled',
  error: () => 'Synthesis found errors in the project (see below)',
};

/** A diagnostic as a button that puts the editor's cursor on its location. */
function diagnosticLink(d, onLocate) {
  return h(
    'button',
    { class: 'diag', onclick: () => onLocate(d.line, d.column) },
    h('span', { class: `diag-${d.severity}` }, d.severity),
    ` line ${d.line}:${d.column}  ${d.message}`,
    ...d.notes.map((n) => h('span', { class: 'muted' }, ` — ${n}`)),
  );
}

export function renderSctSummary(root, { summary, ms, expected, onLocate }) {
  // Decided by the engine (sct::Verdict): every supervisor realizable, one not, stopped or an error.
  const verdict = summary.verdict;
  const n = summary.supervisors.length;
  const list = (items) => (items.length ? items.join(', ') : '—');
  const rows = summary.supervisors.map((s) =>
    h(
      'tr',
      { 'data-supervisor': s.name },
      h('td', {}, s.name),
      h('td', {}, s.realizable ? 'yes' : h('strong', { class: 'reason' }, 'NO')),
      h('td', { class: 'num' }, fmtInt(s.states)),
      h('td', { class: 'num' }, fmtInt(s.transitions)),
      h('td', { class: 'num' }, fmtInt(s.prohibitions)),
      h('td', {}, list(s.prohibited_events)),
      h('td', {}, list(s.enforced_events)),
      h('td', { class: 'num' }, s.millis.toFixed(2)),
    ),
  );
  root.replaceChildren(
    ...[
      h('div', { class: `verdict ${verdict}`, id: 'verdict', 'data-verdict': verdict }, verdictText[verdict](n)),
      expected && (verdict === 'realizable' || verdict === 'unrealizable')
        ? h('p', { class: 'muted' }, expected === verdict ? `As the example expects (${expected}).` : `The example says it should be ${expected}.`)
        : null,
      h('p', { class: 'muted' }, `${summary.method === 'monolithic' ? 'Monolithic' : 'Incremental'} synthesis (Göbe 2019, 5.8): ${fmtInt(summary.states_built)} product states built in ${fmtMs(summary.ms)} (round trip ${fmtMs(ms)}). The Automata tab draws every supervisor; the Code tab generates the runtime framework.`),
      h(
        'table',
        { class: 'report', id: 'sct-report' },
        h('thead', {}, h('tr', {}, ['supervisor', 'realizable', 'states', 'transitions', 'prohibitions', 'prohibited events', 'enforced events', 'ms'].map((t) => h('th', {}, t)))),
        h('tbody', {}, rows),
      ),
      summary.diagnostics.length
        ? h(
            'section',
            { id: 'sct-diagnostics' },
            h('h3', {}, 'Found during synthesis'),
            h('p', { class: 'muted' }, 'Conflicting conditional transitions (6.4.4), cycles of enforced events (5.5.5), and an event one supervisor enforces while another prohibits it (6.4.2). Click to go to the source.'),
            h('div', { class: 'diagnostics' }, summary.diagnostics.map((d) => diagnosticLink(d, onLocate))),
          )
        : null,
    ].filter(Boolean),
  );
}

const kindTitle = { plant: 'plant', spec: 'specification', supervisor: 'supervisor' };

/** The Automata tab of supervisory control: a module picker and the drawings of the chosen
 * module, supervisors first (once synthesised), then plants and specifications. */
export class SctAutomataView {
  constructor(root) {
    this.root = root;
    this.models = [];
    this.supervisors = [];
    this.module = null;
    this.token = 0;
  }

  /** New drawings; `supervisors` may follow later. */
  load(models, supervisors = []) {
    this.models = models ?? [];
    this.supervisors = supervisors ?? [];
    this.drawn = false;
  }

  get all() {
    return [...this.supervisors, ...this.models];
  }

  async draw() {
    if (this.drawn) return;
    this.drawn = true;
    const token = ++this.token;
    const all = this.all;
    const modules = [...new Set(all.map((a) => a.module))].sort();
    if (this.module !== null && !modules.includes(this.module)) this.module = null;
    const picker = h(
      'select',
      { id: 'sct-module', 'aria-label': 'module', onchange: (e) => ((this.module = e.target.value === '*' ? null : e.target.value), (this.drawn = false), this.draw()) },
      h('option', { value: '*' }, `all modules (${all.length} automata)`),
      modules.map((m) => h('option', { value: m, selected: m === this.module }, m === '' ? '(top level)' : m)),
    );
    const shown = all.filter((a) => this.module === null || a.module === this.module);
    this.root.replaceChildren(
      h('div', { class: 'toolbar' }, h('label', {}, 'module ', picker), h('span', { class: 'muted' }, this.supervisors.length ? '' : 'Run to add the supervisors.')),
      h(
        'div',
        { class: 'legend' },
        h('span', { class: 'l-controllable' }, 'controllable'),
        h('span', { class: 'l-uncontrollable' }, 'uncontrollable (dashed)'),
        h('span', { class: 'l-enforceable' }, 'enforceable'),
        h('span', { class: 'l-enforced' }, 'enforced by the supervisor (bold, ⇒)'),
        h('span', { class: 'l-prohibits' }, '✕ prohibited in this state'),
        h('span', { class: 'l-plain' }, '[condition] on plant states'),
      ),
    );
    for (const a of shown) {
      const section = h(
        'section',
        { class: 'automaton', 'data-name': a.name, 'data-kind': a.kind },
        h('h3', {}, a.name, ' ', h('span', { class: 'muted' }, `${kindTitle[a.kind]} · ${fmtInt(a.states)} states, ${fmtInt(a.transitions)} transitions`)),
      );
      this.root.append(section);
      if (a.states > 400) {
        section.append(h('p', { class: 'muted' }, 'Too large to draw; the Code tab and the report list it.'));
        continue;
      }
      await drawInto(section, a.dot, a.name);
      if (token !== this.token) return;
    }
  }

  clear(message) {
    this.token++;
    this.models = [];
    this.supervisors = [];
    this.drawn = false;
    this.root.replaceChildren(h('p', { class: 'muted' }, message));
  }
}
