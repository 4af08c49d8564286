/* While a slider is held, a linear axis that the data outgrows (or shrinks within) by
 * decades keeps its pixels and changes its labels.
 *
 * A drag over α sweeps the lobe's peak over four or five decades: each time it leaves
 * the axes, Plotly re-lays the figure out (15–40 ms of main thread, in which the slider's
 * next input waits). Scaling a linear axis's range by 10^j leaves every tick where it was
 * (Plotly's ticks are multiples of 1, 2 or 5 × 10^k of the range, scale-free under a
 * power of ten): the data divided by 10^j is drawn on the axes as they are (svgpaths.js),
 * and each tick label's decimal point moves j places. On release, or once the page is
 * quiet, Plotly draws the figure on its own axes again (Panel.release, Panel.sync).
 *
 * Plotly writes a linear axis's labels as plain decimals ("0.02", "1500") while its range
 * reaches 10^-3 to 10^4, and beyond as a mantissa times 10 to the range's exponent
 * ("0.2×10⁴"): each label is rewritten as Plotly would write its value times 10^j on the
 * scaled range, in either form.
 *
 * A log axis labelled every whole number of decades (the NDF's: its span is fixed and its
 * decades move with the peak as α does) moves by whole decades the same way: the data
 * divided by 10^j is the curve translated j decades down, on the ticks as they are, each
 * label's exponent k written k + j. Its range is shifted so that the top of the server's
 * fits (the tail below the bottom is cut, as the server's own range cuts it). An axis
 * the user zoomed, a log axis labelled between decades, or a label of another form
 * answers null, and Plotly redraws.
 */
import { numbers } from "./fastdraw.js";

// Sanity bounds of a shifted decimal (Plotly's own forms stay well within them).
const LABEL_MAX = 1e5;
const LABEL_DECIMALS = 5;
const DECIMAL = /^([−-]?)(\d+)(?:\.(\d+))?$/;

/** "0.02" with its decimal point moved j places right (left for j < 0): "20" for j = 3;
 * null for a label that is not a plain decimal or would leave LABEL_MAX / LABEL_DECIMALS. */
export function shiftLabel(text, j) {
  const m = DECIMAL.exec(text);
  if (!m) return null;
  const [, sign, int, frac = ""] = m;
  let digits = int + frac, point = int.length + j;
  if (point < 1) {
    digits = "0".repeat(1 - point) + digits;
    point = 1;
  }
  digits = digits.padEnd(point, "0");
  const whole = digits.slice(0, point).replace(/^0+(?=\d)/, ""), part = digits.slice(point).replace(/0+$/, "");
  if (part.length > LABEL_DECIMALS || Number(whole) >= LABEL_MAX) return null;
  const out = part ? `${whole}.${part}` : whole;
  return sign && /[1-9]/.test(out) ? `−${out}` : out;
}

/** The layout key of the axis a trace's values `key` ("x", "y", "r") are drawn on. */
function axisOf(t, key) {
  if ((t.type || "scatter") === "scatterpolar") return key === "r" ? `${t.subplot || "polar"}.radialaxis` : null;
  const id = key === "x" ? t.xaxis || "x" : t.yaxis || "y";
  return `${key}axis${id.slice(1)}`;
}

/** An axis of the figure as drawn: Plotly writes its range and type back into gd.layout. */
const drawnAxis = (gd, key) => key.split(".").reduce((o, k) => o?.[k], gd.layout);

/** Plotly's exponent of a linear range (axes.js autoTickRound, its 0.01 included): beyond
 * ±3 its labels are written as a mantissa times 10 to this power (exponentformat "power"). */
const rangeExp = (range) => Math.floor(Math.log10(Math.max(Math.abs(range[0]), Math.abs(range[1]))) + 0.01);
const powered = (e) => Math.abs(e) > 3;
// A ratio of data to axis that is a power of ten (the data at the axis's end) stays in the
// decade below: log10's last-bit rounding must not push j up by one.
const DECADE_SLACK = 1e-12;

/** The power of ten per axis that brings `data` back into the axes as drawn (`drawn`:
 * the ranges the panel drew, by layout key; `wanted`: the server's ranges of `data`, what
 * a log axis is shifted by), or null if some axis cannot be scaled. */
