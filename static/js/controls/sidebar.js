/* The sidebar: the choice of model family, then its controls, all from GET /api/v1/models:
 * the default family's (menus from the option choices, sliders from the parameters), every
 * other family's from its entry (familyform.js); only the chosen family's are shown. Kept
 * in step with the state.
 */
import { el, $, richText, setIf } from "../base/dom.js";
import { paramControl } from "../state/sliders.js";
import { reg, subOptions, choiceOf, sameSpec, switchChoice, fixApplicability, appliesTo, whyNot,
         subApplies, activeParams, anisoAllowed, isAnisotropic, isPerceptual, secondLobeAllowed,
         materialIn, MATERIAL_REPLACES } from "../state/model.js";
import { ctx } from "../base/ctx.js";
import { fam, fixModel } from "../state/families.js";
import { familySections, syncFamilyForms } from "./familyform.js";

const SECOND_LOBE_START_MIX = 0.5;
export const controls = new Map();       // state key -> {param, row, box, slider, set}

// The element id of a parameter's number box: the API name without "_deg".
const controlId = (name) => name.replace(/_deg$/, "");

function section(title, ...kids) {
  return el("fieldset", { class: "group" }, el("legend", { text: title }), ...kids);
}

// A measured material in the model menu: the microfacet model with material=<slug>
const MATERIAL_PREFIX = "material:";
const MATERIAL_GROUPS = { conductor: "Measured metals (RGB n, k)", dielectric: "Measured dielectrics (index n)" };

/** The model menu, at the top: every family | a measured material (the default family
 * whose Fresnel is the material's); the rest of the sidebar follows. */
function modelSelect(on) {
  const sel = el("select", { id: "model", name: "model" });
  for (const m of fam.list) sel.append(el("option", { value: m.name, text: m.label, title: m.description }));
  for (const [kind, label] of Object.entries(MATERIAL_GROUPS)) {
    const list = reg.materials.filter((m) => m.kind === kind);
    if (!list.length) continue;
    sel.append(el("optgroup", { label }, ...list.map((m) => el("option", { value: MATERIAL_PREFIX + m.slug, text: m.name }))));
  }
  sel.addEventListener("change", () => {
    const s = ctx.state;
    const slug = sel.value.startsWith(MATERIAL_PREFIX) ? sel.value.slice(MATERIAL_PREFIX.length) : "";
    s.model = slug ? fam.default : sel.value;
    s.material = slug;
    on.notices(fixModel(s));
    syncSidebar();
    on.change();
  });
  const f = section("Model", el("div", { class: "choice" },
    el("label", { for: "model", class: "sr-only", text: "BRDF model or measured material" }), sel,
    el("p", { class: "choice-info", id: "model-info" })));
  f.classList.add("model-group");
  return f;
}

/** What the model menu's choice is, in a sentence. */
function modelInfo(s) {
  const m = materialIn(s);
  if (!m) return fam.byName.get(s.model)?.description || "";
  const what = m.kind === "conductor" ? "a metal: its measured complex index n, k per RGB channel"
    : "a dielectric: its measured index n";
  const base = fam.byName.get(fam.default)?.label || "";
  return `${m.name}, ${what}, sets the Fresnel of the ${base.toLowerCase()} (physicallybased.info, CC0). `
    + `Choose “${base}” to pick a Fresnel yourself.`;
}

const ofDefault = (fieldset) => { fieldset.dataset.model = fam.default; return fieldset; };

function toggle(id, text, title, onChange) {
  const box = el("input", { type: "checkbox", id, name: id });
  box.addEventListener("change", () => onChange(box.checked));
  return el("label", { class: "toggle aniso", for: id, title }, box, el("span", {}, richText(text)));
}

