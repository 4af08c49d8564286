/* The model families (GET /api/v1/models, "models"): which there are, the default one
 * (whose controls model.js and sidebar.js build from the options and parameters at the
 * top level of the same answer), and for every other family its colours, parameters,
 * options, the views that draw it, its query and its link. Nothing here knows a family
 * by name: a family added to the server appears in the menu with its controls.
 * The values of family F live in state.families[F] (each family keeps its values while
 * another is shown); state.model says which family is drawn. A colour is kept as
 * [r, g, b] and sent as the API's "r,g,b".
 */
import { inRange, rangeText, clampParam } from "./sliders.js";

export const fam = { list: [], byName: new Map(), default: "" };

/** The families of GET /api/v1/models (an older server lists none: its one model is the default). */
export function setFamilies(models) {
  const list = models.models || [];
  fam.list = list.map((f) => ({ ...f, colors: f.colors || [], params: f.params || [],
    options: Object.entries(f.options || {}).map(([name, g]) => ({ name, ...g })) }));
  fam.byName = new Map(fam.list.map((f) => [f.name, f]));
  fam.default = (fam.list.find((f) => f.default) || fam.list[0])?.name ?? "";
}

/** The family of state s when it is not the default one (its values are s.families[name]). */
export const otherFamily = (s) => (s.model !== fam.default && fam.byName.get(s.model)) || null;
/** Whether a view draws the model of s. */
export const viewTakes = (view, s) => { const f = fam.byName.get(s.model); return !f?.views || f.views.includes(view); };
export const whyNot = (view, s) => fam.byName.get(s.model)?.refused_views?.[view] || "";
/** Every name family f takes (besides `model`). */
export const familyNames = (f) => [...f.colors.map((c) => c.name), ...f.params.map((p) => p.name), ...f.options.map((g) => g.name)];
export const optionOf = (f, name) => f.options.find((g) => g.name === name);
/** A choice applies unless it requires a parameter at 0 that is not (Kulla-Conty and anisotropic > 0). */
export const choiceApplies = (c, p) => !(c?.requires_zero && p[c.requires_zero] > 0);
/** Whether the model of s is anisotropic, for a family that names its anisotropy parameter. */
export const familyAnisotropic = (s) => { const f = otherFamily(s); return !!f?.anisotropy_param && s.families[f.name][f.anisotropy_param] > 0; };
/** The roughness r of the model of s (α = r²), for a family that names it; else null. */
export const familyRoughness = (s) => { const f = otherFamily(s); return f?.roughness_param ? s.families[f.name][f.roughness_param] : null; };

export function familyDefaults(f) {
  const p = {};
  for (const c of f.colors) p[c.name] = [...c.default];
  for (const x of f.params) p[x.name] = x.default;
  for (const g of f.options) p[g.name] = g.default;
  return p;
}
/** Every non-default family's defaults: the state's `families`. */
export const allFamilyDefaults = () => Object.fromEntries(fam.list.filter((f) => f.name !== fam.default).map((f) => [f.name, familyDefaults(f)]));

export const colorText = (rgb) => rgb.map((x) => String(x)).join(",");
/** "r,g,b" -> [r, g, b] in colour c's range, or null. */
export function parseColor(text, c = { lo: 0, hi: 1 }) {
  const parts = String(text).split(",").map((x) => (x.trim() === "" ? NaN : Number(x)));
  return parts.length === 3 && parts.every((x) => Number.isFinite(x) && x >= c.lo && x <= c.hi) ? parts : null;
}

/** The query of family f's values p: model=<f> and every value. */
export function familyQuery(f, p) {
  const q = { model: f.name };
  for (const c of f.colors) q[c.name] = colorText(p[c.name]);
  for (const x of f.params) q[x.name] = p[x.name];
  for (const g of f.options) q[g.name] = p[g.name];
  return q;
}

/** A family's query without the values that are the API's defaults anyway (model kept). */
export function familyCompact(q) {
  const f = fam.byName.get(q.model);
  const d = familyQuery(f, familyDefaults(f));
  const out = {};
  for (const [k, v] of Object.entries(q)) if (k === "model" || v !== d[k]) out[k] = v;
  return out;
}

/** Values by name (from a link or a pin: get(name) -> text or null) into p; returns
 * notes for what was corrected or left out, as the microfacet reader says them. */
export function readFamily(f, p, get) {
  const notes = [];
  for (const c of f.colors) {
    const text = get(c.name);
    if (text === null) continue;
    const rgb = parseColor(text, c);
    if (rgb) p[c.name] = rgb;
    else notes.push(`${c.name}=${text} is not three numbers r,g,b in [${c.lo}, ${c.hi}]; using ${colorText(p[c.name])}.`);
  }
  for (const x of f.params) {
    const raw = get(x.name);
    if (raw === null) continue;
    const v = raw.trim() === "" ? NaN : Number(raw);
    if (!Number.isFinite(v)) notes.push(`${x.name}=${raw} is not a number; using ${p[x.name]}.`);
    else if (!inRange(x, v)) {
      p[x.name] = clampParam(x, v);
      notes.push(`${x.name}=${raw} is outside ${rangeText(x)}; using ${p[x.name]}.`);
    } else p[x.name] = v;
  }
  for (const g of f.options) {
    const v = get(g.name);
    if (v === null) continue;
    if (g.choices.some((c) => c.name === v)) p[g.name] = v;
    else notes.push(`${g.name}=${v} is not one of ${g.choices.map((c) => c.name).join(", ")}; using ${p[g.name]}.`);
  }
  return notes;
}

/** A choice that does not apply (Kulla-Conty with anisotropic > 0) is replaced by its
 * option's default; returns the notes. */
export function fixFamily(f, p) {
  const notes = [];
  for (const g of f.options) {
    const c = g.choices.find((x) => x.name === p[g.name]);
    if (choiceApplies(c, p)) continue;
    const alt = g.choices.find((x) => x.name === g.default && choiceApplies(x, p)) || g.choices.find((x) => choiceApplies(x, p));
    if (!alt) continue;
    notes.push(`${g.label} “${c.label}” needs ${c.requires_zero} = 0; using “${alt.label}”.`);
    p[g.name] = alt.name;
  }
  return notes;
}
/** fixFamily for the family of state s (none for the default family). */
export const fixModel = (s) => { const f = otherFamily(s); return f ? fixFamily(f, s.families[f.name]) : []; };

/** Link <- family f's values p: model=<f>, then what differs from the defaults. */
export function writeFamily(f, p, q) {
  for (const [k, v] of Object.entries(familyCompact(familyQuery(f, p)))) q.set(k, String(v));
}
