/* Your BRDF on the curve panels: its lobe in the plane of incidence, its albedo E(μ) and
 * its D-like slice on the NDF panel (f at l = v, Disney's BRDF Explorer's θ_h plot), evaluated on the GPU (the user BRDF's PairEvaluator, read back from float targets) and
 * added as one labelled trace ("your BRDF: <name>") to the figure each panel drew, through
 * the panel's own overlay (Panel.overlay: the data module's path; no second renderer).
 *
 * Each time a panel draws (its "brdf-drawn", or the data module's "brdf-data-drawn" over
 * it) the trace is added again at that figure's own angles (computed again only when its
 * inputs changed); when the BRDF changes
 * (opened, a value or the text changed, closed) the panels' last figures are redrawn with
 * the new trace, or without one. Values: Rec. 709 luminance of the RGB f, as the server's
 * "f" of a coloured model (app/environment/render.py LUMINANCE).
 */
import { albedoPairs, albedoOf } from "./measure.js";
import { LUMINANCE } from "../panels/average.js";
import { numbers } from "../chart/traces.js";
import { rangeOverAll } from "../panels/layout.js";

/** The panels that get the trace. */
export const VIEWS = ["lobe", "albedo", "ndf"];
/** The label of the trace: "your BRDF: <name>". */
export const LABEL = "your BRDF";
/** The NDF panel's trace is not the file's D but f itself at l = v (θ_d = 0, h = l = v):
 * for a D term file (its BRDF returns D(h)) that is D(θ_h); for a full BRDF, the D-like
 * slice of Disney's explorer. Its label says which f it is, not the file's name; in
 * Plotly's markup, as the figure's own "D(θ<sub>m</sub>)" (the legend draws subscripts). */
export const DLIKE_LABEL = `${LABEL}: f at l = v (θ<sub>d</sub> = 0)`;
export const DLIKE_COS_LABEL = `${LABEL}: f·cos θ<sub>h</sub> at l = v (θ<sub>d</sub> = 0)`;
/** The trace's colour: Okabe-Ito reddish purple, apart from the model's blue and the guides' orange and green. */
const COLOR = "#CC79A7";
/** The albedo curve's quadrature (measure.js albedoPairs): Gauss-Legendre in μ_l × the
 * midpoint rule in φ, 32 768 pairs a μ. At grazing v the lobe is narrow in φ, not in μ_l:
 * for GGX α = 0.3 at μ = 1/16, 256 φ are off by 1.2e-4 and 512 by 3.6e-7, while 32, 64
 * or 128 μ_l all agree to 1e-9 (float64, against the server's quadrature at tol 1e-7). */
export const CURVE_NODES = { mu: 64, phi: 512 };
/** A BRDF change redraws the lobe at the next frame and the albedo (≈ 0.5 M GPU
 * evaluations at the panel's 16 μ > 0) this long after the last of a burst (a slider). */
const ALBEDO_DELAY_MS = 200;
const DEG = Math.PI / 180;
/** Set on the trace (and kept through the chart): how it is found again and replaced. */
const MARK = "user-brdf";

const dir = (thetaDeg, phiDeg) => [Math.sin(thetaDeg * DEG) * Math.cos(phiDeg * DEG),
  Math.sin(thetaDeg * DEG) * Math.sin(phiDeg * DEG), Math.cos(thetaDeg * DEG)];
const luma = (f, i) => LUMINANCE[0] * f[4 * i] + LUMINANCE[1] * f[4 * i + 1] + LUMINANCE[2] * f[4 * i + 2];
const isMine = (t) => t?.meta?.role === MARK;

/** The lobe panel's directions (app/quantities.py lobe_curve): l at (θ_i, φ_i), v at
 * |θ_o| in the plane of incidence, on the mirror side (φ_i + 180°) for θ_o ≥ 0. */
export function lobePairs(thetaO, thetaI, phiI) {
  const l = [], v = [];
  const li = dir(thetaI, phiI);
  for (const t of thetaO) {
    l.push(...li);
    v.push(...dir(Math.abs(t), t >= 0 ? phiI + 180 : phiI));
  }
  return { l, v };
}

/** The NDF panel's directions (app/quantities.py ndf_curve: m at (θ_m, φ)), as l = v = h. */
export function dlikePairs(thetaM, phiDeg) {
  const l = [];
  for (const t of thetaM) l.push(...dir(t, phiDeg));
  return { l, v: l };
}