/* Builds the form. on: {change(), hold(held), notices(list), pin(), clearPins()}. */
export function buildSidebar(on) {
  const form = $("#controls-form");
  form.textContent = "";
  controls.clear();
  const s = ctx.state;
  const control = (p, key = p.name) => {
    const c = paramControl(p, { id: key === p.name ? controlId(p.name) : key, onHold: on.hold,
                                onValue: (x) => { s[p.name] = x; on.change(); } });
    controls.set(key, { param: p, ...c });
    return c.row;
  };
  const subSelect = (g) => {
    const sel = el("select", { id: g.name, name: g.name });
    for (const c of g.choices) sel.append(el("option", { value: c.name, text: c.label, title: c.description || "" }));
    sel.addEventListener("change", () => { s[g.name] = sel.value; syncSidebar(); on.change(); });
    return el("div", { class: "choice sub-choice", "data-sub": g.name },
      el("label", { for: g.name, class: "choice-label" }, richText(g.label || g.name)), sel,
      el("p", { class: "choice-info", id: `${g.name}-info` }));
  };
  const choiceSelect = (g) => {
    const sel = el("select", { id: g.name, name: g.name });
    for (const c of g.choices) sel.append(el("option", { value: c.name, text: c.label, title: c.description || "" }));
    sel.addEventListener("change", () => {
      switchChoice(g, s, sel.value);
      on.notices(fixApplicability(s));
      syncSidebar();
      on.change();
    });
    // one control per parameter; a name two choices define differently (γ, η) gets one
    // per choice, each with its own range (id "<choice>-<name>")
    const paramsBox = el("div", { class: "choice-params" });
    const all = reg.groups.flatMap((x) => x.choices.flatMap((c) => c.params || []));
    for (const c of g.choices) for (const p of c.params || []) {
      const key = all.some((x) => x.name === p.name && !sameSpec(x, p)) ? `${c.name}-${p.name}` : p.name;
      if (!controls.has(key)) paramsBox.append(control(p, key));
    }
    return el("div", { class: "choice", "data-group": g.name },
      el("label", { for: g.name, class: "choice-label" }, richText(g.label || g.name)), sel,
      el("p", { class: "choice-info", id: `${g.name}-info` }), paramsBox);
  };

  const surface = [];
  const ndf = reg.groups.find((g) => g.name === "ndf");
  if (ndf) surface.push(choiceSelect(ndf));
  for (const p of reg.models.params) {
    if (p.name === "roughness") {
      surface.push(toggle("perceptual", "perceptual roughness r (α = r²)",
                          "Give the roughness as perceptual r (α = r², Burley 2012) and an anisotropy k", (on_) => {
        s.perceptual = on_;
        const r = reg.params.get("roughness");       // start from the same α: nothing jumps
        if (on_) s.roughness = Math.min(r.hi, Math.max(r.lo, Number(Math.sqrt(s.alpha).toPrecision(3))));
        else s.alpha = Number((s.roughness ** 2).toPrecision(3));
        syncSidebar();
        on.change();
      }));
    }
    if (p.name === "alpha_y") {
      surface.push(toggle("anisotropic", "anisotropic (α_x ≠ α_y)", "", (on_) => {
        s.anisotropic = on_;
        if (on_) s.alpha_y = s.alpha;                 // starts isotropic: nothing jumps
        syncSidebar();
        on.change();
      }));
    }
    if (p.name === "alpha2" && secondLobeAllowed()) {
      surface.push(toggle("second-lobe", "second lobe (α_2, weight w)",
                          "Add a second specular lobe of the same NDF: (1 − w) f(α) + w f(α₂) (Kulla & Conty 2017)", (on_) => {
        s.secondLobe = on_;
        if (on_ && s.lobe_mix === 0) s.lobe_mix = SECOND_LOBE_START_MIX;   // a weight of 0 would show nothing
        syncSidebar();
        on.change();
      }));
    }
    surface.push(control(p));
    if (p.name === "anisotropy" && reg.models.sub_options?.aniso_map) {
      surface.push(subSelect({ name: "aniso_map", ...reg.models.sub_options.aniso_map }));
    }
  }
  if (fam.list.length > 1 || reg.materials.length) form.append(modelSelect(on));
  form.append(ofDefault(section("Surface", ...surface)));
  const [first, ...rest] = familySections(on);      // a family's first section beside the surface's
  if (first) form.append(first);
  form.append(section("Incidence", ...reg.models.geometry.map((p) => control(p))));
  const others = reg.groups.filter((g) => g.name !== "ndf");
  if (others.length) form.append(ofDefault(section("Shadowing & Fresnel", ...others.map(choiceSelect))));
  for (const f of rest) form.append(f);
  const g2Box = form.querySelector('.choice[data-group="g2"] .choice-params');
  if (g2Box && reg.models.sub_options?.lambda_phi) g2Box.append(subSelect({ name: "lambda_phi", ...reg.models.sub_options.lambda_phi }));
  const pinCurrent = el("button", { type: "button", id: "pin-current", class: "small-btn", text: "Pin current model" });
  const clear = el("button", { type: "button", id: "pin-clear", class: "small-btn", text: "Clear pins" });
  pinCurrent.addEventListener("click", on.pin);
  clear.addEventListener("click", on.clearPins);
  form.append(section("Compare (pinned models)",
    el("p", { class: "pin-help", id: "pin-help",
              text: "Pin keeps the current model as a curve on the D, G₁, lobe, albedo and Fresnel panels while the controls move on." }),
    el("ul", { class: "pin-list", id: "pin-list", "aria-label": "Pinned models" }),
    el("div", { class: "pin-actions" }, pinCurrent, clear)));
  form.hidden = false;
}