export function decadesFor(gd, data, drawn, wanted = {}) {
  const top = {};
  for (const t of data) {
    for (const key of (t.type || "scatter") === "scatterpolar" ? ["r"] : ["x", "y"]) {
      const ax = axisOf(t, key), vs = numbers(t[key]);
      if (!ax || !vs) return null;
      const extra = key === "y" ? [numbers(t.error_y?.array), numbers(t.error_y?.arrayminus)] : [];
      for (let i = 0; i < vs.length; i++) {
        for (const w of [vs[i], ...extra.map((e) => (e ? vs[i] + e[i] : vs[i]))]) {
          if (Number.isFinite(w)) top[ax] = Math.max(top[ax] || 0, Math.abs(w));
        }
      }
    }
  }
  const out = {};
  for (const [key, range] of Object.entries(drawn)) {
    const ax = drawnAxis(gd, key), shown = ax?.range;
    if (ax?.type === "log") {
      const w = wanted[key];
      if (!w) continue;
      const j = Math.ceil(Math.max(...w) - Math.max(...range) - DECADE_SLACK);
      if (!j) continue;
      if (!Number.isInteger(ax.dtick) || !shown || shown[0] !== range[0] || shown[1] !== range[1]) return null;
      out[key] = j;
      continue;
    }
    const reach = Math.max(Math.abs(range[0]), Math.abs(range[1]));
    const j = top[key] > 0 && reach > 0 ? Math.ceil(Math.log10(top[key] / reach) - DECADE_SLACK) : 0;
    if (!j) continue;
    if (ax?.type !== "linear" || !shown || shown[0] !== range[0] || shown[1] !== range[1]) return null;
    out[key] = j;
  }
  return out;
}

/** `data` divided by 10^j on each scaled axis (new trace objects; the input untouched). */
export function scaleData(data, decades) {
  const keys = Object.keys(decades);
  if (!keys.length) return data;
  // a gap (Plotly's null) stays a gap: a typed array holds NaN, which the path writer
  // skips as Plotly skips null
  const div = (a, j) => {
    const vs = numbers(a);
    return vs ? Float64Array.from(vs, (v) => (v === null ? NaN : v / 10 ** j)) : a;
  };
  return data.map((t) => {
    const out = { ...t };
    for (const key of (t.type || "scatter") === "scatterpolar" ? ["r"] : ["x", "y"]) {
      const j = decades[axisOf(t, key)];
      if (!j) continue;
      out[key] = div(t[key], j);
      if (key === "y" && t.error_y) out.error_y = { ...t.error_y, array: div(t.error_y.array, j),
                                                   arrayminus: div(t.error_y.arrayminus, j) };
    }
    return out;
  });
}

/** The tick label nodes of an axis (layout key), in the plot's SVG. */
function labelNodes(gd, key) {
  const [top] = key.split(".");
  if (key.endsWith(".radialaxis")) return [...gd.querySelectorAll(`.${top} .radial-axis g.xtick text`)];
  const id = `${key[0]}${key.slice(5)}`;           // "yaxis2" -> "y2"
  return [...gd.querySelectorAll(`.cartesianlayer g.${id}tick text`)];
}

// Plotly's power label: the mantissa and "×10", the exponent raised in a tspan, a spacer.
const SVG = "http://www.w3.org/2000/svg";
const exponentOf = (node) => [...node.querySelectorAll("tspan")].find((t) => t.getAttribute("dy") === "-0.6em");
const minus = (text) => text.replace("−", "-");
const unicodeMinus = (n) => String(n).replace("-", "−");     // as Plotly writes exponents

/** A log axis's label as Plotly writes 10^k ("1", "10", "10" and k raised): k, or null. */
function logExponent(node) {
  const sup = exponentOf(node);
  if (sup) return node.textContent === `10\u200b${sup.textContent}\u200b` ? Number(minus(sup.textContent)) : null;
  return node.textContent === "1" ? 0 : node.textContent === "10" ? 1 : null;
}

