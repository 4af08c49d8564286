/* Pinned models: kept as their non-default model parameters (a POST /figures/{kind}
 * "models" entry as it stands). In the URL each pin is one `pin` parameter, name:value
 * entries joined by commas, e.g. ?pin=ndf:beckmann,alpha:0.2 (names and choice values
 * are [a-z0-9_], numbers plain decimals: neither ':' nor ',' occurs inside one).
 * A pin always names its ndf, or model:<family> of another family; the rest are the
 * values that differ from the defaults. A value's own commas (a colour's r,g,b) are
 * written as '/'.
 */
import { reg, subOptions, paramFor, choiceDefaults, fixApplicability, modelQuery, compact,
         isPerceptual, isAnisotropic, materialOf } from "./model.js";
import { inRange, rangeText } from "./sliders.js";
import { ctx } from "../base/ctx.js";
import { fam, otherFamily, familyDefaults, readFamily, fixFamily, familyNames } from "./families.js";

export const MAX_PINS = 6;                // a legend of 7 curves is still readable

export const encodePin = (pin) => Object.entries(pin).map(([k, v]) => `${k}:${String(v).replace(/,/g, "/")}`).join(",");
export const samePin = (a, b) => encodePin(a) === encodePin(b);
/** The model of state s as a pin: its NDF (or model:<family>) always, then what
 * differs from the defaults. */
export const pinOf = (s) => (otherFamily(s) ? compact(modelQuery(s)) : { ndf: s.ndf, ...compact(modelQuery(s)) });
const familyOfPin = (pin) => (pin.model !== undefined && pin.model !== fam.default && fam.byName.get(pin.model)) || null;

/** The state a pin stands for; the forms chosen by presence follow from its keys. */
export function pinState(pin) {
  const s = structuredClone(ctx.defaultState);
  const f = familyOfPin(pin);
  if (f) {
    Object.assign(s, { model: f.name, pins: [] });
    s.families[f.name] = familyDefaults(f);
    readFamily(f, s.families[f.name], (k) => (k in pin ? String(pin[k]) : null));
    return s;
  }
  for (const g of reg.groups) if (pin[g.name]) s[g.name] = pin[g.name];
  choiceDefaults(s);
  Object.assign(s, pin);
  s.anisotropic = "alpha_y" in pin;
  s.perceptual = "roughness" in pin;
  s.secondLobe = "alpha2" in pin;
  s.pins = [];
  return s;
}

/** One `pin` value -> {pin} or {note} saying why it was left out. */
export function decodePin(raw) {
  const bad = (why) => ({ pin: null, note: `pin=${raw}: ${why}; left out.` });
  const entries = [];
  for (const part of raw.split(",")) {
    const i = part.indexOf(":");
    if (i < 1) return bad(`“${part}” is not name:value`);
    entries.push([part.slice(0, i).trim(), part.slice(i + 1).trim()]);
  }
  const model = entries.find(([k]) => k === "model")?.[1];
  if (model !== undefined && model !== fam.default && fam.byName.has(model)) {
    return decodeFamily(fam.byName.get(model), entries, bad);
  }
  if (model !== undefined && model !== fam.default) return bad(`model=${model} is not a model the page knows`);
  const own = entries.filter(([k]) => k !== "model");          // model:<the default> is the default
  const choices = Object.fromEntries(own.filter(([k]) => reg.groups.some((g) => g.name === k)));
  const geometry = new Set(reg.models.geometry.map((x) => x.name));
  const pin = {};
  for (const [k, v] of own) {
    const g = [...reg.groups, ...subOptions()].find((x) => x.name === k);
    const p = reg.params.has(k) && !geometry.has(k) ? paramFor(k, choices) : null;
    if (k === "material") {
      if (!materialOf(v)) return bad(`material=${v} is not a measured material`);
      pin[k] = v;
    } else if (g) {
      if (!g.choices.some((c) => c.name === v)) return bad(`${k}=${v} is not one of ${g.choices.map((c) => c.name).join(", ")}`);
      pin[k] = v;
    } else if (p) {
      const x = v === "" ? NaN : Number(v);
      if (!Number.isFinite(x) || !inRange(p, x)) return bad(`${k}=${v} is not a number in ${rangeText(p)}`);
      pin[k] = x;
    } else {
      return bad(`${k} is not a model parameter`);
    }
  }
  const s = pinState(pin);
  const notes = fixApplicability(s);
  if (notes.length) return bad(notes[0]);
  return { pin: pinOf(s), note: null };     // canonical: parameters that take no part dropped
}

function decodeFamily(f, entries, bad) {
  const names = new Set(familyNames(f));
  const alien = entries.find(([k]) => k !== "model" && !names.has(k));
  if (alien) return bad(`${alien[0]} is not a parameter of model=${f.name}`);
  const given = new Map(entries.map(([k, v]) => [k, v.replace(/\//g, ",")]));
  const s = pinState({ model: f.name });
  const p = s.families[f.name];
  const notes = [...readFamily(f, p, (k) => given.get(k) ?? null), ...fixFamily(f, p)];
  if (notes.length) return bad(notes[0]);
  return { pin: pinOf(s), note: null };
}

/** A short name: the NDF and roughness always, then what else differs. */
export function pinLabel(pin) {
  const f = familyOfPin(pin);
  if (f) {
    // the family's roughness always (its symbol: the label's last word, "roughness r" → r)
    const rough = f.params.find((p) => p.name === f.roughness_param);
    const { model, [rough?.name]: r, ...rest } = pin;
    const head = rough ? `${model} ${rough.label.split(" ").at(-1)}=${r ?? pinState(pin).families[f.name][rough.name]}` : model;
    return [head, ...Object.entries(rest).map(([k, v]) => `${k}=${v}`)].join(", ");
  }
  const s = pinState(pin);
  const q = modelQuery(s);
  const parts = [q.ndf];
  if (isPerceptual(s)) parts.push(`r=${q.roughness}`);
  else parts.push(isAnisotropic(s) ? `α=${q.alpha}×${q.alpha_y}` : `α=${q.alpha}`);
  for (const [k, v] of Object.entries(pin)) {
    if (["ndf", "alpha", "alpha_y", "roughness"].includes(k)) continue;
    parts.push(reg.groups.some((g) => g.name === k) ? String(v) : `${k}=${v}`);
  }
  return parts.join(", ");
}

/** POST /figures/{kind} body: the pins and the current model (once), labelled as in
 * the pin list, the current one marked "now". */
export function compareModels(s) {
  const current = pinOf(s);
  const models = [...s.pins];
  const labels = s.pins.map((pin) => (samePin(pin, current) ? `${pinLabel(pin)} (now)` : pinLabel(pin)));
  if (!s.pins.some((pin) => samePin(pin, current))) {
    models.push(current);
    labels.push(`now: ${pinLabel(current)}`);
  }
  return { models, labels };
}
