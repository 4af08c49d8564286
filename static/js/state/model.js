/* The model registry (GET /api/v1/models) and the rules it implies for a state:
 * which parameters take part, which choices apply, the query a state stands for.
 * A state is a plain object: choice names, parameter values, and the forms chosen by
 * presence (anisotropic, perceptual, secondLobe); with a family other than the default
 * the query is that family's (families.js).
 */
import { inRange } from "./sliders.js";
import { fam, otherFamily, familyQuery, familyCompact } from "./families.js";

export const reg = { models: null, groups: [], params: new Map(), materials: [] };

/** The measured materials (GET /api/v1/materials). A material sets the Fresnel: `material=`
 * replaces `fresnel` and that choice's parameters in a query (the API refuses both). */
export const MATERIAL_REPLACES = "fresnel";
export function setMaterials(listing) {
  reg.materials = listing?.materials || [];
  reg.materialSource = listing ? `${listing.source}; ${listing.license}` : "";
}
export const materialOf = (slug) => reg.materials.find((m) => m.slug === slug);
/** The material of s, or null (a family other than the default takes none). */
export const materialIn = (s) => (!otherFamily(s) && s.material && materialOf(s.material)) || null;

export function setModels(models) {
  models.params = models.params || [];
  models.geometry = models.geometry || [];
  reg.models = models;
  reg.groups = Object.entries(models.options || {}).map(([name, g]) => ({ name, ...g }));
  reg.params = new Map();
  for (const p of [...models.params, ...models.geometry]) reg.params.set(p.name, p);
  for (const g of reg.groups) for (const c of g.choices) for (const p of c.params || []) {
    if (!reg.params.has(p.name)) reg.params.set(p.name, p);
  }
}

export const subOptions = () => Object.entries(reg.models.sub_options || {}).map(([name, g]) => ({ name, ...g }));
export const choiceOf = (group, name) => reg.groups.find((x) => x.name === group)?.choices.find((c) => c.name === name);

// α_y takes part when the toggle is on and the NDF can be anisotropic.
export const anisoAllowed = (s) => reg.params.has("alpha_y") && choiceOf("ndf", s.ndf)?.anisotropic !== false;
// The other form of the roughness: perceptual r (α = r²) and anisotropy k; the API
// takes one form or the other, never both.
export const PERCEPTUAL = { params: ["roughness", "anisotropy"], replaces: ["alpha", "alpha_y"] };
export const perceptualAllowed = () => reg.params.has("roughness");
export const isPerceptual = (s) => !!s.perceptual && perceptualAllowed();
export const isAnisotropic = (s) => !!s.anisotropic && anisoAllowed(s) && !isPerceptual(s);
// The second lobe (alpha2 with weight lobe_mix) takes part only when switched on.
export const SECOND_LOBE = ["alpha2", "lobe_mix"];
export const secondLobeAllowed = () => SECOND_LOBE.every((n) => reg.params.has(n));
// Parameters whose presence in a query says something: kept even at their default.
export const PRESENCE = new Set(["alpha_y", "roughness", "alpha2"]);

/** A parameter as the chosen choices define it (γ of GTR and of Student-t differ). */
export function paramFor(name, s) {
  for (const g of reg.groups) {
    const p = (choiceOf(g.name, s[g.name])?.params || []).find((x) => x.name === name);
    if (p) return p;
  }
  return reg.params.get(name);
}

export function choiceDefaults(s) {
  for (const g of reg.groups) for (const p of choiceOf(g.name, s[g.name])?.params || []) s[p.name] = p.default;
}

export const sameSpec = (a, b) => a.lo === b.lo && a.hi === b.hi && a.default === b.default && !!a.lo_open === !!b.lo_open;

/** Choose `name` in group g: a parameter the new choice shares with other choices under
 * another range or default starts at the new choice's default. */
export function switchChoice(g, s, name) {
  const old = choiceOf(g.name, s[g.name]);
  s[g.name] = name;
  for (const p of choiceOf(g.name, name)?.params || []) {
    const prev = (old?.params || []).find((x) => x.name === p.name);
    const shared = g.choices.filter((c) => (c.params || []).some((x) => x.name === p.name)).length > 1;
    if (prev ? !sameSpec(prev, p) : (shared || !inRange(p, s[p.name]))) s[p.name] = p.default;
  }
}

