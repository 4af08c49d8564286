/* The controls of every non-default model family in the sidebar, built from its entry
 * of GET /api/v1/models: its sections (as the family declares them; else one titled with
 * its label), each a colour (a picker and its r,g,b), a slider or an option menu. Ids are
 * "<family>-<name>" (a name's own "<family>_" prefix not repeated): the default family's
 * controls already use names such as "roughness".
 */
import { el, $, richText } from "../base/dom.js";
import { paramControl } from "../state/sliders.js";
import { fam, familyNames, choiceApplies, parseColor, colorText, fixFamily } from "../state/families.js";
import { ctx } from "../base/ctx.js";

export const familyControls = new Map();      // "<family>/<name>" -> {row, set}
export const fid = (f, name) => `${f.name}-${name.replace(new RegExp(`^${f.name}_`), "").replace(/_/g, "-")}`;
const values = (f) => ctx.state.families[f.name];

// a colour input holds 8-bit sRGB hex: its digits as r,g,b in [0, 1] (3 decimals), as typed
const hex = (rgb) => `#${rgb.map((x) => Math.round(x * 255).toString(16).padStart(2, "0")).join("")}`;
const fromHex = (h) => [1, 3, 5].map((i) => Number((parseInt(h.slice(i, i + 2), 16) / 255).toFixed(3)));

function fieldset(f, title, kids) {
  return el("fieldset", { class: "group", "data-model": f.name }, el("legend", {}, richText(title)), ...kids);
}

function optionSelect(f, g, on) {
  const id = fid(f, g.name);
  const sel = el("select", { id, name: g.name });
  for (const c of g.choices) sel.append(el("option", { value: c.name, text: c.label, title: c.description || "" }));
  sel.addEventListener("change", () => {
    values(f)[g.name] = sel.value;
    syncFamilyForms();
    on.change();
  });
  familyControls.set(`${f.name}/${g.name}`, { set: () => {} });
  return el("div", { class: "choice", "data-family-option": g.name },
    el("label", { for: id, class: "choice-label" }, richText(g.label)), sel,
    el("p", { class: "choice-info", id: `${id}-info` }));
}

function colorControl(f, c, on) {
  const id = fid(f, c.name);
  const picker = el("input", { type: "color", id: `${id}-picker`, "aria-label": `${c.label} picker`,
                               title: `Pick the ${c.label} (its 8-bit digits become r,g,b)` });
  const box = el("input", { type: "text", id, name: c.name, class: "rgb", inputmode: "decimal", spellcheck: "false",
                            "aria-describedby": `${id}-msg` });
  const msg = el("div", { class: "param-msg", id: `${id}-msg`, hidden: true });
  const set = (rgb, source) => {
    values(f)[c.name] = rgb;
    if (source !== "box") box.value = colorText(rgb);
    picker.value = hex(rgb);
    box.removeAttribute("aria-invalid");
    msg.hidden = true;
    if (source) on.change();
  };
  picker.addEventListener("input", () => set(fromHex(picker.value), "picker"));
  box.addEventListener("input", () => {
    const rgb = parseColor(box.value, c);
    if (rgb) return set(rgb, "box");
    box.setAttribute("aria-invalid", "true");
    msg.textContent = `Three numbers r,g,b in [${c.lo}, ${c.hi}].`;
    msg.hidden = false;
  });
  box.addEventListener("change", () => set(values(f)[c.name]));   // an invalid box is restored
  const row = el("div", { class: "param color-param", "data-param": c.name },
    el("div", { class: "param-head" },
      el("label", { for: id, title: c.description || "" }, c.label), el("span", { class: "box" }, picker, box)), msg);
  familyControls.set(`${f.name}/${c.name}`, { row, set: (rgb) => set(rgb) });
  return row;
}

function control(f, name, on) {
  const color = f.colors.find((c) => c.name === name);
  if (color) return colorControl(f, color, on);
  const g = f.options.find((x) => x.name === name);
  if (g) return optionSelect(f, g, on);
  const p = f.params.find((x) => x.name === name);
  const c = paramControl(p, { id: fid(f, p.name), onHold: on.hold, onValue: (x) => {
    values(f)[p.name] = x;
    on.notices(fixFamily(f, values(f)));       // a choice may need this parameter at 0
    syncOptions(f);
    on.change();
  } });
  familyControls.set(`${f.name}/${p.name}`, c);
  return c.row;
}

/** The fieldsets of every non-default family. on: {change(), hold(held), notices(list)}. */
export function familySections(on) {
  familyControls.clear();
  const out = [];
  for (const f of fam.list.filter((x) => x.name !== fam.default)) {
    const sections = f.sections || [{ title: f.label, names: familyNames(f) }];
    sections.forEach((sec, i) => {
      const kids = sec.names.map((name) => control(f, name, on));
      if (i === 0 && f.reference) kids.push(el("p", { class: "choice-info ref", text: f.reference.split(";")[0] }));
      out.push(fieldset(f, sec.title, kids));
    });
  }
  return out;
}

function syncOptions(f) {
  const p = values(f);
  for (const g of f.options) {
    const sel = document.getElementById(fid(f, g.name));
    if (!sel) continue;
    sel.value = p[g.name];
    for (const opt of sel.options) {
      const c = g.choices.find((x) => x.name === opt.value);
      opt.disabled = !choiceApplies(c, p);
      opt.title = opt.disabled ? `Not available: needs ${c.requires_zero} = 0` : (c.description || "");
    }
    const info = $(`#${fid(f, g.name)}-info`);
    const text = g.choices.find((x) => x.name === p[g.name])?.description || "";
    if (info.textContent !== text) info.textContent = text;
    info.hidden = !text;
  }
}

/** Every family's controls <- state.families. */
export function syncFamilyForms() {
  if (!ctx.state.families) return;
  for (const f of fam.list.filter((x) => x.name !== fam.default)) {
    const p = values(f);
    for (const name of [...f.colors, ...f.params].map((x) => x.name)) familyControls.get(`${f.name}/${name}`)?.set(p[name]);
    syncOptions(f);
  }
}
