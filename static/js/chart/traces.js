/* The curves of a figure as the API sends them (Plotly's figure format: scatter and
 * scatterpolar traces, arrays plain or as {dtype, bdata}), read into what the chart
 * draws: numbers, styles with their defaults, stacked groups summed.
 */

const DTYPES = { f8: Float64Array, f4: Float32Array, i4: Int32Array, u4: Uint32Array, i2: Int16Array,
                 u2: Uint16Array, i1: Int8Array, u1: Uint8Array };

/** An array of the figure as numbers: a plain array, a typed array, or Plotly's
 * base64 form {dtype, bdata}; null when there is none. */
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

/** Whether the chart draws this figure: curves only (lines, markers, fills), in one
 * cartesian plot (y and an optional y2) or one polar plot. */
export function drawsFigure(figure) {
  const data = figure?.data;
  if (!Array.isArray(data) || !data.length) return false;
  const kinds = new Set(data.map((t) => t.type || "scatter"));
  return kinds.size === 1 && (kinds.has("scatter") || kinds.has("scatterpolar"))
    && !figure.layout?.scene && !Object.keys(figure.layout || {}).some((k) => /^[xy]axis[3-9]/.test(k));
}

// Plotly's default colours, for a trace that names none
const COLORWAY = ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"];

/** rgba() of a colour at an opacity: the fill of a trace that gives only its line's colour. */
export function withAlpha(color, a) {
  const m = /^#([0-9a-f]{6})$/i.exec(color || "");
  if (m) {
    const n = parseInt(m[1], 16);
    return `rgba(${n >> 16},${(n >> 8) & 255},${n & 255},${a})`;
  }
  return color;
}

const num = (v, d) => (Number.isFinite(v) ? v : d);

/** A trace's style and roles, its arrays left as sent. */
function styleOf(t, i, colorway) {
  const polar = t.type === "scatterpolar";
  const color = t.line?.color || t.marker?.color || colorway[i % colorway.length];
  const mode = t.mode || "lines";
  const width = num(t.line?.width, 2);
  return {
    index: i, t, polar,
    axis: t.yaxis === "y2" ? "y2" : "y",
    name: t.name ?? `trace ${i}`, group: t.legendgroup ?? null,
    legend: t.showlegend !== false && t.name != null,
    hidden: t.visible === "legendonly" || t.visible === false,
    lines: mode.includes("lines") && width > 0, markers: mode.includes("markers"),
    color, width, dash: t.line?.dash || "solid",
    marker: { size: num(t.marker?.size, 6), symbol: t.marker?.symbol || "circle", color: t.marker?.color || color },
    fill: t.fill || (t.stackgroup ? "tonexty" : "none"), fillcolor: t.fillcolor || withAlpha(color, t.stackgroup ? 0.5 : 0.25),
    stack: t.stackgroup || null,
    hover: t.hoverinfo !== "skip" && t.hoverinfo !== "none",
    template: t.hovertemplate || null, customdata: t.customdata || null, text: t.text ?? null,
  };
}

/** The figure's traces as the chart draws them. */
export function readTraces(figure) {
  const colorway = figure.layout?.colorway || COLORWAY;
  const out = figure.data.map((t, i) => {
    const style = styleOf(t, i, colorway);
    return {
      ...style,
      x: numbers(style.polar ? t.theta : t.x) || [], y: numbers(style.polar ? t.r : t.y) || [],
      error: t.error_y && t.error_y.visible !== false ? { array: numbers(t.error_y.array) || [],
        color: t.error_y.color || style.color, thickness: num(t.error_y.thickness, 1.5), width: num(t.error_y.width, 3) } : null,
    };
  });
  stack(out);
  return out;
}

/** What a legend click hides or shows: the trace's group, else the trace itself (by its
 * place: its name may carry a number that moves with a slider, "E_avg = 0.0489"). */
export const toggleKey = (tr) => tr.group ?? `#${tr.index}`;

/** The legend's entries (named traces, each hidden where `hidden` holds its name or
 * group), without reading the arrays. */
export function legendEntries(figure, hidden = new Set()) {
  const colorway = figure.layout?.colorway || COLORWAY;
  return figure.data.map((t, i) => styleOf(t, i, colorway)).filter((tr) => tr.legend)
    .map((tr) => ({ ...tr, hidden: tr.hidden || hidden.has(toggleKey(tr)) }));
}

/** Traces of one stackgroup are drawn summed, each filled down to the one before it
 * (Plotly's stackgroup); the values shown on hover stay each trace's own. */
function stack(traces) {
  const sums = new Map();
  for (const tr of traces) {
    if (!tr.stack) continue;
    const below = sums.get(tr.stack);
    tr.own = tr.y;
    tr.base = below || null;
    tr.y = Float64Array.from(tr.y, (v, k) => (below ? below[k] : 0) + (Number.isFinite(v) ? v : 0));
    sums.set(tr.stack, tr.y);
  }
}
