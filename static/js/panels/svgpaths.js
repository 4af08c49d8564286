/* Data-only redraws by writing the plot's SVG paths directly.
 *
 * When only a figure's arrays move (fastdraw.js decides that), Plotly still re-runs
 * its defaults, calc and transition machinery for the whole figure: 15–20 ms of main
 * thread a panel. The new curves need none of it: each point goes through the axes
 * Plotly has already laid out (their ranges and types as Plotly writes them back into the
 * figure's public layout, the plot area's size from the clip Plotly drew it in; for a
 * polar trace, the centre and radius of its radial axis line), and the trace's existing
 * <path> elements get new `d` attributes — about a millisecond for a whole panel. No
 * private field of Plotly is read: its public figure (gd.layout, gd.data) and the SVG it
 * drew say where each point goes.
 *
 * Supported: scatter and scatterpolar traces drawn as lines and/or markers, with a
 * `toself` fill and y error bars. Anything the page cannot place exactly as Plotly
 * would (another trace type, a count of line segments, markers or bars that does not
 * match what is drawn) makes `writePaths` answer false, and the caller takes Plotly's
 * way. The points themselves (`geometry`) also serve heldcanvas.js, which draws them on
 * a canvas while a slider is held.
 *
 * Plotly's own state (its calcdata, read by hover, zoom, resize and its image export)
 * still describes the previous data: the caller keeps the new figure and hands it to
 * Plotly.react before any of those is used (Panel.sync).
 */
import { numbers } from "./fastdraw.js";

const round = (v) => Math.round(v * 100) / 100;       // Plotly writes 2 decimals too
const finite = (p) => Number.isFinite(p[0]) && Number.isFinite(p[1]);

/** An axis of the drawn figure (layout key "xaxis2", "polar.radialaxis") as a map from
 * data to its range's units (log10 on a log axis), or null where Plotly laid out none
 * or a kind of axis the page does not place (category, date). */
function axisScale(gd, key) {
  const ax = key.split(".").reduce((o, k) => o?.[k], gd.layout);
  const r = ax?.range, type = ax?.type || "linear";
  if (!Array.isArray(r) || r.length !== 2 || r[0] === r[1] || (type !== "linear" && type !== "log")) return null;
  return { r0: r[0], r1: r[1], l: type === "log" ? (v) => (v > 0 ? Math.log10(v) : NaN) : (v) => v };
}

/** An element's translation (its transform's leading translate()), or null. */
function translateOf(node) {
  const m = /^\s*translate\(\s*(-?[\d.e+-]+)[\s,]+(-?[\d.e+-]+)\s*\)/.exec(node?.getAttribute("transform") || "");
  return m ? [Number(m[1]), Number(m[2])] : null;
}

/** The plot area of a cartesian subplot ("xy", "x2y2") in the SVG's pixels, as Plotly
 * clips it: {x, y, w, h}, or null before it is drawn. */
export function plotBox(gd, subplot = "xy") {
  const rect = gd.querySelector(`clipPath.axesclip[id$="${subplot}"] rect`);
  const n = (a) => Number(rect?.getAttribute(a));
  const box = { x: n("x"), y: n("y"), w: n("width"), h: n("height") };
  return rect && Object.values(box).every(Number.isFinite) && box.w > 0 && box.h > 0 ? box : null;
}

