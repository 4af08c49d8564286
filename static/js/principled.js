/* The principled BRDF (Burley 2012) as GET /api/v1/principled describes it: its
 * parameters and options, which views take it, its query and its link.
 * Its values live in state.principled, apart from the microfacet model's (both keep
 * their values while the other model is shown); state.model says which one is drawn.
 * base_color is kept as [r, g, b] and sent as the API's "r,g,b".
 */
import { inRange, rangeText, clampParam } from "./sliders.js";

export const PRINCIPLED = "principled";
export const MICROFACET = "microfacet";
/** The choice of model (the API's `model`), as the sidebar offers it. */
export const MODELS = [
  { name: MICROFACET, label: "Microfacet (choose D, G, F)",
    description: "A specular microfacet lobe built from your choice of NDF, masking, G2 and Fresnel, with a diffuse term." },
  { name: PRINCIPLED, label: "Principled (Burley 2012)",
    description: "Disney's principled BRDF: base colour, metallic, roughness, sheen, clearcoat… each in [0, 1]." },
];

export const preg = { cat: null, params: [], options: [], views: new Set(), why: {} };

export function setPrincipled(cat) {
  preg.cat = cat;
  preg.params = cat ? cat.params : [];
  preg.options = cat ? Object.entries(cat.options || {}).map(([name, g]) => ({ name, ...g })) : [];
  preg.views = new Set(cat?.views || []);
  preg.why = cat?.microfacet_only || {};
}

export const principledAvailable = () => !!preg.cat;
export const isPrincipled = (s) => s.model === PRINCIPLED && principledAvailable();
/** Whether a view draws the model of s (the microfacet model: every view). */
export const viewTakes = (view, s) => !isPrincipled(s) || preg.views.has(view);
export const whyMicrofacetOnly = (view) => preg.why[view] || "";
/** Every name the principled model takes (besides `model`). */
export const principledNames = () => ["base_color", ...preg.params.map((p) => p.name), ...preg.options.map((g) => g.name)];
export const optionOf = (name) => preg.options.find((g) => g.name === name);

/** A choice applies unless it is for isotropic roughness only and anisotropic > 0. */
export const choiceApplies = (c, p) => !(c?.isotropic_only && p.anisotropic > 0);

export function principledDefaults() {
  const p = { base_color: [...(preg.cat?.base_color.default || [])] };
  for (const x of preg.params) p[x.name] = x.default;
  for (const g of preg.options) p[g.name] = g.default;
  return p;
}

export const colorText = (rgb) => rgb.map((x) => String(x)).join(",");
/** "r,g,b" -> [r, g, b] in the catalogue's range, or null. */
export function parseColor(text) {
  const parts = String(text).split(",").map((x) => (x.trim() === "" ? NaN : Number(x)));
  const { lo, hi } = preg.cat?.base_color || { lo: 0, hi: 1 };
  return parts.length === 3 && parts.every((x) => Number.isFinite(x) && x >= lo && x <= hi) ? parts : null;
}

/** The query of principled values p: model=principled and every value. */
export function principledQuery(p) {
  const q = { model: PRINCIPLED, base_color: colorText(p.base_color) };
  for (const x of preg.params) q[x.name] = p[x.name];
  for (const g of preg.options) q[g.name] = p[g.name];
  return q;
}

/** A principled query without the values that are the API's defaults anyway (model kept). */
export function principledCompact(q) {
  const d = principledQuery(principledDefaults());
  const out = {};
  for (const [k, v] of Object.entries(q)) if (k === "model" || v !== d[k]) out[k] = v;
  return out;
}

/** Values by name (from a link or a pin: get(name) -> text or null) into p; returns
 * notes for what was corrected or left out, as the microfacet reader says them. */
export function readPrincipled(p, get) {
  const notes = [];
  const color = get("base_color");
  if (color !== null) {
    const rgb = parseColor(color);
    if (rgb) p.base_color = rgb;
    else notes.push(`base_color=${color} is not three numbers r,g,b in [0, 1]; using ${colorText(p.base_color)}.`);
  }
  for (const x of preg.params) {
    const raw = get(x.name);
    if (raw === null) continue;
    const v = raw.trim() === "" ? NaN : Number(raw);
    if (!Number.isFinite(v)) notes.push(`${x.name}=${raw} is not a number; using ${p[x.name]}.`);
    else if (!inRange(x, v)) {
      p[x.name] = clampParam(x, v);
      notes.push(`${x.name}=${raw} is outside ${rangeText(x)}; using ${p[x.name]}.`);
    } else p[x.name] = v;
  }
  for (const g of preg.options) {
    const v = get(g.name);
    if (v === null) continue;
    if (g.choices.some((c) => c.name === v)) p[g.name] = v;
    else notes.push(`${g.name}=${v} is not one of ${g.choices.map((c) => c.name).join(", ")}; using ${p[g.name]}.`);
  }
  return notes;
}

/** A choice that does not apply (Kulla-Conty with anisotropic > 0) is replaced by its
 * option's default; returns the notes. */
export function fixPrincipled(p) {
  const notes = [];
  for (const g of preg.options) {
    const c = g.choices.find((x) => x.name === p[g.name]);
    if (choiceApplies(c, p)) continue;
    const alt = g.choices.find((x) => x.name === g.default && choiceApplies(x, p)) || g.choices.find((x) => choiceApplies(x, p));
    if (!alt) continue;
    notes.push(`${g.label} “${c.label}” is for isotropic roughness only (anisotropic = 0); using “${alt.label}”.`);
    p[g.name] = alt.name;
  }
  return notes;
}

/** Link <- principled values p: model=principled, then what differs from the defaults. */
export function writePrincipled(p, q) {
  for (const [k, v] of Object.entries(principledCompact(principledQuery(p)))) q.set(k, String(v));
}