/** The model menu <- state; only the chosen model's fieldsets are shown. */
function syncModel() {
  const s = ctx.state;
  const sel = $("#model");
  if (!sel) return;
  const m = materialIn(s);
  sel.value = m ? MATERIAL_PREFIX + m.slug : s.model;
  $("#model-info").textContent = modelInfo(s);
  $("#model-info").title = m ? reg.materialSource : "";
  for (const f of document.querySelectorAll("#controls-form fieldset[data-model]")) f.hidden = f.dataset.model !== s.model;
  syncFamilyForms();
}

/** Only the parameters that take part are shown and enabled. */
export function syncActiveRows() {
  const active = new Set([...activeParams(ctx.state), ...reg.models.geometry]);
  for (const c of controls.values()) {
    const on = active.has(c.param);
    setIf(c.row, "hidden", !on);
    setIf(c.box, "disabled", !on);
    setIf(c.slider, "disabled", !on);
  }
}

/** Menus <- state: the selected choice, which choices apply, the choice's note. */
export function syncChoices() {
  const s = ctx.state;
  const material = materialIn(s);
  for (const g of reg.groups) {
    const sel = document.getElementById(g.name);
    const byMaterial = !!material && g.name === MATERIAL_REPLACES;
    sel.value = byMaterial ? material.kind : s[g.name];
    setIf(sel, "disabled", byMaterial);
    for (const opt of sel.options) {
      const c = choiceOf(g.name, opt.value);
      opt.disabled = !appliesTo(c, s);
      opt.title = opt.disabled ? `Not available: ${whyNot(c, s)}` : (c.description || "");
    }
    const info = document.getElementById(`${g.name}-info`);
    const shown = byMaterial ? MATERIAL_PREFIX + material.slug : s[g.name];
    if (info.dataset.choice === shown) continue;
    info.dataset.choice = shown;
    info.textContent = "";
    if (byMaterial) {
      info.append(el("span", { text: `Set by the material ${material.name} (Model menu above): its measured RGB index.` }));
      info.hidden = false;
      continue;
    }
    const c = choiceOf(g.name, s[g.name]);
    if (c?.description) info.append(el("span", {}, richText(c.description)));
    if (c?.reference) info.append(el("span", { class: "ref", text: c.reference }));
    info.hidden = !info.textContent;
  }
}

// Blinn-Phong's α is the Beckmann-equivalent α_b; its Phong exponent α_p = 2/α_b² − 2
// (Walter et al. 2007, eq. 33) is shown beside the roughness.
const DERIVED = { blinn_phong: (alpha) => `α_p = 2/α² − 2 = ${fmtNum(2 / alpha ** 2 - 2)}` };
const fmtNum = (x) => (Math.abs(x) >= 1e4 ? x.toExponential(2).replace("e+", "e") : String(Number(x.toPrecision(4))));

export function syncDerived() {
  const s = ctx.state;
  let out = $("#derived");
  const f = DERIVED[s.ndf];
  const row = controls.get(isPerceptual(s) ? "roughness" : "alpha")?.row;
  if (!f || !row) { if (out) setIf(out, "hidden", true); return; }
  if (!out) out = el("p", { class: "derived", id: "derived", "aria-live": "polite" });
  const text = f(isPerceptual(s) ? s.roughness ** 2 : s.alpha);
  setIf(out, "textContent", text);
  setIf(out, "title", choiceOf("ndf", s.ndf)?.derived_doc?.alpha_p || "");
  setIf(out, "hidden", false);
  if (out.parentElement !== row) row.append(out);
}

/** Every control <- state (after load, reset, or a change that moves other controls). */
export function syncSidebar() {
  const s = ctx.state;
  syncModel();
  for (const c of controls.values()) c.set(s[c.param.name]);
  syncActiveRows();
  syncChoices();
  for (const g of subOptions()) {
    const sel = document.getElementById(g.name);
    if (!sel) continue;
    sel.value = s[g.name];
    sel.closest(".sub-choice").hidden = !subApplies(g.name, s);
    const info = document.getElementById(`${g.name}-info`);
    info.textContent = g.choices.find((x) => x.name === s[g.name])?.description || "";
    info.hidden = !info.textContent;
  }
  const second = $("#second-lobe");
  if (second) second.checked = !!s.secondLobe;
  syncDerived();
  const perceptual = $("#perceptual");
  if (perceptual) perceptual.checked = isPerceptual(s);
  const aniso = $("#anisotropic");
  if (aniso) {
    aniso.parentElement.hidden = isPerceptual(s);
    aniso.disabled = !anisoAllowed(s);
    aniso.checked = isAnisotropic(s);
    aniso.parentElement.title = aniso.disabled ? `${s.ndf} is isotropic only` : "";
  }
}
