/* A data-only redraw when nothing but the data moved.
 *
 * Plotly.react redraws a figure whole when its data change: axes, ticks, legend and
 * margins are measured again (10–20 ms of main thread a panel). When the new answer has
 * the same traces (same types, names, styles: only the arrays differ), the same layout,
 * and its data fits the autoranged axes as drawn (inside the range and filling at least
 * FILL of it), the traces alone are moved: their SVG paths rewritten in the next
 * animation frame (svgpaths.js), or where that cannot place them, Plotly.animate with
 * redraw: false. Anything else (a range that must change, an image, a 3-D surface)
 * goes through react.
 */
const ARRAY_KEYS = new Set(["x", "y", "r", "theta", "customdata", "text", "hovertext"]);
const ANIMATABLE = new Set(["scatter", "scatterpolar"]);
const FILL = 0.6;
// While a slider is held the axes stay put unless the data leaves them: the data need
// fill only HELD_FILL of a range, and a range that must grow gets HELD_HEADROOM of its
// span beyond the data (a drag over α sweeps the lobe's peak over decades: each re-layout
// is a full Plotly draw, 20–40 ms). The panel fits its axes again on release.
export const HELD_FILL = 0.1;
export const HELD_HEADROOM = 0.5;

const DTYPES = { f4: Float32Array, f8: Float64Array, i1: Int8Array, u1: Uint8Array, i2: Int16Array,
                 u2: Uint16Array, i4: Int32Array, u4: Uint32Array };

/** The numbers of a trace array: a plain or typed array, or Plotly's {dtype, bdata}. */
export function numbers(a) {
  if (Array.isArray(a) || ArrayBuffer.isView(a)) return a;
  if (a && typeof a.bdata === "string" && DTYPES[a.dtype]) {
    const bin = atob(a.bdata);
    const bytes = new Uint8Array(bin.length);
    for (let i = 0; i < bin.length; i++) bytes[i] = bin.charCodeAt(i);
    return new DTYPES[a.dtype](bytes.buffer);
  }
  return null;
}

/** A trace without its data arrays: what must not change for a data-only redraw. */
export function traceStyle(t) {
  const out = {};
  for (const [k, v] of Object.entries(t)) {
    if (ARRAY_KEYS.has(k)) continue;
    out[k] = k === "error_y" || k === "error_x" ? { ...v, array: undefined, arrayminus: undefined } : v;
  }
  return JSON.stringify(out);
}

function widen(ext, ax, values, plus, minus) {
  const vs = numbers(values);
  if (!vs) return false;
  const log = ax.type === "log";
  const up = numbers(plus), down = numbers(minus) || up;
  for (let i = 0; i < vs.length; i++) {
    const v = vs[i];
    if (v === null || !Number.isFinite(v)) continue;
    for (const w of [v, up ? v + (up[i] || 0) : v, down ? v - (down[i] || 0) : v]) {
      if (log && !(w > 0)) continue;
      const u = log ? Math.log10(w) : w;
      if (u < ext.lo) ext.lo = u;
      if (u > ext.hi) ext.hi = u;
    }
  }
  return true;
}

/** Does `data` fit the drawn figure's autoranged axes as they are? */
function fitsAxes(gd, data, fill) {
  const fl = gd.layout;            // Plotly writes each axis's range and autorange back into it
  const extents = new Map();
  const ext = (ax) => {
    if (!extents.has(ax)) extents.set(ax, { lo: Infinity, hi: -Infinity });
    return extents.get(ax);
  };
  for (const t of data) {
    if ((t.type || "scatter") === "scatterpolar") {
      const ax = fl[t.subplot || "polar"]?.radialaxis;
      if (!ax || !widen(ext(ax), ax, t.r)) return false;
    } else {
      const xa = fl[`xaxis${(t.xaxis || "x").slice(1)}`], ya = fl[`yaxis${(t.yaxis || "y").slice(1)}`];
      if (!xa || !ya || !widen(ext(xa), xa, t.x) || !widen(ext(ya), ya, t.y, t.error_y?.array, t.error_y?.arrayminus)) return false;
    }
  }
  for (const [ax, { lo, hi }] of extents) {
    if (ax.autorange !== true || !Array.isArray(ax.range) || lo > hi) continue;
    const r0 = Math.min(...ax.range), r1 = Math.max(...ax.range);
    if (lo < r0 || hi > r1 || hi - lo < fill * (r1 - r0)) return false;
  }
  return true;
}

/** An axis without what follows from its range: the range itself, and on a log axis
 * the tick spacing, which the server derives from the range's span (app/figures/style.py
 * log_dtick: "D1", "D2", then whole decades). */
