/* THE state and its URL. One plain object is the single source of truth; the URL
 * carries its non-default values (API names), so a link restores the page exactly.
 * Values the API would refuse are corrected and said so; parameters the API does not
 * know are flagged, as the API flags them. `model=<family>` of a family other than the
 * default carries that family's values instead of the default's (families.js).
 */
import { reg, subOptions, paramFor, choiceDefaults, activeParams, activeGroups, subApplies, fixApplicability,
         perceptualAllowed, secondLobeAllowed, materialIn, materialOf, PRESENCE, MATERIAL_REPLACES } from "./model.js";
import { inRange, rangeText, clampParam } from "./sliders.js";
import { fam, otherFamily, writeFamily, readFamily, fixFamily, familyNames } from "./families.js";
import { ctx } from "../base/ctx.js";
import { encodePin, decodePin, samePin, MAX_PINS } from "./pins.js";


export const TRUE_WORDS = new Set(["1", "true", "yes", "on"]);
// Page parameters that are not the API's: which panels, a comparison, pins, embedding.
const PAGE_PARAMS = new Set(["show", "vary", "values", "pin", "embed", "lobe3d"]);

/** State -> page URL: API names, only non-default values (a presence parameter such as
 * alpha_y always), one `pin` per pinned model. */
export function stateToSearch(s) {
  const q = new URLSearchParams();
  const f = otherFamily(s);
  if (f) writeFamily(f, s.families[f.name], q);
  else {
    for (const g of activeGroups(s)) if (s[g.name] !== g.default) q.set(g.name, s[g.name]);
    if (materialIn(s)) q.set("material", s.material);
    for (const g of subOptions()) if (subApplies(g.name, s) && s[g.name] !== g.default) q.set(g.name, s[g.name]);
    for (const p of activeParams(s)) if (PRESENCE.has(p.name) || s[p.name] !== p.default) q.set(p.name, String(s[p.name]));
  }
  for (const p of reg.models.geometry) if (s[p.name] !== p.default) q.set(p.name, String(s[p.name]));
  for (const key of ctx.locals.keys()) if (s[key] !== ctx.defaultState[key]) q.set(key, String(s[key]));
  const shown = ctx.panelList.filter((v) => s.show.includes(v.name)).map((v) => v.name);
  if (shown.join(",") !== ctx.defaultState.show.join(",")) q.set("show", shown.join(",") || "none");
  if (s.vary) {
    q.set("vary", s.vary);
    q.set("values", s.values);
  }
  for (const pin of s.pins) q.append("pin", encodePin(pin));
  for (const [k, v] of Object.entries(s.extra || {})) q.set(k, v);
  if (ctx.embed) q.set("embed", "1");
  // ':', ',' and '/' may stand as they are in a query (RFC 3986 3.4): readable pins and lists
  const str = q.toString().replace(/%3A/gi, ":").replace(/%2C/gi, ",").replace(/%2F/gi, "/");
  return str ? `?${str}` : "";
}

function readLocal(s, key, f, raw, notes) {
  if (f.type === "boolean") s[key] = TRUE_WORDS.has(raw.toLowerCase());
  else if (f.enum) {
    if (f.enum.includes(raw)) s[key] = raw;
    else notes.push(`${key}=${raw} is not one of ${f.enum.join(", ")}; using ${f.default}.`);
  } else {
    const x = Number(raw);
    if (raw.trim() !== "" && Number.isFinite(x) && x >= f.minimum && x <= f.maximum) s[key] = x;
    else notes.push(`${key}=${raw} is not a number in [${f.minimum}, ${f.maximum}]; using ${f.default}.`);
  }
}

function readParam(s, p, raw, notes) {
  if (raw === null) return;
  const x = raw.trim() === "" ? NaN : Number(raw);
  if (!Number.isFinite(x)) notes.push(`${p.name}=${raw} is not a number; using ${p.default}.`);
  else if (!inRange(p, x)) {
    s[p.name] = clampParam(p, x);
    notes.push(`${p.name}=${raw} is outside ${rangeText(p)}; using ${s[p.name]}.`);
  } else s[p.name] = x;
}

/** The microfacet model's choices, parameters and forms from a link. */
function readMicrofacet(s, q, named, notes) {
  for (const g of named) {
    const v = q.get(g.name);
    if (v === null) continue;
    if (g.choices.some((c) => c.name === v)) s[g.name] = v;
    else notes.push(`${g.name}=${v} is not one of ${g.choices.map((c) => c.name).join(", ")}; using ${g.default}.`);
  }
  choiceDefaults(s);
  for (const name of reg.params.keys()) {
    const p = paramFor(name, s);
    readParam(s, p, q.get(p.name), notes);
  }
  s.anisotropic = reg.params.has("alpha_y") && q.has("alpha_y");
  s.perceptual = perceptualAllowed() && q.has("roughness");
  s.secondLobe = secondLobeAllowed() && q.has("alpha2");
  readMaterial(s, q, notes);
}

/** material=<slug> (GET /api/v1/materials): it sets the Fresnel, so a Fresnel named beside
 * it is left out, as the API would refuse the pair. */
function readMaterial(s, q, notes) {
  const slug = q.get("material");
  if (slug === null || slug === "") return;
  if (!materialOf(slug)) {
    const near = reg.materials.filter((m) => m.slug.startsWith(slug.toLowerCase().slice(0, 3))).map((m) => m.slug);
    notes.push(`material=${slug} is not a measured material${near.length ? ` (did you mean ${near.slice(0, 4).join(", ")}?)` : ""}; `
               + "using the Fresnel menu.");
    return;
  }
  s.material = slug;
  const replaced = reg.groups.find((g) => g.name === MATERIAL_REPLACES);
  const given = [MATERIAL_REPLACES, ...replaced.choices.flatMap((c) => (c.params || []).map((p) => p.name))].filter((k) => q.has(k));
  if (given.length) notes.push(`${[...new Set(given)].join(", ")}: set by material=${slug}; ignored.`);
}

