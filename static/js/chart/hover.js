/* What the chart says of the point under the pointer: the nearest drawn point of a
 * trace that is hovered (within HOVER_PX), in the trace's own hovertemplate (Plotly's
 * "%{y:.4g}", "%{customdata[2]:.3g}", "%{text}"; d3's f, g, e and % formats).
 */

export const HOVER_PX = 24;

/** A value in a d3 format's common forms: ".3f", ".4g", ".2e", ".0%", "" (as is). */
export function formatValue(v, spec = "") {
  if (typeof v !== "number") return v == null ? "" : String(v);
  if (!Number.isFinite(v)) return String(v);
  const m = /^\.(\d+)([fge%])$/.exec(spec);
  if (!m) return String(Number(v.toPrecision(6)));
  const n = Number(m[1]);
  const out = m[2] === "f" ? v.toFixed(n) : m[2] === "e" ? v.toExponential(n)
    : m[2] === "%" ? `${(v * 100).toFixed(n)}%` : v.toPrecision(Math.max(1, n)).replace(/(\.\d*?)0+(e|$)/, "$1$2").replace(/\.(e|$)/, "$1");
  return out.replace("-", "−");
}

/** The trace's text for point i: its template filled in, <extra> dropped; or, without
 * a template, "name: x, y". */
export function hoverText(tr, i) {
  const value = (field) => {
    const m = /^(customdata|text)(?:\[(\d+)\])?$/.exec(field);
    if (m) {
      const base = m[1] === "text" ? (Array.isArray(tr.text) ? tr.text[i] : tr.text) : tr.customdata?.[i];
      return m[2] !== undefined ? base?.[Number(m[2])] : base;
    }
    const own = tr.own || tr.y;
    return { x: tr.x[i], theta: tr.x[i], y: own[i], r: own[i] }[field];
  };
  if (!tr.template) return `${tr.name}: ${formatValue(tr.x[i])}, ${formatValue((tr.own || tr.y)[i])}`;
  return tr.template.replace(/<extra>.*?<\/extra>/g, "")
    .replace(/%\{([\w[\]]+)(?::([^}]*))?\}/g, (_, field, spec) => formatValue(value(field), spec));
}

/** The nearest hovered point to (px, py) over the traces' pixels (pts[k][i]), or null. */
export function nearest(traces, pts, px, py) {
  let best = null, bestD = HOVER_PX * HOVER_PX;
  traces.forEach((tr, k) => {
    if (tr.hidden || !tr.hover || !pts[k]) return;
    const ps = pts[k];
    for (let i = 0; i < ps.length; i++) {
      const p = ps[i];
      if (!p) continue;
      const d = (p[0] - px) ** 2 + (p[1] - py) ** 2;
      if (d < bestD) { bestD = d; best = { tr, i, p }; }
    }
  });
  return best;
}