const withoutRange = (ax) => ({ ...ax, range: undefined, ...(ax.type === "log" ? { dtick: undefined } : {}) });

/** A layout's axis ranges by axis ("xaxis", "yaxis2", "polar.radialaxis"), and the
 * layout without them (what must not change for a data-only redraw). */
export function splitRanges(layout) {
  const ranges = {};
  const rest = { ...layout };
  for (const k of Object.keys(layout)) {
    if (/^[xy]axis\d*$/.test(k) && Array.isArray(layout[k]?.range)) {
      ranges[k] = layout[k].range;
      rest[k] = withoutRange(layout[k]);
    } else if (/^polar\d*$/.test(k) && Array.isArray(layout[k]?.radialaxis?.range)) {
      ranges[`${k}.radialaxis`] = layout[k].radialaxis.range;
      rest[k] = { ...layout[k], radialaxis: withoutRange(layout[k].radialaxis) };
    }
  }
  return { ranges, rest: JSON.stringify(rest) };
}

/** Ranges to draw, given the server's previous and new ones: an end that moved since
 * the last full draw (the peak of the lobe growing as α falls) gets HEADROOM of the span
 * beyond it, so that the next moves in that direction still fit the axes as drawn.
 * An axis that does not move (θ from 0 to 90°) is drawn as the server gives it. */
const HEADROOM = 0.1;
// Two ranges are the same within this fraction of their span: the server's range of one
// figure differs in its last digits between its numpy and compiled paths (the first
// answers of a fresh server and the later ones), which is no move of the data.
const RANGE_SLACK = 1e-9;
export function withHeadroom(previous, next, headroom = HEADROOM, free = new Set()) {
  const out = {};
  for (const [k, w] of Object.entries(next)) {
    const p = previous?.[k];
    const slack = w.length === 2 ? RANGE_SLACK * Math.abs(w[1] - w[0]) : 0;
    const still = (i) => Math.abs(p[i] - w[i]) <= slack;
    if (!p || p.length !== 2 || w.length !== 2 || (still(0) && still(1))) {
      out[k] = w;
      continue;
    }
    // an axis in `free` (a log axis: its decades move at both ends as α does) gets the
    // headroom at both ends once either moved
    const both = free.has(k), [lo, hi] = padded(w, headroom);
    out[k] = [still(0) && !both ? w[0] : lo, still(1) && !both ? w[1] : hi];
  }
  return out;
}

/** A range with `headroom` of its span added beyond each end. */
function padded(range, headroom) {
  const pad = headroom * Math.abs(range[1] - range[0]) * Math.sign(range[1] - range[0]);
  return [range[0] - pad, range[1] + pad];
}

/** The keys (as splitRanges gives them) of a layout's log axes. */
export function logAxes(layout) {
  const out = new Set();
  for (const [k, ax] of Object.entries(layout)) {
    if (/^[xy]axis\d*$/.test(k) && ax?.type === "log") out.add(k);
    else if (/^polar\d*$/.test(k) && ax?.radialaxis?.type === "log") out.add(`${k}.radialaxis`);
  }
  return out;
}

/** The tick spacing of a log axis over `span` decades, by the server's rule for the
 * ranges it draws (app/figures/style.py, log_dtick): every digit within 1.5 decades,
 * 1-2-5 within 3.5, else a power of ten every ⌈span/10⌉ decades. Plotly's own choice
 * on a short axis over many decades labels 2×10, 3×10⁻¹, 4×10⁻³… */
const LOG_DIGITS_DECADES = 1.5, LOG_TICKS_125_DECADES = 3.5;   // style.py's, the same rule
export function logDtick(span) {
  if (span <= LOG_DIGITS_DECADES) return "D1";
  if (span <= LOG_TICKS_125_DECADES) return "D2";
  return Math.max(1, Math.ceil(span / 10));
}

/** The layout with these axis ranges (keys as splitRanges gives them). A log axis the
 * server gave a tick spacing, drawn over another span, gets the spacing for that span. */
export function withRanges(layout, ranges) {
  const out = { ...layout };
  const ranged = (ax, r) => {
    const same = Array.isArray(ax?.range) && ax.range[0] === r[0] && ax.range[1] === r[1];
    const next = { ...ax, range: r };
    if (ax?.type === "log" && !same && ax.dtick !== undefined) next.dtick = logDtick(Math.abs(r[1] - r[0]));
    return next;
  };
  for (const [k, r] of Object.entries(ranges)) {
    const [top, sub] = k.split(".");
    out[top] = sub ? { ...out[top], [sub]: ranged(out[top][sub], r) } : ranged(out[top], r);
  }
  return out;
}