/** A family's values and the geometry from a link; the names of other families there
 * are said to be left out (the API refuses them with this model). */
function readFamilyLink(s, f, q, foreign, notes) {
  const p = s.families[f.name];
  notes.push(...readFamily(f, p, (k) => q.get(k)), ...fixFamily(f, p));
  const geometry = reg.models.geometry;
  for (const x of geometry) readParam(s, x, q.get(x.name), notes);
  const own = new Set(familyNames(f));
  const alien = [...foreign].filter((k) => q.has(k) && !own.has(k) && !geometry.some((x) => x.name === k));
  if (alien.length) notes.push(`${alien.join(", ")}: not a parameter of model=${f.name}; ignored.`);
}

/** Page URL -> {s, notes}: a hand-edited link always opens a working page, and says
 * what it changed or left out. */
export function stateFromSearch(search) {
  const q = new URLSearchParams(search);
  const s = structuredClone(ctx.defaultState);
  const notes = [];
  const named = [...reg.groups, ...subOptions()];
  const model = q.get("model");
  if (model !== null && fam.byName.has(model)) s.model = model;
  else if (model !== null) {
    notes.push(`model=${model} is not one of ${[...fam.byName.keys()].join(", ")}; using ${fam.default}.`);
  }
  // every name some family other than the default takes, and the default's
  const others = new Set(fam.list.filter((x) => x.name !== fam.default).flatMap(familyNames));
  const defaults = new Set([...named.map((g) => g.name), ...reg.params.keys(), "material"]);
  const f = otherFamily(s);
  if (f) readFamilyLink(s, f, q, new Set([...defaults, ...others]), notes);
  else {
    readMicrofacet(s, q, named, notes);
    const alien = [...others].filter((k) => q.has(k) && !reg.params.has(k));
    if (alien.length) {
      const owners = (k) => fam.list.filter((x) => familyNames(x).includes(k)).map((x) => `model=${x.name}`).join(" or ");
      notes.push(`${alien.map((k) => `${k} (only with ${owners(k)})`).join(", ")}: ignored.`);
    }
  }
  for (const [key, loc] of ctx.locals) {
    const raw = q.get(key);
    if (raw !== null) readLocal(s, key, loc.field, raw, notes);
  }
  const names = ctx.panelList.map((v) => v.name);
  if (q.has("show")) {
    const want = q.get("show").split(",").map((x) => x.trim()).filter(Boolean);
    const unknown = want.filter((n) => n !== "none" && !names.includes(n));
    if (unknown.length) notes.push(`show=${unknown.join(",")}: no such panel.`);
    s.show = names.filter((n) => want.includes(n));
  }
  if (TRUE_WORDS.has((q.get("lobe3d") || "").toLowerCase()) && !s.show.includes("lobe3d")) {
    s.show = names.filter((n) => n === "lobe3d" || s.show.includes(n));
  }
  if (q.get("vary") && q.get("values")) {
    s.vary = q.get("vary");
    s.values = q.get("values");
  }
  notes.push(...fixApplicability(s));
  s.pins = [];
  for (const raw of q.getAll("pin")) {
    const { pin, note } = decodePin(raw);
    if (note) notes.push(note);
    if (pin && !s.pins.some((x) => samePin(x, pin)) && s.pins.length < MAX_PINS) s.pins.push(pin);
  }
  s.extra = {};
  for (const k of ctx.extraKeys) if (q.has(k)) s.extra[k] = q.get(k);
  const known = new Set([...named.map((g) => g.name), ...reg.params.keys(), ...ctx.locals.keys(), ...PAGE_PARAMS,
                         ...ctx.extraKeys, ...others, "model", "material"]);
  const unknown = [...new Set(q.keys())].filter((k) => !known.has(k));
  if (unknown.length) {
    notes.push(`Unknown parameter${unknown.length > 1 ? "s" : ""} ${unknown.map((k) => `“${k}”`).join(", ")}: `
               + "ignored here (the API refuses it). Check the spelling against the API's parameter names.");
  }
  return { s, notes, unknown };
}

// URL <- state, URL_WRITE_MS after a change: off the path from a slider to the plots (a
// replaceState costs milliseconds, and Chrome throttles it past ~200 calls per 10 s).
// While a slider is held (ctx.held) it waits for the release: a replaceState took 5 ms of
// main thread (its same-document navigation), 7 times a second of a drag, in the frames
// the drag's redraws need.
const URL_WRITE_MS = 150;
let urlTimer = 0;
let urlAfterHold = false;
function writeUrl() {
  urlTimer = 0;
  const search = stateToSearch(ctx.state);
  if (search !== location.search) history.replaceState(null, "", location.pathname + search);
  for (const a of document.querySelectorAll("a[data-query]")) a.search = search;   // links that carry the state
}
export function scheduleUrlWrite() {
  if (ctx.held) urlAfterHold = true;
  else if (!urlTimer) urlTimer = setTimeout(writeUrl, URL_WRITE_MS);
}
/** The slider let go: the URL a held slider left unwritten is written. */
export function releaseUrlWrite() {
  if (urlAfterHold && !ctx.held) {
    urlAfterHold = false;
    scheduleUrlWrite();
  }
}
export const urlPending = () => (urlTimer ? 1 : 0);
