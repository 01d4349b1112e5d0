// The State space tab: a searchable, filterable state list beside a graph. Up to
// FULL_LIMIT states the whole explored space is drawn; beyond, the k-step neighbourhood of
// the selected state. Selecting a state (list or graph) calls `onSelect(id)`.
//
// The graph zooms (buttons, Ctrl/⌘+wheel, or *fit*: the whole drawing in its box) and pans
// (scrollbars, or dragging); the selected state is scrolled into view.
//
// Keyboard: every state of the list and of the graph is a Tab stop (a listbox option, an SVG
// button) with a spoken name; Enter or Space selects it; in the list the arrows, Home and End
// move between states.
import { $, h, fmtInt } from './dom.js';
import { render } from './graphs.js';

export const FULL_LIMIT = 300;
const LIST_LIMIT = 500;
const HOOD_LIMIT = 150;
const ZOOM_STEP = 1.25;
const [MIN_ZOOM, MAX_ZOOM] = [0.05, 4];
/** Below this scale Graphviz's 10-point labels are hard to read: a drawing that would need it
 * to fit opens at 100 % and scrolls instead (until the user decides with *fit*). */
const LEGIBLE = 0.55;
/** A press that moves less than this (pixels) is a click, not a drag. */
const DRAG_SLOP = 4;