/** (u, v) data → [px, py] in the trace layer's pixels, as Plotly draws the trace type. */
function projector(gd, t) {
  if (t.type === "scatterpolar") {
    const key = t.subplot || "polar", aa = gd.layout?.[key]?.angularaxis || {};
    const ra = axisScale(gd, `${key}.radialaxis`);
    const g = gd.querySelector(`.polarlayer g.${key}`);
    const line = g?.querySelector(".radial-line line"), centre = translateOf(line), at = translateOf(g?.querySelector(".frontplot"));
    const inner = Number(line?.getAttribute("x1")), outer = Number(line?.getAttribute("x2"));
    if (!ra || !centre || !at || !(outer > inner) || (aa.type && aa.type !== "linear")) return null;
    // Plotly's angle: counterclockwise from +x by default, `rotation` where θ = 0 is
    // (90° by default when clockwise); θ in the trace's unit
    const dir = aa.direction === "clockwise" ? -1 : 1, rotation = aa.rotation ?? (dir < 0 ? 90 : 0);
    const toDeg = t.thetaunit === "radians" ? 180 / Math.PI : 1;
    const perUnit = (outer - inner) / (ra.r1 - ra.r0), cx = centre[0] - at[0], cy = centre[1] - at[1];
    return { u: "r", v: "theta", at: (r, th) => {
      const rad = inner + (ra.l(r) - ra.r0) * perUnit, a = (rotation + dir * th * toDeg) * Math.PI / 180;
      return [cx + rad * Math.cos(a), cy - rad * Math.sin(a)];
    } };
  }
  const xid = t.xaxis || "x", yid = t.yaxis || "y";
  const xa = axisScale(gd, `xaxis${xid.slice(1)}`), ya = axisScale(gd, `yaxis${yid.slice(1)}`);
  // the size of the subplot's plot area (an overlaying axis's subplot has its own clip)
  const rect = gd.querySelector(`clipPath.plotclip[id$="${xid}${yid}plot"] rect`);
  const box = { w: Number(rect?.getAttribute("width")), h: Number(rect?.getAttribute("height")) };
  if (!xa || !ya || !(box.w > 0) || !(box.h > 0)) return null;
  const py = (y) => (ya.r1 - ya.l(y)) * box.h / (ya.r1 - ya.r0);
  return { u: "x", v: "y", py, at: (x, y) => [(xa.l(x) - xa.r0) * box.w / (xa.r1 - xa.r0), py(y)] };
}

/** The pixel points of one trace (null where Plotly leaves a gap). */
function pixels(proj, t) {
  const us = numbers(t[proj.u]), vs = numbers(t[proj.v]);
  if (!us || !vs || us.length !== vs.length) return null;
  const out = new Array(us.length);
  for (let i = 0; i < us.length; i++) {
    const u = us[i], v = vs[i];
    const p = u === null || v === null ? null : proj.at(u, v);
    out[i] = p && finite(p) ? p : null;
  }
  return out;
}

/** The runs of at least two points between gaps: the line segments Plotly draws. */
function runs(points) {
  const out = [];
  let run = [];
  for (const p of points) {
    if (p) run.push(p);
    else {
      if (run.length > 1) out.push(run);
      run = [];
    }
  }
  if (run.length > 1) out.push(run);
  return out;
}

const pathOf = (run) => `M${run.map((p) => `${round(p[0])},${round(p[1])}`).join("L")}`;

/** One trace as Plotly would place it, in its layer's pixels, or null if what is drawn
 * cannot take it: {group, lines, fill, marks, bars, half, segs, drawn, ticks}
 * (segs: the line runs; drawn: the points with a marker; ticks: each error bar's
 * [x, top, bottom]; half: half its cap width). */
function traceGeometry(gd, group, t) {
  const ft = { ...t, type: t.type || "scatter" };
  if (ft.type !== "scatter" && ft.type !== "scatterpolar") return null;
  const proj = projector(gd, ft);
  const points = proj && pixels(proj, t);
  if (!points) return null;
  const mode = String(ft.mode || "");
  const lines = [...group.querySelectorAll("path.js-line")];
  let segs = [], fill = null;
  if (mode.includes("lines")) {
    segs = runs(points);
    fill = group.querySelector("path.js-fill");
    if (segs.length !== lines.length) return null;
    if (fill ? ft.fill !== "toself" : ft.fill && ft.fill !== "none") return null;
  } else if (lines.length) return null;
  const drawn = points.filter(Boolean);
  const marks = [...group.querySelectorAll("g.points path.point")];
  if (mode.includes("markers") ? marks.length !== drawn.length : marks.length) return null;
  const bars = [...group.querySelectorAll("g.errorbar path.yerror")];
  const ticks = [];
  let half = 0;
  if (bars.length || t.error_y?.array) {
    const plus = numbers(t.error_y?.array), minus = numbers(t.error_y?.arrayminus) || plus;
    const ys = numbers(t.y), py = proj.py;
    if (!plus || !py || bars.length !== drawn.length) return null;
    half = Number(/h(-?[\d.]+)/.exec(bars[0]?.getAttribute("d") || "")?.[1]) / 2;
    if (bars.length && !Number.isFinite(half)) return null;
    for (let i = 0; i < points.length; i++) {
      if (!points[i]) continue;
      const hi = py(ys[i] + (plus[i] || 0)), lo = py(ys[i] - (minus[i] || 0));
      if (!Number.isFinite(hi) || !Number.isFinite(lo)) return null;
      ticks.push([points[i][0], hi, lo]);
    }
  }
  return { group, lines, fill, marks, bars, half, segs, drawn, ticks };
}