/** What Plotly.relayout takes to draw `layout`'s ranges (and tick spacing) of these axes. */
export function rangeUpdate(layout, keys) {
  const update = {};
  for (const k of keys) {
    const [top, sub] = k.split(".");
    const ax = sub ? layout[top]?.[sub] : layout[top];
    update[`${k}.range`] = ax.range;
    if (ax.type === "log") update[`${k}.dtick`] = ax.dtick ?? null;
  }
  return update;
}

/** The server's new ranges are close enough to the drawn ones to keep the axes: each
 * inside the drawn range and spanning at least FILL of it (in the axis's own units,
 * log10 on a log axis, as Plotly keeps them). An axis in `openBelow` may reach below the
 * drawn range (a held slider's log axis: the tail the bottom cuts is cut a little more). */
export function rangesFit(drawn, wanted, fill = FILL, openBelow = new Set()) {
  const keys = Object.keys(wanted);
  if (keys.length !== Object.keys(drawn).length) return false;
  return keys.every((k) => {
    const d = drawn[k], w = wanted[k];
    if (!d || d.length !== 2 || w.length !== 2) return false;
    const d0 = Math.min(...d), d1 = Math.max(...d), w0 = Math.min(...w), w1 = Math.max(...w);
    const slack = RANGE_SLACK * (d1 - d0);
    return (w0 >= d0 - slack || openBelow.has(k)) && w1 <= d1 + slack && Math.min(w1, d1) - Math.max(w0, d0) >= fill * (d1 - d0);
  });
}

/** Can `data` replace what `gd` shows by a data-only redraw? styles: the traceStyle of
 * each trace drawn last. A plain-text legend name may change (E_avg = 0.0488 → 0.0505):
 * its legend entry is rewritten in place. */
export function canAnimate(gd, data, styles, fill = FILL) {
  return !!gd.layout && sameTraces(data, styles) && fitsAxes(gd, data, fill);
}

/** Are `data` the traces drawn (styles: their traceStyle), with other arrays only? */
export function sameTraces(data, styles) {
  if (!styles || styles.length !== data.length) return false;
  for (let i = 0; i < data.length; i++) {
    if (!ANIMATABLE.has(data[i].type || "scatter")) return false;
    if (traceStyle(data[i]) === styles[i]) continue;
    const drawnName = JSON.parse(styles[i]).name;
    if (traceStyle({ ...data[i], name: drawnName }) !== styles[i]) return false;
    if (!renamable(drawnName, data[i].name)) return false;
  }
  return true;
}

export function animateData(gd, data) {
  return Plotly.animate(gd, { data, traces: data.map((_, i) => i) },
                        { mode: "immediate", transition: { duration: 0 }, frame: { duration: 0, redraw: false } })
    .then(() => renameLegend(gd, data));
}

// A name's markup ("E<sub>avg</sub> = 0.0488"): what comes up to its last tag, and after it.
const markupHead = (name) => String(name).slice(0, String(name).lastIndexOf(">") + 1);
const plainTail = (name) => String(name).slice(String(name).lastIndexOf(">") + 1);

/** Can the legend text drawn for `before` be rewritten in place as `after`? When their
 * markup is the same and only the plain text after it differs (E<sub>avg</sub> = 0.0488
 * → 0.0505): Plotly drew that text as the last text node of the entry. */
function renamable(before, after) {
  if (before === after) return true;
  if (before === undefined || after === undefined) return false;
  return markupHead(before) === markupHead(after) && !/[<&]/.test(plainTail(after));
}

/** A legend entry whose trace's name changed (E_avg = 0.0488 → 0.0505) gets its new
 * text in place (a data-only redraw leaves the legend as drawn). */
export function renameLegend(gd, data) {
  // Plotly's legend lists the traces that show in it in trace order, those of one
  // legendgroup together where the group first appears: paired in that order, and left
  // as drawn if the counts differ
  const entries = [...gd.querySelectorAll(".legend .traces")];
  const shown = data.filter((t) => t.visible !== false && t.showlegend !== false);
  const first = new Map();
  shown.forEach((t, i) => { if (!first.has(t.legendgroup ?? i)) first.set(t.legendgroup ?? i, i); });
  const listed = shown.map((t, i) => [first.get(t.legendgroup ?? i), i, t]).sort((a, b) => a[0] - b[0] || a[1] - b[1]).map((e) => e[2]);
  if (entries.length !== listed.length) return;
  entries.forEach((g, k) => {
    const text = g.querySelector(".legendtext"), name = listed[k].name;
    if (!text || name === undefined) return;
    const walker = document.createTreeWalker(text, NodeFilter.SHOW_TEXT);
    let last = null;
    while (walker.nextNode()) last = walker.currentNode;
    const tail = plainTail(name);
    if (last && last.textContent !== tail) last.textContent = tail;
  });
}
