/* A panel's own controls (its toggles, menus and bounded numbers, beside its figure)
 * and the bar of panels above the figures, one toggle per view. */
import { el, $, richText } from "../base/dom.js";
import { reg } from "../state/model.js";
import { ctx } from "../base/ctx.js";
import { hintOf, fieldRole, fieldLabel, localKey, localId, OPTION_LABELS } from "../state/views.js";

/** The view's fields a panel sets itself: toggles, menus and bounded numbers that are
 * not geometry (the sidebar's θ_i, φ_i) nor resolution (left at the API's defaults). */
export function panelFields(view) {
  const geometry = new Set(reg.models.geometry.map((p) => p.name));
  const hint = hintOf(view.name);
  const own = new Set(hint.fields || []);
  // a number without a default (the quadrature's fixed order) is the API's to choose
  return view.fields.filter((f) => (own.has(f.name) || fieldRole(f) !== "resolution") && !geometry.has(f.name)
    && (f.default !== null && f.default !== undefined || f.type === "boolean" || !!f.enum)
    && !(hint.slice && f.name === "phi_deg")
    && (f.type === "boolean" || f.enum || ((f.type === "number" || f.type === "integer")
                                           && Number.isFinite(f.minimum) && Number.isFinite(f.maximum))));
}

/** A field that matters only for some values of another (x-applies-to) is hidden, and
 * not sent, elsewhere: the API refuses it there. */
export function fieldApplies(viewName, f, s) {
  const view = ctx.views.find((v) => v.name === viewName);
  return Object.entries(f.applies_to || {}).every(([other, allowed]) => {
    const key = localKey(viewName, other);
    return allowed.includes(key in s ? s[key] : view?.fields.find((x) => x.name === other)?.default);
  });
}

export function localControl(view, f, onChange) {
  const key = localKey(view.name, f.name), id = localId(view.name, f.name);
  const set = (v) => { ctx.state[key] = v; onChange(); };
  let input, label;
  if (f.type === "boolean") {
    input = el("input", { type: "checkbox", id });
    label = el("label", { class: "toggle", for: id, title: f.description }, input, el("span", {}, richText(fieldLabel(view, f))));
    input.addEventListener("change", () => set(input.checked));
  } else if (f.enum) {
    input = el("select", { id, class: "mini" });
    for (const x of f.enum) input.append(el("option", { value: x, text: OPTION_LABELS[f.name]?.[x] || x }));
    label = el("label", { class: "mini-field", for: id, title: f.description }, el("span", {}, richText(fieldLabel(view, f))), input);
    input.addEventListener("change", () => set(input.value));
  } else {
    const integer = f.type === "integer";
    input = el("input", { type: "number", id, class: "mini", min: f.minimum, max: f.maximum,
                          step: integer ? 1 : "any", inputmode: integer ? "numeric" : "decimal" });
    label = el("label", { class: "mini-field", for: id, title: f.description }, el("span", {}, richText(fieldLabel(view, f))), input);
    input.addEventListener("input", () => {
      const x = input.value.trim() === "" ? NaN : Number(input.value);
      const ok = Number.isFinite(x) && x >= f.minimum && x <= f.maximum && (!integer || Number.isInteger(x));
      input.toggleAttribute("aria-invalid", !ok);
      if (ok) set(x);
    });
    input.addEventListener("change", () => { input.value = String(ctx.state[key]); input.removeAttribute("aria-invalid"); });
  }
  ctx.locals.set(key, { view: view.name, field: f, input });
  return label;
}

/** The list of panels, at the top of the figures: one toggle per panel (views.js panelList). */
export function panelBar(list, onToggle) {
  const bar = $("#panel-bar");
  bar.textContent = "";
  bar.append(el("span", { class: "panel-bar-label", text: "Panels" }));
  for (const v of list) {
    const box = el("input", { type: "checkbox", id: `show-${v.name}`, name: `show-${v.name}` });
    box.addEventListener("change", () => onToggle(v.name, box.checked));
    bar.append(el("label", { class: "chip", for: `show-${v.name}`, title: v.caption || "" },
      box, el("span", {}, richText(v.title))));
  }
}