/** One trace's attribute writes. */
function traceWrites({ lines, fill, marks, bars, half: w, segs, drawn, ticks }) {
  const writes = [];
  const ds = segs.map(pathOf);
  ds.forEach((d, i) => writes.push([lines[i], "d", d]));
  if (fill) writes.push([fill, "d", ds.length ? `${ds.join("Z")}Z` : "M0,0Z"]);
  marks.forEach((m, i) => writes.push([m, "transform", `translate(${round(drawn[i][0])},${round(drawn[i][1])})`]));
  ticks.forEach(([x, hi, lo], k) => writes.push([bars[k], "d", `M${round(x - w)},${round(hi)}h${2 * w}m-${w},0V${round(lo)}m-${w},0h${2 * w}`]));
  return writes;
}

/** The indices of the traces of `data` that Plotly draws (visible: true, its default). */
export const drawnTraces = (data) => data.map((t, i) => (t.visible ?? true) === true ? i : -1).filter((i) => i >= 0);

/** The subplot a trace is drawn in ("xy", "xy2", "polar"). */
const subplotOfTrace = (t) => (t.type === "scatterpolar" ? t.subplot || "polar" : `${t.xaxis || "x"}${t.yaxis || "y"}`);

/** The subplot a drawn trace group is in: the class of its nearest subplot group. */
function subplotOfGroup(gd, g) {
  for (let n = g.parentElement; n && n !== gd; n = n.parentElement) {
    const c = [...n.classList].find((k) => /^(x\d*y\d*|polar\d*)$/.test(k));
    if (c) return c;
  }
  return null;
}

/** Every drawn trace of `data` placed on `gd` as Plotly would place it (trace order),
 * or null if they cannot all be: read in an animation frame, with the axes as they are.
 * Plotly draws one group a visible trace, subplot by subplot in trace order, so within
 * each subplot the groups drawn and its visible traces pair up in order; any mismatch
 * of count or kind answers null. */
export function geometry(gd, data) {
  if (!gd.layout) return null;
  const groups = new Map(), traces = new Map();
  for (const g of gd.querySelectorAll(".scatterlayer g.trace")) {
    const sub = subplotOfGroup(gd, g);
    if (!groups.has(sub)) groups.set(sub, []);
    groups.get(sub).push(g);
  }
  for (const i of drawnTraces(data)) {
    const sub = subplotOfTrace({ ...data[i], type: data[i].type || "scatter" });
    if (!traces.has(sub)) traces.set(sub, []);
    traces.get(sub).push(i);
  }
  if (groups.size !== traces.size) return null;
  const out = [];
  for (const [sub, indices] of traces) {
    const gs = groups.get(sub);
    if (!gs || gs.length !== indices.length) return null;
    for (let k = 0; k < indices.length; k++) {
      const g = traceGeometry(gd, gs[k], data[indices[k]]);
      if (!g) return null;
      out.push([indices[k], g]);
    }
  }
  return out.sort((a, b) => a[0] - b[0]).map(([, g]) => g);
}

/** Draws `data` on `gd` by writing its paths (in an animation frame: it reads the axes
 * as they are then); false, and nothing written, if it cannot. */
export function writePaths(gd, data) {
  const traces = geometry(gd, data);
  if (!traces) return false;
  for (const [node, attr, value] of traces.flatMap(traceWrites)) node.setAttribute(attr, value);
  return true;
}
