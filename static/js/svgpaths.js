/* Data-only redraws by writing the plot's SVG paths directly.
 *
 * When only a figure's arrays move (fastdraw.js decides that), Plotly still re-runs
 * its defaults, calc and transition machinery for the whole figure: 15–20 ms of main
 * thread a panel. The new curves need none of it: each point goes through the axes
 * Plotly has already laid out (c2p; for a polar trace, its radial and angular c2g as
 * Plotly's scatterpolar uses them), and the trace's existing <path> elements get new
 * `d` attributes — about a millisecond for a whole panel.
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

function axis(fl, id, letter) {
  const n = id && id.length > 1 ? id.slice(1) : "";
  return fl[`${letter}axis${n}`];
}

/** (u, v) data → [px, py] in the trace layer's pixels, as Plotly draws the trace type. */
function projector(gd, ft) {
  const fl = gd._fullLayout;
  if (ft.type === "scatterpolar") {
    const sp = fl[ft.subplot || "polar"]?._subplot;
    const ra = sp?.radialAxis, aa = sp?.angularAxis, xa = sp?.xaxis, ya = sp?.yaxis;
    if (!ra?.c2g || !aa?.c2g || !xa?.c2p || !ya?.c2p || aa.type !== "linear") return null;
    // Plotly's calcdata holds θ in radians (its calc converts a trace's degrees), which
    // is what c2g takes
    const toRad = ft.thetaunit === "radians" ? 1 : Math.PI / 180;
    return { u: "r", v: "theta", at: (r, t) => {
      const g = ra.c2g(r), a = aa.c2g(t * toRad);
      return [xa.c2p(g * Math.cos(a)), ya.c2p(g * Math.sin(a))];
    } };
  }
  const xa = axis(fl, ft.xaxis, "x"), ya = axis(fl, ft.yaxis, "y");
  if (!xa?.c2p || !ya?.c2p) return null;
  return { u: "x", v: "y", ya, at: (x, y) => [xa.c2p(x), ya.c2p(y)] };
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
  const ft = group.__data__?.[0]?.trace;
  if (!ft || (ft.type !== "scatter" && ft.type !== "scatterpolar")) return null;
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
    const ys = numbers(t.y), ya = proj.ya;
    if (!plus || !ya || bars.length !== drawn.length) return null;
    half = Number(/h(-?[\d.]+)/.exec(bars[0]?.getAttribute("d") || "")?.[1]) / 2;
    if (bars.length && !Number.isFinite(half)) return null;
    for (let i = 0; i < points.length; i++) {
      if (!points[i]) continue;
      const hi = ya.c2p(ys[i] + (plus[i] || 0)), lo = ya.c2p(ys[i] - (minus[i] || 0));
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

/** Every drawn trace of `data` placed on `gd` as Plotly would place it (trace order),
 * or null if they cannot all be: read in an animation frame, with the axes as they are. */
export function geometry(gd, data) {
  // every trace that Plotly drew (a hidden one is not drawn) must be placed
  if (!gd._fullLayout || !gd._fullData || gd._fullData.length !== data.length) return null;
  const groups = new Map();
  for (const g of gd.querySelectorAll(".scatterlayer g.trace")) {
    const i = g.__data__?.[0]?.trace?.index;
    if (Number.isInteger(i)) groups.set(i, g);
  }
  for (let i = 0; i < data.length; i++) {
    if ((gd._fullData[i].visible === true) !== groups.has(i)) return null;
  }
  const out = [];
  for (const i of [...groups.keys()].sort((a, b) => a - b)) {
    const g = traceGeometry(gd, groups.get(i), data[i]);
    if (!g) return null;
    out.push(g);
  }
  return out;
}

/** Draws `data` on `gd` by writing its paths (in an animation frame: it reads the axes
 * as they are then); false, and nothing written, if it cannot. */
export function writePaths(gd, data) {
  const traces = geometry(gd, data);
  if (!traces) return false;
  for (const [node, attr, value] of traces.flatMap(traceWrites)) node.setAttribute(attr, value);
  return true;
}
