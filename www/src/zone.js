// A zone (list of constraints x_i - x_j ≺ c, index 0 the constant 0) closed into a difference
// bound matrix, projected on two clocks and drawn in clock space: as a polygon, or, where the
// projection is flat, as a segment (one clock or a difference fixed, as after a reset) or a
// dot (both clocks fixed, as x = y = 0 in an initial state), each with its equation.

const INF = { c: Infinity, strict: true };
const less = (a, b) => a.c < b.c || (a.c === b.c && a.strict && !b.strict);
const add = (a, b) => ({ c: a.c + b.c, strict: a.strict || b.strict });

/** The canonical matrix of a zone of `dim` clocks (index 0 included). */
export function closeZone(dim, constraints) {
  const d = Array.from({ length: dim }, (_, i) =>
    Array.from({ length: dim }, (_, j) => (i === j || i === 0 ? { c: 0, strict: false } : INF)),
  );
  for (const { i, j, c, strict } of constraints) {
    const b = { c, strict };
    if (less(b, d[i][j])) d[i][j] = b;
  }
  for (let k = 0; k < dim; k++)
    for (let i = 0; i < dim; i++)
      for (let j = 0; j < dim; j++) {
        const via = add(d[i][k], d[k][j]);
        if (less(via, d[i][j])) d[i][j] = via;
      }
  return d;
}

export const isEmpty = (d) => d.some((row, i) => less(row[i], { c: 0, strict: false }));

function fmt(b) {
  return `${b.strict ? '<' : '≤'} ${b.c}`;
}

/** The projection of the zone on clocks x and y, as readable bounds. */
export function projectionText(d, x, y, names) {
  const parts = [];
  const axes = x === y ? [[x, names[x]]] : [[x, names[x]], [y, names[y]]];
  for (const [i, n] of axes) {
    const lo = d[0][i];
    const hi = d[i][0];
    const low = -lo.c === 0 && !lo.strict ? '0 ≤' : `${-lo.c} ${lo.strict ? '<' : '≤'}`;
    parts.push(`${low} ${n}${hi.c === Infinity ? '' : ` ${fmt(hi)}`}`);
  }
  if (x === y) return parts;
  // A difference only when it says more than the single-clock bounds imply.
  if (less(d[x][y], add(d[x][0], d[0][y]))) parts.push(`${names[x]} − ${names[y]} ${fmt(d[x][y])}`);
  if (less(d[y][x], add(d[y][0], d[0][x]))) parts.push(`${names[y]} − ${names[x]} ${fmt(d[y][x])}`);
  return parts;
}

/** Clips a convex polygon with a·p ≤ c (Sutherland–Hodgman). */
function clip(poly, a, b, c) {
  const out = [];
  const inside = (p) => a * p[0] + b * p[1] <= c + 1e-9;
  for (let k = 0; k < poly.length; k++) {
    const p = poly[k];
    const q = poly[(k + 1) % poly.length];
    if (inside(p)) out.push(p);
    if (inside(p) !== inside(q)) {
      const fp = a * p[0] + b * p[1] - c;
      const fq = a * q[0] + b * q[1] - c;
      const t = fp / (fp - fq);
      out.push([p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]);
    }
  }
  return out;
}

/** The projected polygon inside [0, size]²; `unbounded` tells if it reaches past the view. */
export function polygon(d, x, y) {
  const finite = [d[x][0], d[y][0], d[0][x], d[0][y], d[x][y], d[y][x]].map((b) => Math.abs(b.c)).filter(Number.isFinite);
  const size = Math.max(3, ...finite.map((c) => c + 2));
  let poly = [[0, 0], [size, 0], [size, size], [0, size]];
  const halfPlanes = [
    [1, 0, d[x][0].c], [-1, 0, d[0][x].c], [0, 1, d[y][0].c], [0, -1, d[0][y].c],
    [1, -1, d[x][y].c], [-1, 1, d[y][x].c],
  ];
  for (const [a, b, c] of halfPlanes) if (Number.isFinite(c) && poly.length) poly = clip(poly, a, b, c);
  const unbounded = d[x][0].c === Infinity || d[y][0].c === Infinity;
  return { points: poly, size, unbounded };
}

const num = (v) => String(Math.round(v * 100) / 100);

/** What the clipped polygon is: `{ dim: 0, points: [p] }` a point, `{ dim: 1, points: [a, b] }`
 * a segment from a to b, `{ dim: 2, points }` a polygon, `{ dim: -1 }` nothing. Clipping a flat
 * zone leaves a polygon without area (repeated or collinear corners) that draws nothing. */
export function shapeOf(points) {
  const eps = 1e-6;
  const same = (p, q) => Math.abs(p[0] - q[0]) < eps && Math.abs(p[1] - q[1]) < eps;
  const unique = points.filter((p, i) => !points.slice(0, i).some((q) => same(p, q)));
  if (unique.length === 0) return { dim: -1, points: [] };
  if (unique.length === 1) return { dim: 0, points: unique };
  let [a, b, far] = [unique[0], unique[1], -1];
  for (const p of unique)
    for (const q of unique) {
      const dist = Math.hypot(p[0] - q[0], p[1] - q[1]);
      if (dist > far) [a, b, far] = [p, q, dist];
    }
  const offLine = (p) => Math.abs((b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])) / far;
  return unique.every((p) => offLine(p) < eps) ? { dim: 1, points: [a, b] } : { dim: 2, points };
}

