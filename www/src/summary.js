// The Summary tab: verdict, statistics, time, and the explanation of an unrealizable spec.
import { actionLink, h, fmtInt, fmtMs } from './dom.js';
import { counterPlayList } from './simulator.js';

const verdictText = {
  realizable: 'Realizable: a controller exists',
  unrealizable: 'Unrealizable: no controller can meet the spec',
  budget_exceeded: 'Budget exceeded: the search stopped before deciding',
  cancelled: 'Cancelled',
};

/** The explanation tree: one item per move; state ids link to the state space. */
function stepTree(step, onState) {
  const link = actionLink(`s${step.state}`, () => onState(step.state), { class: 'state-link', 'data-state': step.state });
  const head = h('div', { class: 'step' }, step.event ? [h('strong', {}, step.event), ' → '] : 'initially ', step.locations, ' ', link);
  const o = step.outcome;
  if (o.kind === 'violation') return [head, h('div', { class: 'violation' }, `✗ ${o.reason}`)];
  if (o.kind === 'forced') return [head, ...stepTree(o.next, onState)];
  if (o.kind === 'truncated') return [head, h('div', { class: 'muted' }, '… (cut off)')];
  return [
    head,
    h('div', { class: 'muted' }, 'every controller choice fails:'),
    h('ul', { class: 'choices' }, o.branches.map((b) => h('li', {}, stepTree(b, onState)))),
  ];
}

const scanText = {
  realizable: (ms) => `Implementable at ${ms} ms: a PLC with this scan time can meet the spec`,
  unrealizable: (ms) => `Not implementable at ${ms} ms: only a controller reacting faster than a PLC scan can meet the spec`,
  budget_exceeded: (ms) => `At ${ms} ms: budget exceeded before deciding`,
  cancelled: () => 'Cancelled',
};

/** How slow the PLC may be: the neighbouring scan times the bound search solved (text from the engine). */
function boundPart(scan) {
  if (!scan.bound_text) return null;
  const { works, fails } = scan.bound;
  return h('p', { id: 'scan-bound', 'data-works': works ?? '', 'data-fails': fails ?? '' }, `Scan time: ${scan.bound_text}.`);
}

/** The verdict at the declared scan time, or a note that the verdict assumes zero time. */
function scanPart(summary) {
  const scan = summary.scan;
  if (!scan) {
    return summary.verdict === 'realizable'
      ? h('p', { class: 'muted', id: 'zero-time-note' }, 'This verdict assumes a controller that reacts in zero time (the thesis’s semantics). Declare the PLC’s cycle, e.g. `scan 10 ms;`, to decide it for a real PLC.')
      : null;
  }
  return h(
    'section',
    {},
    h('div', { class: `verdict ${scan.verdict}`, id: 'scan-verdict', 'data-verdict': scan.verdict }, scanText[scan.verdict]?.(scan.scan_ms) ?? scan.verdict),
    h('p', { class: 'muted' }, `The scan game: ${fmtInt(scan.stats.visited)} states visited, ${fmtInt(scan.stats.removed)} removed.`),
    boundPart(scan),
    scan.code_from ? h('p', { class: 'muted', id: 'scan-code-from' }, `Code from ${scan.code_from}.`) : null,
    scan.explanation_text
      ? [
          h('h3', {}, `Why a PLC with a ${scan.scan_ms} ms scan cannot do it`),
          h('p', { class: 'muted' }, '`plc` is the scan: it reads at plc.read, decides scan:r or scan:idle, and its output r takes effect at some moment of the scan.'),
          h('pre', { class: 'explanation', id: 'scan-explanation' }, scan.explanation_text),
        ]
      : null,
  );
}

// Which budget stopped the search; only the state budget has a field on the page.
/** `stop` is the engine's `{ stop: 'budget', resource, message }` (src/search.rs). */
function budgetText(stop, maxStates) {
  if (!stop || stop.resource === 'states') {
    return `The search stored more than ${fmtInt(maxStates)} states (the "max states" setting). The statistics so far:`;
  }
  const what = stop.resource === 'memory' ? 'memory' : 'work';
  return `Budget exceeded: ${stop.message} (the ${what} budget of the page). The statistics so far:`;
}