/** y(θ_h) as the NDF panel draws D: f, or f·cos θ_h (`cosine`, its D·cos θ_m); a gap
 * where not finite (a file dividing by n·l at 90°), or ≤ 0 on its log axis. */
export function dlikeValues(f, thetaM, { cosine, log }) {
  return Array.from(thetaM, (t, i) => {
    const y = luma(f, i) * (cosine ? Math.cos(t * DEG) : 1);
    return !Number.isFinite(y) || (log && !(y > 0)) ? NaN : y;
  });
}

/** r(θ_o) as the lobe panel draws it: f, or f·cos θ_o (`cosine`), NaN where ≤ 0 on a
 * log axis (lobe_figure's gaps). */
export function lobeValues(f, thetaO, { cosine, log }) {
  return Array.from(thetaO, (t, i) => {
    const y = luma(f, i) * (cosine ? Math.cos(Math.abs(t) * DEG) : 1);
    return log && !(y > 0) ? NaN : y;
  });
}

/** μ = k/(n−1), the albedo view's nodes (app/views/schemas.py AlbedoQuery), or its `mu`. */
export const albedoNodes = (params, n) => (params.mu != null ? String(params.mu).split(",").map(Number)
  : Array.from({ length: n }, (_, k) => k / (n - 1)));

export class UserCurves {
  /** user: the UserBrdf; page: { figure(name), params(name), defaults(name), overlay(name, figure) }
   * — the panel's last figure, its query, its view's field defaults, and its overlay. */
  constructor(user, page, root = document) {
    Object.assign(this, { user, page, base: new Map(), drawn: new Map(), timers: new Map(), kept: new Map(),
                          count: 0, evaluations: 0 });
    user.listen(() => this.changed());
    const drawn = (e) => {
      const name = e.target?.closest?.("[data-panel]")?.dataset.panel;
      if (VIEWS.includes(name)) this.apply(name);
    };
    // "brdf-drawn" does not bubble: heard in the capture phase (as app/data.js does)
    root.addEventListener("brdf-drawn", drawn, true);
    root.addEventListener("brdf-data-drawn", drawn, true);
  }

  changed() {
    for (const name of VIEWS) {
      clearTimeout(this.timers.get(name));
      const later = name === "albedo" && this.user.file ? ALBEDO_DELAY_MS : 0;
      this.timers.set(name, setTimeout(() => requestAnimationFrame(() => this.apply(name)), later));
    }
  }

  /** The panel's figure (as the panel or the data module drew it) with this BRDF's trace
   * in place of an earlier one, or without one when none is open. */
  apply(name) {
    const current = this.page.figure(name);
    if (!current) return;
    // a figure carrying our trace is ours: its base is the one it was made from
    const base = current.data.some(isMine) ? this.base.get(name) : current;
    if (!base) return;
    this.base.set(name, base);
    const trace = this.user.file ? this.trace(name, base) : null;
    if (!trace && !current.data.some(isMine)) return;
    this.count++;
    this.drawn.set(name, trace);
    // the NDF figure hides its one-curve legend: with the trace beside it, both are named
    const layout = trace ? { ...rangeOverAll(base.layout), ...(name === "ndf" ? { showlegend: true } : {}) } : base.layout;
    this.page.overlay(name, { data: trace ? [...base.data, trace] : base.data, layout });
  }

  /** The trace for this figure, computed again only when its inputs changed: a panel
   * redrawn for the registry model (a slider of the page) reuses the user's values. */
  trace(name, base) {
    const q = { ...this.page.defaults(name), ...this.page.params(name) };
    const nodes = name === "lobe" ? numbers(base.data.find((t) => t.type === "scatterpolar" && t.meta?.role !== "guide")?.theta)
      : name === "ndf" ? numbers(base.data.find((t) => t.type === "scatter" && !t.meta?.role)?.x) : null;
    const key = JSON.stringify([this.user.source, this.user.values, this.user.name, q.theta_i_deg, q.phi_i_deg, q.cosine,
                                q.log, q.n, q.mu, q.phi_deg, nodes && Array.from(nodes)]);
    const kept = this.kept.get(name);
    if (kept && kept.key === key) return kept.trace;
    const trace = this.compute(name, q, nodes);
    this.kept.set(name, { key, trace });
    return trace;
  }