/** Enter and Space act as a click on an element that is not a native button. */
const onActivate = (action) => (e) => {
  if (e.key !== 'Enter' && e.key !== ' ') return;
  e.preventDefault(); // Space would scroll
  action();
};

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
    $('#state-list').addEventListener('keydown', (e) => {
      const items = [...document.querySelectorAll('#state-list li[data-id]')];
      const at = items.indexOf(document.activeElement);
      const to = { ArrowDown: at + 1, ArrowUp: at - 1, Home: 0, End: items.length - 1 }[e.key];
      if (at < 0 || to === undefined || !items[to]) return;
      e.preventDefault();
      items[to].focus();
    });
    $('#hood-k').addEventListener('change', () => this.drawGraph());
    this.zoom = 1;
    this.wirePanZoom();
  }

  wirePanZoom() {
    const box = $('#space-graph');
    // Zooming by hand ends fitting: the user has chosen a scale.
    const zoomTo = (zoom, at) => {
      this.fitChosen = true;
      $('#fit-graph').checked = false;
      this.setZoom(zoom, at);
    };
    $('#zoom-in').addEventListener('click', () => zoomTo(this.zoom * ZOOM_STEP));
    $('#zoom-out').addEventListener('click', () => zoomTo(this.zoom / ZOOM_STEP));
    $('#zoom-reset').addEventListener('click', () => zoomTo(1));
    $('#fit-graph').addEventListener('change', () => {
      this.fitChosen = true;
      if ($('#fit-graph').checked) this.setZoom(this.fitZoom());
      else {
        this.setZoom(1);
        this.reveal();
      }
    });
    // Ctrl+wheel (and a trackpad's pinch, which Chromium and Firefox send as one) zooms about
    // the pointer instead of zooming the page; a plain wheel scrolls as usual.
    box.addEventListener(
      'wheel',
      (e) => {
        if (!(e.ctrlKey || e.metaKey) || !this.drawn) return;
        e.preventDefault();
        const pixels = e.deltaY * (e.deltaMode === 1 ? 16 : e.deltaMode === 2 ? box.clientHeight : 1);
        const r = box.getBoundingClientRect();
        zoomTo(this.zoom * Math.exp(-pixels * 0.002), { x: e.clientX - r.left - box.clientLeft, y: e.clientY - r.top - box.clientTop });
      },
      { passive: false },
    );
    // Dragging pans. The pointer is captured only once it has moved, so that a click on a
    // state still reaches the state; the click that ends a drag is swallowed.
    let drag = null;
    box.addEventListener('pointerdown', (e) => {
      this.dragged = false;
      // Touch and pen pan natively (the box scrolls).
      if (e.button !== 0 || e.pointerType !== 'mouse' || !this.drawn) return;
      // A press on a scrollbar moves it, as usual (it is outside the client area).
      const r = box.getBoundingClientRect();
      if (e.clientX - r.left - box.clientLeft >= box.clientWidth || e.clientY - r.top - box.clientTop >= box.clientHeight) return;
      drag = { id: e.pointerId, x: e.clientX, y: e.clientY, left: box.scrollLeft, top: box.scrollTop, moving: false };
    });
    box.addEventListener('pointermove', (e) => {
      if (!drag || e.pointerId !== drag.id) return;
      const [dx, dy] = [e.clientX - drag.x, e.clientY - drag.y];
      if (!drag.moving) {
        if (Math.hypot(dx, dy) < DRAG_SLOP) return;
        drag.moving = true;
        box.setPointerCapture(e.pointerId);
        box.classList.add('panning');
      }
      box.scrollLeft = drag.left - dx;
      box.scrollTop = drag.top - dy;
    });
    const end = (e) => {
      if (!drag || e.pointerId !== drag.id) return;
      this.dragged = drag.moving;
      box.classList.remove('panning');
      drag = null;
    };
    box.addEventListener('pointerup', end);
    box.addEventListener('pointercancel', end);
    box.addEventListener(
      'click',
      (e) => {
        if (!this.dragged) return;
        this.dragged = false;
        e.stopPropagation();
      },
      true,
    );
    // The box has no size while its tab is hidden (a run ends on the Summary tab): the drawing
    // is sized and the selected state scrolled to once it has one, and refitted when it changes.
    new ResizeObserver(() => {
      if (!box.clientWidth || !this.drawn) return;
      if (this.pendingLayout) this.layout();
      else if ($('#fit-graph').checked) this.setZoom(this.fitZoom());
    }).observe(box, { box: 'border-box' });
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
    $('#graph-cut').hidden = true;
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
          role: 'option',
          tabindex: 0,
          'aria-selected': String(r.id === this.selected),
          // Said aloud: winning or removed is otherwise only the colour of the border.
          'aria-label': `s${r.id} ${r.winning ? 'winning' : 'removed'}${r.initial ? ', initial' : ''}: ${r.text}`,
          title: r.text,
          onclick: () => this.select(r.id),
          onkeydown: onActivate(() => this.select(r.id)),
        },
        `s${r.id}${r.initial ? ' (initial)' : ''}: ${r.text}`,
      ),
    );
    if (found.total > found.rows.length) items.push(h('li', { class: 'more', role: 'option', 'aria-disabled': 'true' }, `… ${fmtInt(found.total - found.rows.length)} more: refine the search`));
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
      // The engine draws the view (`timed::export::space_dot`): classes, the strategy's
      // requests, the ids `st-<n>` the handlers below look up.
      svg = await render(view.dot);
    } catch (error) {
      this.drawn = null;
      box.replaceChildren(h('p', { class: 'reason' }, `Graphviz could not draw the graph: ${error.message ?? error}`));
      return;
    }
    if (token !== this.token) return;
    const byId = new Map(view.states.map((s) => [s.id, s]));
    svg.querySelectorAll('g.state').forEach((g) => {
      const id = Number(g.id.replace('st-', ''));
      const s = byId.get(id);
      g.setAttribute('tabindex', '0');
      g.setAttribute('role', 'button');
      g.setAttribute('aria-label', `s${id} ${s.winning ? 'winning' : 'removed'}, ${s.kind} state${id === view.initial ? ', initial' : ''}: ${s.locations.join(', ')}${s.reason ? `; ${s.reason}` : ''}`);
      g.addEventListener('click', () => this.select(id));
      g.addEventListener('keydown', onActivate(() => this.select(id)));
    });
    // A redraw (the neighbourhood of a newly selected state) replaces the focused state: the
    // focus goes to the same state in the new drawing, else to the selected one.
    const focused = box.contains(document.activeElement) ? document.activeElement.id : null;
    // Graphviz gives the size in points; the zoom scales it in CSS pixels.
    this.natural = { width: svg.width.baseVal.value, height: svg.height.baseVal.value };
    this.drawn = svg;
    $('#graph-cut').hidden = !view.truncated;
    $('#graph-cut').textContent = view.truncated ? `Showing ${view.states.length} states; the neighbourhood is larger.` : '';
    box.replaceChildren(svg);
    this.markSelected();
    this.layout();
    if (focused) (svg.querySelector(`[id="${focused}"]`) ?? svg.querySelector(`#st-${this.selected}`))?.focus();
  }

  /** Sizes a new drawing (fit, or the current zoom) and scrolls to the selected state; waits
   * for the box to have a size when its tab is hidden. */
  layout() {
    const box = $('#space-graph');
    if (!this.drawn) return;
    this.pendingLayout = !box.clientWidth;
    if (this.pendingLayout) return;
    // Until the user decides: fit when that keeps the text legible, else 100 % and scroll.
    if (!this.fitChosen) $('#fit-graph').checked = this.fitZoom() >= LEGIBLE;
    this.setZoom($('#fit-graph').checked ? this.fitZoom() : this.zoom);
    this.reveal();
  }

  /** The zoom that shows the whole drawing in the box (never above 100 %). */
  fitZoom() {
    const box = $('#space-graph');
    if (!this.drawn || !this.natural.width) return 1;
    // The box's inner size without scrollbars, which go away once the drawing fits.
    const width = box.offsetWidth - 2 * box.clientLeft - 2;
    const height = box.offsetHeight - 2 * box.clientTop - 2;
    return Math.max(MIN_ZOOM, Math.min(1, width / this.natural.width, height / this.natural.height));
  }

  /** Scales the drawing; the point of it at `at` (box coordinates, default the middle of the
   * box) stays where it is. */
  setZoom(zoom, at = null) {
    const box = $('#space-graph');
    const svg = this.drawn;
    zoom = Math.min(MAX_ZOOM, Math.max(MIN_ZOOM, zoom));
    $('#zoom-reset').textContent = `${Math.round(zoom * 100)}%`;
    if (!svg) {
      this.zoom = zoom;
      return;
    }
    const { x, y } = at ?? { x: box.clientWidth / 2, y: box.clientHeight / 2 };
    const [px, py] = [(box.scrollLeft + x) / this.zoom, (box.scrollTop + y) / this.zoom];
    const sized = svg.style.width !== '';
    this.zoom = zoom;
    svg.style.width = `${this.natural.width * zoom}px`;
    svg.style.height = `${this.natural.height * zoom}px`;
    box.dataset.zoom = String(zoom);
    // A new drawing keeps the scroll position it was given (see `reveal`).
    if (sized) {
      box.scrollLeft = px * zoom - x;
      box.scrollTop = py * zoom - y;
    }
  }

  /** Scrolls the box so that the selected state is in view, centred along an axis where it
   * was not; a state already in view stays put (a click in the graph does not move it). */
  reveal() {
    const box = $('#space-graph');
    const g = this.drawn?.querySelector(`#st-${this.selected}`);
    if (!g || !box.clientWidth) return;
    const b = box.getBoundingClientRect();
    const r = g.getBoundingClientRect();
    const [left, top] = [b.left + box.clientLeft, b.top + box.clientTop];
    if (r.left < left || r.right > left + box.clientWidth) box.scrollLeft += r.left + r.width / 2 - (left + box.clientWidth / 2);
    if (r.top < top || r.bottom > top + box.clientHeight) box.scrollTop += r.top + r.height / 2 - (top + box.clientHeight / 2);
  }

  markSelected() {
    document.querySelectorAll('#state-list li').forEach((li) => li.setAttribute('aria-selected', String(Number(li.dataset.id) === this.selected)));
    this.drawn?.querySelectorAll('g.state').forEach((g) => {
      const on = g.id === `st-${this.selected}`;
      g.classList.toggle('selected', on);
      g.setAttribute('aria-current', String(on));
    });
  }

  async select(id) {
    this.selected = id;
    this.markSelected();
    this.reveal();
    await this.onSelect(id);
    if (this.big) await this.drawGraph();
  }
}