export function renderSummary(root, { summary, ms, expected, maxStates, onState, onReplay }) {
  const s = summary.stats;
  const row = (label, value, id) => h('tr', {}, h('th', {}, label), h('td', { id }, value));
  const parts = [
    h('div', { class: `verdict ${summary.verdict}`, id: 'verdict', 'data-verdict': summary.verdict }, summary.scan && summary.verdict === 'realizable' ? 'Realizable with a zero-time controller' : (verdictText[summary.verdict] ?? summary.verdict)),
    expected && summary.verdict !== 'budget_exceeded'
      ? h('p', { class: 'muted' }, expected === summary.verdict ? `As the example expects (${expected}).` : `The example says it should be ${expected}.`)
      : null,
    summary.verdict === 'budget_exceeded' ? h('p', {}, budgetText(summary.stop, maxStates)) : null,
    scanPart(summary),
    // Why an unrealizable spec is lost comes before the statistics: it is what the user reads.
    summary.explanationText ? whyPart(summary, onState, onReplay) : null,
    h(
      'table',
      { class: 'stats' },
      row('visited states', fmtInt(s.visited), 'stat-visited'),
      row('winning states', fmtInt(s.winning), 'stat-winning'),
      row('removed states', fmtInt(s.removed), 'stat-removed'),
      row('expanded states', fmtInt(s.expanded), 'stat-expanded'),
      row('edges', fmtInt(s.edges), 'stat-edges'),
      row('distinct zones', fmtInt(s.zones), 'stat-zones'),
      row('memory (approx.)', `${(s.bytes / 1048576).toFixed(2)} MiB`, 'stat-bytes'),
      row('work (units)', fmtInt(s.work ?? 0), 'stat-work'),
      row('solve time', fmtMs(summary.ms), 'stat-solve-ms'),
      row('round trip', fmtMs(ms), 'stat-total-ms'),
    ),
  ];
  root.replaceChildren(...parts.filter(Boolean));
}

/** Why an unrealizable spec is lost: one counter-play first (the plant's winning line against
 * the controller that holds out longest: short, and replayable in the simulator), then the
 * whole tree of the explanation, folded (it repeats subtrees and runs to hundreds of lines). */
const TREE_LINES_OPEN = 30;

function whyPart(summary, onState, onReplay) {
  const play = summary.counterPlay;
  const tree = h('div', { class: 'explanation', id: 'explanation' }, stepTree(summary.explanation.root, onState));
  return h(
    'section',
    {},
    // Without a bound (u32::MAX) the plant wins by a cycle without plan progress, not by a
    // finite line of moves, and there is no counter-play.
    h('h3', {}, summary.explanation_depth >= 4294967295 ? 'Why: every controller choice fails; the plant can keep the plans from progressing' : `Why: the plant can force a failure within ${summary.explanation_depth} moves`),
    play
      ? [
          h('p', { class: 'muted' }, 'One line of play: at each choice the controller takes the move that fails last, and the plant its winning answer. Click a state to inspect it.'),
          h('div', { class: 'explanation' }, counterPlayList(play, onState)),
          h('p', {}, h('button', { id: 'replay-counter-play', onclick: () => onReplay?.() }, '▶ Replay in the simulator')),
        ]
      : null,
    h(
      'details',
      // A short tree stays open; a long one (two robots in 13 s: over 300 lines) is folded.
      { id: 'explanation-tree', open: !play || summary.explanationText.split('\n').length <= TREE_LINES_OPEN },
      h('summary', {}, 'The whole tree: every controller choice, each shown failing'),
      h('p', { class: 'muted' }, 'Each line is a move from the initial state; where the controller has choices, every one of them is shown failing. Click a state to inspect it.'),
      tree,
    ),
  );
}
