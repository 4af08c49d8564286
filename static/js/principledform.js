/* The principled model's controls in the sidebar, built from GET /api/v1/principled:
 * which lobe and channel are drawn first (what one changes while looking), then the
 * base colour (a colour picker and its r,g,b), the paper's sliders, and, apart, the
 * options where implementations differ. Ids are "principled-<name>": the microfacet
 * controls already use "roughness" and "anisotropic".
 */
import { el, $, richText } from "./dom.js";
import { paramControl } from "./sliders.js";
import { preg, optionOf, choiceApplies, parseColor, colorText, fixPrincipled, PRINCIPLED } from "./principled.js";
import { ctx } from "./ctx.js";

const SHOWN = ["lobe", "channel"];                 // what is drawn; the rest change the model
export const principledControls = new Map();      // name -> {row, box, slider, set}
// "principled-metallic", "principled-g2" (an option's own prefix not repeated)
export const pid = (name) => `principled-${name.replace(/^principled_/, "").replace(/_/g, "-")}`;

// a colour input holds 8-bit sRGB hex: its digits as r,g,b in [0, 1] (3 decimals), as typed
const hex = (rgb) => `#${rgb.map((x) => Math.round(x * 255).toString(16).padStart(2, "0")).join("")}`;
const fromHex = (h) => [1, 3, 5].map((i) => Number((parseInt(h.slice(i, i + 2), 16) / 255).toFixed(3)));

function fieldset(title, ...kids) {
  return el("fieldset", { class: "group", "data-model": PRINCIPLED }, el("legend", {}, richText(title)), ...kids);
}

function optionSelect(g, on) {
  const id = pid(g.name);
  const sel = el("select", { id, name: g.name });
  for (const c of g.choices) sel.append(el("option", { value: c.name, text: c.label, title: c.description || "" }));
  sel.addEventListener("change", () => {
    ctx.state.principled[g.name] = sel.value;
    syncPrincipledForm();
    on.change();
  });
  return el("div", { class: "choice", "data-principled": g.name },
    el("label", { for: id, class: "choice-label" }, richText(g.label)), sel,
    el("p", { class: "choice-info", id: `${id}-info` }));
}

function colorControl(on) {
  const id = pid("base_color");
  const picker = el("input", { type: "color", id: `${id}-picker`, "aria-label": "base colour picker",
                               title: "Pick the base colour (its 8-bit digits become r,g,b)" });
  const box = el("input", { type: "text", id, name: "base_color", class: "rgb", inputmode: "decimal", spellcheck: "false",
                            "aria-describedby": `${id}-msg` });
  const msg = el("div", { class: "param-msg", id: `${id}-msg`, hidden: true });
  const set = (rgb, source) => {
    ctx.state.principled.base_color = rgb;
    if (source !== "box") box.value = colorText(rgb);
    picker.value = hex(rgb);
    box.removeAttribute("aria-invalid");
    msg.hidden = true;
    if (source) on.change();
  };
  picker.addEventListener("input", () => set(fromHex(picker.value), "picker"));
  box.addEventListener("input", () => {
    const rgb = parseColor(box.value);
    if (rgb) return set(rgb, "box");
    box.setAttribute("aria-invalid", "true");
    msg.textContent = "Three numbers r,g,b in [0, 1].";
    msg.hidden = false;
  });
  box.addEventListener("change", () => set(ctx.state.principled.base_color));   // an invalid box is restored
  const row = el("div", { class: "param color-param", "data-param": "base_color" },
    el("div", { class: "param-head" },
      el("label", { for: id, title: "Base colour r,g,b in [0, 1] (linear, or decoded as sRGB-like: see its encoding below)" },
         "base colour"),
      el("span", { class: "box" }, picker, box)), msg);
  principledControls.set("base_color", { row, set: (rgb) => set(rgb) });
  return row;
}

/** The principled fieldsets. on: {change(), hold(held), notices(list)}. */
export function principledSections(on) {
  principledControls.clear();
  if (!preg.cat) return [];
  const sliders = preg.params.map((p) => {
    const c = paramControl(p, { id: pid(p.name), onHold: on.hold, onValue: (x) => {
      ctx.state.principled[p.name] = x;
      on.notices(fixPrincipled(ctx.state.principled));   // anisotropic > 0 rules Kulla-Conty out
      syncOptions();
      on.change();
    } });
    principledControls.set(p.name, c);
    return c.row;
  });
  const shown = SHOWN.map(optionOf).filter(Boolean).map((g) => optionSelect(g, on));
  const others = preg.options.filter((g) => !SHOWN.includes(g.name)).map((g) => optionSelect(g, on));
  return [
    fieldset("Principled BRDF", ...shown, colorControl(on), ...sliders,
             el("p", { class: "choice-info ref", text: preg.cat.reference.split(";")[0] })),
    fieldset("Where implementations differ", ...others),
  ];
}

function syncOptions() {
  const p = ctx.state.principled;
  for (const g of preg.options) {
    const sel = document.getElementById(pid(g.name));
    if (!sel) continue;
    sel.value = p[g.name];
    for (const opt of sel.options) {
      const c = g.choices.find((x) => x.name === opt.value);
      opt.disabled = !choiceApplies(c, p);
      opt.title = opt.disabled ? "Not available: isotropic roughness only (anisotropic = 0)" : (c.description || "");
    }
    const info = $(`#${pid(g.name)}-info`);
    const text = g.choices.find((x) => x.name === p[g.name])?.description || "";
    if (info.textContent !== text) info.textContent = text;
    info.hidden = !text;
  }
}

/** Every principled control <- state.principled. */
export function syncPrincipledForm() {
  const p = ctx.state.principled;
  if (!p) return;
  for (const [name, c] of principledControls) c.set(p[name]);
  syncOptions();
}
