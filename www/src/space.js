// The State space tab: a searchable, filterable state list beside a graph. Up to
// FULL_LIMIT states the whole explored space is drawn; beyond, the k-step neighbourhood of
// the selected state. Selecting a state (list or graph) calls `onSelect(id)`.
import { $, h, fmtInt } from './dom.js';
import { spaceDot, render } from './graphs.js';

export const FULL_LIMIT = 300;
const LIST_LIMIT = 500;
const HOOD_LIMIT = 150;

export class SpaceView {
  constructor({ query, onSelect }) {
    this.query = query;
    this.onSelect = onSelect;
    this.reset(null);
    let timer = 0;
    $('#state-search').addEventListener('input', () => {
      clearTimeout(timer);
      timer = setTimeout(() => this.refreshList(), 200);
    });
    $('#state-filter').addEventListener('change', () => this.refreshList());
    $('#hood-k').addEventListener('change', () => this.drawGraph());
    $('#fit-graph').addEventListener('change', () => ((this.fitChosen = true), this.fit()));
  }

  /** A new run: `meta` is a one-state SpaceView (clocks, units, initial, total_states) or null. */
  reset(meta) {
    this.meta = meta;
    this.strategy = null;
    this.full = null;
    this.selected = null;
    this.drawn = null;
    this.token = (this.token ?? 0) + 1;
    $('#state-list').replaceChildren();
    $('#space-note').textContent = '';
    if (!meta) $('#space-graph').replaceChildren(h('p', { class: 'muted' }, 'Run the spec to see its state space.'));
  }

  get big() {
    return this.meta && this.meta.total_states > FULL_LIMIT;
  }

  /** `strategy`: the engine's strategy choices, or null without a controller. */
  async load(meta, strategy) {
    this.reset(meta);
    this.strategy = strategy ? new Map(strategy.map((c) => [c.state, c])) : null;
    $('#hood-label').hidden = !this.big;
    if (!this.big) this.full = await this.query('space', [FULL_LIMIT]);
    this.selected = meta.initial;
    await Promise.all([this.refreshList(), this.drawGraph()]);
  }

  async refreshList() {
    if (!this.meta) return;
    const token = this.token;
    const text = $('#state-search').value;
    const filter = $('#state-filter').value;
    const found = await this.query('states', [text, filter, LIST_LIMIT]);
    if (token !== this.token) return;
    const items = found.rows.map((r) =>
      h(
        'li',
        {
          class: r.winning ? 'winning' : 'removed',
          'data-id': r.id,
          'aria-selected': String(r.id === this.selected),
          title: r.text,
          onclick: () => this.select(r.id),
        },
        `s${r.id}${r.initial ? ' (initial)' : ''}: ${r.text}`,
      ),
    );
    if (found.total > found.rows.length) items.push(h('li', { class: 'more' }, `… ${fmtInt(found.total - found.rows.length)} more: refine the search`));
    $('#state-list').replaceChildren(...items);
    const what = this.big ? `neighbourhood of the selected state (${fmtInt(this.meta.total_states)} states in all)` : `all ${fmtInt(this.meta.total_states)} states`;
    $('#space-note').textContent = `${fmtInt(found.total)} match · graph: ${what}`;
  }

  async drawGraph() {
    if (!this.meta) return;
    const token = this.token;
    const box = $('#space-graph');
    let view = this.full;
    if (this.big) {
      view = await this.query('neighbourhood', [this.selected, Number($('#hood-k').value), HOOD_LIMIT]);
      if (token !== this.token) return;
    }
    let svg;
    try {
      svg = await render(spaceDot(view, { selected: this.selected, strategy: this.strategy }));
    } catch (error) {
      box.replaceChildren(h('p', { class: 'reason' }, `Graphviz could not draw the graph: ${error.message ?? error}`));
      return;
    }
    if (token !== this.token) return;
    svg.querySelectorAll('g.state').forEach((g) => {
      const id = Number(g.id.replace('st-', ''));
      g.addEventListener('click', () => this.select(id));
    });
    this.drawn = svg;
    const cut = view.truncated ? h('p', { class: 'muted' }, `Showing ${view.states.length} states; the neighbourhood is larger.`) : null;
    box.replaceChildren(cut ?? '', svg);
    // Until the user decides: fit the width when that keeps the text legible, else scroll.
    if (!this.fitChosen) {
      const natural = svg.width.baseVal.value;
      $('#fit-graph').checked = natural > 0 && box.clientWidth / natural >= 0.55;
    }
    this.fit();
    this.markSelected();
  }

  fit() {
    if (!this.drawn) return;
    const on = $('#fit-graph').checked;
    this.drawn.style.maxWidth = on ? '100%' : '';
    this.drawn.style.height = on ? 'auto' : '';
  }

  markSelected() {
    document.querySelectorAll('#state-list li').forEach((li) => li.setAttribute('aria-selected', String(Number(li.dataset.id) === this.selected)));
    this.drawn?.querySelectorAll('g.state').forEach((g) => g.classList.toggle('selected', g.id === `st-${this.selected}`));
    const g = this.drawn?.querySelector(`#st-${this.selected}`);
    g?.scrollIntoView?.({ block: 'nearest', inline: 'nearest' });
  }

  async select(id) {
    this.selected = id;
    this.markSelected();
    await this.onSelect(id);
    if (this.big) await this.drawGraph();
  }
}