function anisoAlpha(s) {
  if (isAnisotropic(s)) return s.alpha_y !== s.alpha;
  return isPerceptual(s) && anisoAllowed(s) && s.anisotropy > 0;
}

/** A choice applies to the NDF of s (applies_to) and, if isotropic_only, to its α. */
export function appliesTo(choice, s) {
  if (choice.applies_to && !choice.applies_to.includes(s.ndf)) return false;
  return !(choice.isotropic_only && anisoAlpha(s));
}
export function whyNot(choice, s) {
  if (choice.applies_to && !choice.applies_to.includes(s.ndf)) return `only for ${choice.applies_to.join(", ")}`;
  return "isotropic roughness only (α_y = α)";
}

/** A sub-option is sent only where it applies (the API refuses it elsewhere). */
export function subApplies(name, s) {
  if (name === "lambda_phi") return !!choiceOf("g2", s.g2)?.needs_phi;
  if (name === "aniso_map") return isPerceptual(s) && anisoAllowed(s);
  return false;   // an unknown sub-option: its rule is not known here, so never sent
}

/** The continuous parameters that belong in a query for state s, in a fixed order. */
export function activeParams(s) {
  const out = [];
  for (const p of reg.models.params) {
    if (p.name === "alpha_y" && !isAnisotropic(s)) continue;
    if (PERCEPTUAL.params.includes(p.name) && !isPerceptual(s)) continue;
    if (PERCEPTUAL.replaces.includes(p.name) && isPerceptual(s)) continue;
    if (p.name === "anisotropy" && !anisoAllowed(s)) continue;
    if (SECOND_LOBE.includes(p.name) && !s.secondLobe) continue;
    out.push(p);
  }
  for (const g of reg.groups) {
    if (g.name === MATERIAL_REPLACES && materialIn(s)) continue;
    for (const p of choiceOf(g.name, s[g.name])?.params || []) if (!out.some((q) => q.name === p.name)) out.push(p);
  }
  return out;
}

/** The option groups a query of s names (the Fresnel's is the material's when one is chosen). */
export const activeGroups = (s) => reg.groups.filter((g) => !(g.name === MATERIAL_REPLACES && materialIn(s)));

export function modelQuery(s) {
  const f = otherFamily(s);
  if (f) return familyQuery(f, s.families[f.name]);
  const q = {};
  for (const g of activeGroups(s)) q[g.name] = s[g.name];
  if (materialIn(s)) q.material = s.material;
  for (const g of subOptions()) if (subApplies(g.name, s)) q[g.name] = s[g.name];
  for (const p of activeParams(s)) q[p.name] = s[p.name];
  return q;
}

/** A query without the values that are the API's defaults anyway. */
export function compact(q) {
  if (q.model !== undefined && q.model !== fam.default) return familyCompact(q);
  const out = {};
  const named = [...reg.groups, ...subOptions()];
  for (const [k, v] of Object.entries(q)) {
    const g = named.find((x) => x.name === k);
    const p = paramFor(k, q);
    if (!PRESENCE.has(k) && ((g && v === g.default) || (p && v === p.default))) continue;
    out[k] = v;
  }
  return out;
}

/** A masking or G2 that does not apply (to the NDF, to anisotropic α) is replaced by
 * the group's default, or else the first choice that applies; returns the notes. */
export function fixApplicability(s) {
  const notes = [];
  for (const g of reg.groups) {
    const c = choiceOf(g.name, s[g.name]);
    if (!c || appliesTo(c, s)) continue;
    const alt = [choiceOf(g.name, g.default), ...g.choices].find((x) => x && appliesTo(x, s));
    if (alt) {
      const what = c.applies_to && !c.applies_to.includes(s.ndf) ? `does not apply to ${s.ndf}` : "is for isotropic roughness only";
      notes.push(`${g.label} “${c.label}” ${what}; using “${alt.label}”.`);
      s[g.name] = alt.name;
    }
  }
  return notes;
}

/** The defaults: every choice and parameter at the API's default, one form each. */
export function modelDefaults() {
  const s = {};
  for (const g of reg.groups) s[g.name] = g.default;
  for (const p of reg.params.values()) s[p.name] = p.default;
  for (const g of subOptions()) s[g.name] = g.default;
  choiceDefaults(s);
  Object.assign(s, { anisotropic: false, perceptual: false, secondLobe: false, material: "" });
  return s;
}
