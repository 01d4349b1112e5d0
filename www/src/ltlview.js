// LTL synthesis in the page: the verdict with the specification as decided, what refinement
// learned, the compositional groups, the assumption suggestions of an unrealizable
// specification (each can be added to the text), the counter-strategy as a tree, and the
// controller or counter-strategy as a Mealy machine (Automata tab).
import { h, fmtInt, fmtMs } from './dom.js';
import { drawInto } from './graphs.js';

const verdictText = {
  realizable: 'Realizable: a controller exists',
  unrealizable: 'Unrealizable: the environment has a counter-strategy',
  unknown: 'Unknown: no player won within the bound',
  budget_exceeded: 'Budget exceeded: the search stopped before deciding',
  cancelled: 'Cancelled before deciding',
};

/**
 * Adds `assumption` (LTL in the engine's notation) to a specification of `kind`: a line
 * `ASSUME …` for G4LTL's lines, an entry of the ASSUMPTIONS block of MAIN for TLSF (the block is
 * created before GUARANTEES when missing). Returns the new text.
 */
export function addAssumption(text, kind, assumption) {
  if (kind !== 'tlsf') return `${text.replace(/\s*$/, '')}\nASSUME ${assumption}\n`;
  const block = text.match(/\b(ASSUMPTIONS|ASSUME)\s*\{/);
  if (block) {
    const at = block.index + block[0].length;
    return `${text.slice(0, at)}\n    ${assumption};${text.slice(at)}`;
  }
  const guarantees = text.match(/^([ \t]*)(GUARANTEES|GUARANTEE)\s*\{/m);
  if (guarantees) {
    const indent = guarantees[1];
    return `${text.slice(0, guarantees.index)}${indent}ASSUMPTIONS {\n${indent}  ${assumption};\n${indent}}\n${text.slice(guarantees.index)}`;
  }
  throw new Error('the TLSF text has no GUARANTEES block to put the assumption before');
}

export function renderLtlSummary(root, { summary, ms, expected, onAddAssumption }) {
  const report = summary.report;
  const parts = [
    h('div', { class: `verdict ${summary.verdict}`, id: 'verdict', 'data-verdict': summary.verdict }, verdictText[summary.verdict] ?? summary.verdict),
    expected && !summary.stop && summary.verdict !== 'unknown'
      ? h('p', { class: 'muted' }, expected === summary.verdict ? `As the example expects (${expected}).` : `The example says it should be ${expected}.`)
      : null,
    h('p', { id: 'ltl-summary' }, summary.summary, h('span', { class: 'muted', id: 'ltl-solver-used' }, ` · ${summary.solver} solver · ${fmtMs(summary.ms)} (round trip ${fmtMs(ms)})`)),
    report.ltl ? h('p', { class: 'muted' }, 'Specification as decided: ', h('code', {}, report.ltl)) : null,
    report.inputs ? h('p', { class: 'muted' }, `Inputs: ${report.inputs.join(', ') || '—'} · outputs: ${report.outputs.join(', ') || '—'}${report.semantics ? ` · ${report.semantics} semantics` : ''}`) : null,
    report.learned?.length
      ? h('section', {}, h('h3', {}, 'Learned from counter-strategies (refinement)'), h('ul', {}, report.learned.map((l) => h('li', {}, h('code', {}, `ASSUME ${l.formula}`), h('span', { class: 'muted' }, ` — ${l.reason}`)))))
      : null,
    summary.groups.length
      ? h(
          'section',
          { id: 'ltl-groups' },
          h('h3', {}, `Compositional: ${summary.groups.length} groups of guarantees, each with its own outputs, solved alone`),
          h(
            'table',
            { class: 'report' },
            h('thead', {}, h('tr', {}, ['group', 'guarantees', 'writes', 'states', 'k'].map((t) => h('th', {}, t)))),
            h('tbody', {}, summary.groups.map((g, i) => h('tr', {}, h('td', {}, String(i + 1)), h('td', {}, g.guarantees.join(', ')), h('td', {}, g.outputs.join(', ')), h('td', { class: 'num' }, fmtInt(g.states)), h('td', { class: 'num' }, String(g.k))))),
          ),
          h('p', { class: 'muted' }, 'The controller is the groups’ machines run side by side.'),
        )
      : null,
    suggestionsPart(summary, onAddAssumption),
    summary.counter_tree
      ? h(
          'section',
          {},
          h('h3', {}, 'How the environment wins'),
          h('p', { class: 'muted' }, 'Its counter-strategy unfolded from the initial state: what it sets, and where each answer of the controller leads. A state reached again closes a loop (a lasso).'),
          h('pre', { class: 'explanation', id: 'counter-tree' }, summary.counter_tree),
        )
      : null,
    summary.circuit_text
      ? h(
          'section',
          { id: 'ltl-circuit' },
          h('h3', {}, 'The controller as a circuit (its function block is the code)'),
          h('p', { class: 'muted' }, 'Latches remember what the monitors of the guarantees need; the controller pursues one goal (a guarantee’s “infinitely often”) at a time, and each output is a Boolean function of the latches and the inputs of the scan.'),
          h('pre', { class: 'code', id: 'circuit-text' }, summary.circuit_text),
        )
      : null,
    summary.machine_text
      ? h(
          'section',
          {},
          h('h3', {}, summary.verdict === 'realizable' ? 'The controller (state: inputs / outputs → next)' : 'The counter-strategy (state: inputs it sets / outputs it reads → next)'),
          h('pre', { class: 'code', id: 'machine-text' }, summary.machine_text),
        )
      : null,
  ];
  root.replaceChildren(...parts.filter(Boolean));
}

function suggestionsPart(summary, onAddAssumption) {
  if (summary.verdict !== 'unrealizable') return null;
  const s = summary.suggestions;
  if (!s) {
    return h(
      'section',
      { id: 'suggestions' },
      h('h3', {}, 'Assumption suggestions'),
      summary.suggest_stopped ? h('p', { class: 'muted' }, `The search stopped: ${summary.suggest_stopped}`) : h('p', { class: 'muted' }, 'Tick “suggest assumptions” and run again to search for assumptions on the environment that make the specification realizable.'),
    );
  }
  return h(
    'section',
    { id: 'suggestions' },
    h('h3', {}, 'Assumption suggestions'),
    s.play ? h('p', { class: 'muted' }, `The longest play the counter-strategy forces: ${s.play}`) : null,
    h('p', { class: 'muted' }, `${fmtInt(s.candidates)} candidates from the templates, ${fmtInt(s.tried)} re-syntheses.`),
    s.found.length
      ? h(
          'ol',
          { class: 'suggestions' },
          s.found.map((f, i) =>
            h(
              'li',
              { 'data-suggestion': i },
              f.assumptions.map((a) => h('code', {}, `ASSUME ${a}`)),
              h('span', { class: 'muted' }, ` (template ${f.template}) → a controller of ${f.states} states at k = ${f.k} `),
              h('button', { class: 'add-assumption', title: 'Add these assumptions to the specification', onclick: () => onAddAssumption(f.assumptions) }, 'Add to the spec'),
            ),
          ),
        )
      : h('p', {}, `None found: ${s.limit ?? 'no candidate made the specification realizable'}.`),
  );
}

/** The Automata tab of LTL: the controller or counter-strategy as a Mealy machine. */
export async function drawMachine(root, summary) {
  if (!summary?.machine_dot) {
    const why = summary?.circuit_text ? 'the controller is a circuit (in the Summary), its table too large to draw' : summary?.stop ? 'the search stopped before deciding' : summary?.verdict === 'unknown' ? 'the verdict is unknown' : 'it was not built';
    root.replaceChildren(h('p', { class: 'muted' }, summary ? `No machine: ${why}.` : 'Run the specification to see its controller as a Mealy machine.'));
    return;
  }
  const title = summary.verdict === 'realizable' ? 'The controller as a Mealy machine' : 'The environment’s counter-strategy';
  const note = summary.verdict === 'realizable' ? 'Each edge: the inputs read / the outputs written in that step.' : 'Each edge: one step, the signals of the side that moves first before the slash.';
  const section = h('section', { class: 'automaton', 'data-name': 'machine' }, h('h3', {}, title), h('p', { class: 'muted' }, note));
  root.replaceChildren(section);
  await drawInto(section, summary.machine_dot, 'it');
}