/** The equation of a segment: one clock fixed, or the difference of the two (the only flat
 * projections a zone has). */
function segmentText([a, b], xn, yn) {
  if (Math.abs(a[0] - b[0]) < 1e-6) return `${xn} = ${num(a[0])}`;
  if (Math.abs(a[1] - b[1]) < 1e-6) return `${yn} = ${num(a[1])}`;
  const c = a[0] - a[1];
  return Math.abs(c) < 1e-6 ? `${xn} = ${yn}` : `${xn} − ${yn} = ${num(c)}`;
}

/** The projection as an SVG element, with integer grid and axis labels. */
export function zoneSvg(d, x, y, names, px = 280) {
  const { points, size, unbounded } = polygon(d, x, y);
  const m = 28;
  const bottom = 42; // room for the ticks and the x label
  const scale = (px - m - bottom) / size;
  const X = (v) => m + v * scale;
  const Y = (v) => px - bottom - v * scale;
  const step = size > 50 ? 10 : size > 20 ? 5 : size > 8 ? 2 : 1;
  let grid = '';
  for (let v = 0; v <= size + 1e-9; v += step) {
    grid += `<line class="grid" x1="${X(v)}" y1="${Y(0)}" x2="${X(v)}" y2="${Y(size)}"/>`;
    grid += `<line class="grid" x1="${X(0)}" y1="${Y(v)}" x2="${X(size)}" y2="${Y(v)}"/>`;
    grid += `<text class="tick" x="${X(v)}" y="${Y(0) + 14}" text-anchor="middle">${v}</text>`;
    grid += `<text class="tick" x="${X(0) - 6}" y="${Y(v) + 4}" text-anchor="end">${v}</text>`;
  }
  const esc = (s) => s.replace(/[<&]/g, (c) => (c === '<' ? '&lt;' : '&amp;'));
  const flat = shapeOf(points);
  /** A label near (sx, sy) in pixels, kept inside the plot. */
  const label = (text, sx, sy) => {
    const right = sx > px * 0.6;
    const ly = sy < m + 8 ? sy + 16 : sy - 8;
    return `<text class="zone-label" x="${(right ? sx - 8 : sx + 8).toFixed(1)}" y="${ly.toFixed(1)}" text-anchor="${right ? 'end' : 'start'}">${esc(text)}</text>`;
  };
  let shape;
  let described;
  if (flat.dim === 0) {
    const [[a, b]] = flat.points;
    described = `the point (${num(a)}, ${num(b)})`;
    shape = `<circle class="zone zone-point" cx="${X(a).toFixed(1)}" cy="${Y(b).toFixed(1)}" r="5"/>${label(`(${num(a)}, ${num(b)})`, X(a), Y(b))}`;
  } else if (flat.dim === 1) {
    const [[a1, b1], [a2, b2]] = flat.points;
    const text = segmentText(flat.points, names[x], names[y]);
    described = `the segment ${text}`;
    shape = `<line class="zone zone-segment${unbounded ? ' unbounded' : ''}" x1="${X(a1).toFixed(1)}" y1="${Y(b1).toFixed(1)}" x2="${X(a2).toFixed(1)}" y2="${Y(b2).toFixed(1)}"/>`;
    // With the same clock on both axes the diagonal says nothing more (the note below says why).
    if (x !== y) shape += label(text, X((a1 + a2) / 2), Y((b1 + b2) / 2));
  } else if (flat.dim === 2) {
    const pts = points.map(([a, b]) => `${X(a).toFixed(1)},${Y(b).toFixed(1)}`).join(' ');
    described = 'a polygon';
    shape = `<polygon class="zone${unbounded ? ' unbounded' : ''}" points="${pts}"/>`;
  } else {
    described = 'empty';
    shape = `<text x="${px / 2}" y="${px / 2}" text-anchor="middle">empty</text>`;
  }
  const svg = `<svg xmlns="http://www.w3.org/2000/svg" class="zone-plot" width="${px}" height="${px}" viewBox="0 0 ${px} ${px}" role="img" aria-label="zone projected on ${esc(names[x])} and ${esc(names[y])}: ${described}">
    ${grid}
    <line class="axis" x1="${X(0)}" y1="${Y(0)}" x2="${X(size)}" y2="${Y(0)}"/>
    <line class="axis" x1="${X(0)}" y1="${Y(0)}" x2="${X(0)}" y2="${Y(size)}"/>
    ${shape}
    <text class="axis-label" x="${X(size)}" y="${px - 6}" text-anchor="end">${esc(names[x])}</text>
    <text class="axis-label" x="4" y="${m - 10}">${esc(names[y])}</text>
  </svg>`;
  return svg;
}
