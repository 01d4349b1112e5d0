// The Zone tab: the selected state's locations, removal reason, zone constraints, and the zone
// projected on two clocks chosen from menus, as a polygon.
import { h } from './dom.js';
import { closeZone, isEmpty, projectionText, zoneSvg } from './zone.js';

const short = (name) => name.split('.').pop();

function constraintText(c, names) {
  const op = c.strict ? '<' : '≤';
  if (c.i === 0 && c.j === 0) return 'empty zone';
  if (c.j === 0) return `${names[c.i]} ${op} ${c.c}`;
  if (c.i === 0) return `${names[c.j]} ${c.strict ? '>' : '≥'} ${-c.c}`;
  return `${names[c.i]} − ${names[c.j]} ${op} ${c.c}`;
}

export class ZoneView {
  constructor(root) {
    this.root = root;
    this.axes = [1, 2];
  }

  show(state, meta) {
    this.state = state;
    this.meta = meta;
    if (!this.chosen) {
      // Until the user picks axes: the clocks this zone constrains, then the others.
      const used = [...new Set(state.constraints.flatMap((c) => [c.i, c.j]).filter((i) => i > 0))];
      const rest = meta.clocks.map((_, i) => i).filter((i) => i > 0 && !used.includes(i));
      const axes = [...used, ...rest];
      this.axes = [axes[0] ?? 1, axes[1] ?? axes[0] ?? 1];
    }
    this.render();
  }

  render() {
    const { state, meta } = this;
    if (!state) return;
    const names = meta.clocks.map((n, i) => (i === 0 ? '0' : n));
    const dim = names.length;
    const plot = [];
    if (dim >= 2) {
      const d = closeZone(dim, state.constraints);
      const [x, y] = this.axes.map((a) => Math.min(a, dim - 1));
      const menu = (axis, value) =>
        h(
          'select',
          { id: `zone-${axis}`, 'aria-label': `${axis} axis clock`, onchange: (e) => ((this.chosen = true), (this.axes[axis === 'x' ? 0 : 1] = Number(e.target.value)), this.render()) },
          names.slice(1).map((n, i) => {
            const o = h('option', { value: i + 1 }, n);
            o.selected = i + 1 === value;
            return o;
          }),
        );
      const wrap = h('div');
      wrap.innerHTML = zoneSvg(d, x, y, names);
      plot.push(
        h(
          'div',
          {},
          h('div', { class: 'toolbar' }, 'x:', menu('x', x), 'y:', menu('y', y)),
          isEmpty(d) ? h('p', { class: 'reason' }, 'empty zone') : wrap,
          h('ul', { id: 'zone-projection' }, projectionText(d, x, y, names).map((t) => h('li', {}, t))),
          x === y ? h('p', { class: 'muted' }, 'The same clock on both axes: the zone is on the diagonal.') : null,
        ),
      );
    } else plot.push(h('p', { class: 'muted' }, 'This game has no clocks.'));
    const units = meta.units;
    // One wrapper: `replaceChildren` would print an absent reason as the text "null".
    this.root.replaceChildren(
      h(
        'div',
        {},
        h('div', { class: 'zone-head', id: 'zone-title' }, `State s${state.id} (${state.kind}) — ${state.winning ? 'winning' : 'removed'}`),
        state.reason ? h('p', { class: 'reason' }, `Removed: ${state.reason}`) : null,
      h(
        'div',
        { class: 'zone-grid' },
        h(
          'div',
          {},
          h('table', { class: 'locations' }, state.locations.map((l, i) => h('tr', {}, h('td', { class: 'muted' }, units[i] ?? `unit ${i}`), h('td', {}, l)))),
          h('h4', {}, 'Zone'),
          h('div', { id: 'zone-text' }, state.zone),
          h('h4', {}, 'Constraints'),
          h('ul', { id: 'zone-constraints' }, state.constraints.length ? state.constraints.map((c) => h('li', {}, constraintText(c, names.map(short)))) : h('li', {}, 'none (every clock valuation)')),
        ),
        ...plot,
        ),
      ),
    );
  }
}