/** The labels as Plotly drew them, per axis: [node, mantissa, exponent] (a plain label's
 * exponent is 0; a log axis's mantissa is null), and the axis's exponent after a shift
 * of j decades (null: plain). */
export function baseLabels(gd, keys, ranges) {
  const out = {};
  for (const key of keys) {
    if (drawnAxis(gd, key)?.type === "log") {
      out[key] = { labels: labelNodes(gd, key).map((n) => [n, null, logExponent(n)]), exponent: () => null, log: true };
      continue;
    }
    const e0 = rangeExp(ranges[key]);
    const labels = labelNodes(gd, key).map((n) => {
      const sup = exponentOf(n);
      if (!sup) return [n, n.textContent, 0];
      return [n, n.firstChild?.nodeValue?.replace(/×10\u200b?$/, "") ?? "", Number(minus(sup.textContent))];
    });
    out[key] = { labels, exponent: (j) => (powered(e0 + j) ? e0 + j : null) };
  }
  return out;
}

/** A label's text for value mantissa × 10^exp × 10^j, written as Plotly writes it on an
 * axis whose exponent is `axisExp` (null: plain decimals); null if it cannot be. */
function labelText(mantissa, exp, j, axisExp) {
  if (/^[−-]?0(\.0*)?$/.test(mantissa)) return "0";
  return axisExp === null ? shiftLabel(mantissa, exp + j) : shiftLabel(mantissa, exp + j - axisExp);
}

/** Can every label of these axes be shifted? */
export function labelsShift(base, decades) {
  return Object.entries(decades).every(([key, j]) => base[key]?.labels.length
    && base[key].labels.every(([, m, e]) => (base[key].log ? Number.isInteger(e)
                                              : labelText(m, e, j, base[key].exponent(j)) !== null)));
}

/** Writes 10^k on a log axis's label as Plotly writes it. */
function writePower(node, k) {
  const want = k === 0 ? "1" : k === 1 ? "10" : `10\u200b${unicodeMinus(k)}\u200b`;
  if (node.textContent === want) return;
  node.textContent = k === 0 || k === 1 ? want : "10\u200b";
  if (k !== 0 && k !== 1) raise(node, unicodeMinus(k));
}

/** Plotly's raised exponent: a tspan at 70 % 0.6em up, and a spacer bringing it back. */
function raise(node, text) {
  const sup = document.createElementNS(SVG, "tspan");
  sup.setAttribute("style", "font-size:70%");
  sup.setAttribute("dy", "-0.6em");
  sup.textContent = text;
  const back = document.createElementNS(SVG, "tspan");
  back.setAttribute("dy", "0.42em");
  back.textContent = "\u200b";
  node.append(sup, back);
}

/** Writes each axis's labels shifted by its decades (0: as Plotly drew them). */
export function writeLabels(base, decades) {
  for (const [key, { labels, exponent, log }] of Object.entries(base)) {
    const j = decades[key] || 0, axisExp = exponent(j);
    if (log) {
      for (const [node, , k] of labels) if (Number.isInteger(k)) writePower(node, k + j);
      continue;
    }
    for (const [node, mantissa, exp] of labels) {
      const text = labelText(mantissa, exp, j, axisExp) ?? mantissa;
      const power = axisExp !== null && text !== "0";
      const want = power ? `${text}×10\u200b${unicodeMinus(axisExp)}\u200b` : text;
      if (node.textContent === want) continue;
      node.textContent = power ? `${text}×10\u200b` : text;
      if (power) raise(node, unicodeMinus(axisExp));
    }
  }
}

/** The ranges with each scaled axis multiplied by 10^(sign·j) (a log axis, in decades:
 * shifted by sign·j): sign 1, what the drawn axes now mean; -1, a range in data units as
 * the drawn axes take it. `logs`: the keys of the log axes. */
export function scaleRanges(ranges, decades, sign = 1, logs = new Set()) {
  const out = { ...ranges };
  for (const [key, j] of Object.entries(decades || {})) {
    if (out[key]) out[key] = out[key].map((v) => (logs.has(key) ? v + sign * j : v * 10 ** (sign * j)));
  }
  return out;
}