  /** thetaO: the lobe figure's θ_o nodes, or the NDF figure's θ_m (degrees). */
  compute(name, q, thetaO) {
    const label = `${LABEL}: ${this.user.name}`;
    const flag = (k) => q[k] === true || q[k] === "true";
    if (name === "ndf") {
      if (!thetaO) return null;
      const { l, v } = dlikePairs(thetaO, Number(q.phi_deg || 0));
      const f = this.user.evaluate(l, v);
      if (!f) return null;
      this.evaluations += thetaO.length;
      const cosine = flag("cosine");
      return { type: "scatter", mode: "lines", name: cosine ? DLIKE_COS_LABEL : DLIKE_LABEL, x: Array.from(thetaO),
               y: dlikeValues(f, thetaO, { cosine, log: flag("log") }),
               line: { color: COLOR, width: 2, dash: "dot" }, meta: { role: MARK },
               hovertemplate: `θ_h=%{x:.2f}°<br>${cosine ? "f·cos θ_h" : "f"}=%{y:.4g} (l = v)<extra></extra>` };
    }
    if (name === "lobe") {
      if (!thetaO) return null;
      const { l, v } = lobePairs(thetaO, Number(q.theta_i_deg), Number(q.phi_i_deg));
      const f = this.user.evaluate(l, v);
      if (!f) return null;
      this.evaluations += thetaO.length;
      const r = lobeValues(f, thetaO, { cosine: q.cosine === true || q.cosine === "true", log: q.log === true || q.log === "true" });
      return { type: "scatterpolar", mode: "lines", name: label, theta: Array.from(thetaO), r,
               line: { color: COLOR, width: 2, dash: "dot" }, meta: { role: MARK },
               hovertemplate: "θ_o=%{theta:.1f}°<br>%{r:.4g}<extra></extra>" };
    }
    // the albedo E(μ_v) = ∫ f(l, v) (n·l) dl, the server's (app/integrate/albedo.py; the
    // directional-hemispherical reflectance of Nicodemus et al. 1977, NBS Monograph 160).
    // The grazing node μ = 0 is left out (a gap): f(l, v) there divides by
    // n·v = 0 in most files, and E(0) is the server's limit, not a value to evaluate
    const mus = albedoNodes(q, Number(q.n));
    const inside = mus.filter((mu) => mu > 0 && mu <= 1);
    if (!inside.length) return null;
    const pairs = this.albedoPairs(inside, Number(q.phi_deg || 0) * DEG);
    const f = this.user.evaluate(pairs.l, pairs.v);
    if (!f) return null;
    this.evaluations += pairs.l.length / 3;
    const E = albedoOf(f, pairs.weights, pairs.per, inside.length).map((e) => LUMINANCE[0] * e[0] + LUMINANCE[1] * e[1] + LUMINANCE[2] * e[2]);
    const y = mus.map((mu) => (mu > 0 && mu <= 1 ? E[inside.indexOf(mu)] : NaN));
    return { type: "scatter", mode: "lines+markers", name: label,
             x: mus, y, line: { color: COLOR, width: 2, dash: "dot" }, marker: { size: 4, color: COLOR },
             meta: { role: MARK },
             hovertemplate: `μ=%{x:.3f}<br>E=%{y:.6f} (GPU, Gauss-Legendre ${CURVE_NODES.mu} μ_l × midpoint ${CURVE_NODES.phi} φ)<extra></extra>` };
  }

  /** The albedo's pairs, kept while the μ nodes and the azimuth stay (they are not the
   * BRDF's: forming 0.5 M of them took 67 ms, the GPU's evaluation 190 ms, at load 7). */
  albedoPairs(mus, phiV) {
    const key = JSON.stringify([mus, phiV]);
    if (this.pairs?.key !== key) this.pairs = { key, ...albedoPairs(CURVE_NODES.mu, CURVE_NODES.phi, mus, phiV) };
    return this.pairs;
  }

  hook() {
    const self = this;
    return {
      get count() { return self.count; },
      /** GPU evaluations of f made for the traces so far. */
      get evaluations() { return self.evaluations; },
      /** The trace last added to a panel (null: none), as drawn. */
      trace: (name) => self.drawn.get(name) ?? null,
    };
  }
}
