/* The explorer: boots from the API, wires state -> URL and panels, and the chrome.
 *   controls --(input)--> state --> URL (replaceState, throttled)
 *                               \--> every wanted panel fetches at once (scheduler)
 */
import { el, $, richText, getJSON, copyText, flash, setIf } from "../base/dom.js";
import { setModels, setMaterials, reg, modelDefaults, fixApplicability, choiceDefaults, choiceOf, isPerceptual } from "../state/model.js";
import { ctx } from "../base/ctx.js";
import { stateFromSearch, scheduleUrlWrite, releaseUrlWrite, urlPending } from "../state/state.js";
import { MAX_PINS, pinOf, samePin, pinLabel, encodePin } from "../state/pins.js";
import { HINTS, PANEL_ORDER, PAGE_DEFAULTS, panelList } from "../state/views.js";
import { lightDrag } from "../panels/spheredrag.js";
import { buildSidebar, syncSidebar, syncChoices, syncDerived, syncActiveRows, controls } from "../controls/sidebar.js";
import { Panel } from "../panels/panels.js";
import { panelBar, fieldApplies } from "../controls/panelcontrols.js";
import { Scheduler } from "../net/scheduler.js";
import { fam, setFamilies, allFamilyDefaults, familyRoughness } from "../state/families.js";
import { GpuPanel } from "../gpu/panel.js";
import { LINK_KEY as USER_BRDF_KEY } from "../gpu/userbrdf.js";
import { UserCurves } from "../gpu/usercurves.js";

const state = ctx.state;
const scheduler = new Scheduler();
let panels = [];
let booting = true;

function showNotices(notes) {
  if (!notes.length && $("#notice").hidden) return;
  const list = $("#notice-list");
  list.textContent = "";
  for (const n of notes) list.append(el("li", { text: n }));
  $("#notice").hidden = !notes.length;
}

function updateErrorLine() {
  const line = $("#error-line");
  const errs = [...new Set(panels.filter((p) => p.error && p.shown() && p.takesModel()).map((p) => p.error))];
  const text = errs.length ? `Error: ${errs.join(" · ")}` : "";
  if (line.textContent !== text) line.textContent = text;
  setIf(line, "hidden", !errs.length);
}
scheduler.onIdle = updateErrorLine;
scheduler.held = () => ctx.held;

// ------------------------------------------------------------------- pins ----
let pinListKey = null;
function syncPinList() {
  const current = pinOf(state);
  const key = state.pins.map(encodePin).join("|") + "#" + encodePin(current);
  if (key === pinListKey) return;
  pinListKey = key;
  const list = $("#pin-list");
  list.textContent = "";
  state.pins.forEach((pin, i) => {
    const label = pinLabel(pin);
    const rm = el("button", { type: "button", class: "pin-remove", "aria-label": `Remove pin ${label}`,
                              title: "Remove this pinned model", text: "×" });
    rm.addEventListener("click", () => setPins(state.pins.filter((_, j) => j !== i)));
    list.append(el("li", { class: samePin(pin, current) ? "pin is-current" : "pin", "data-pin": encodePin(pin) },
      el("span", { class: "pin-label", title: encodePin(pin) }, richText(label)), rm));
  });
  setIf(list, "hidden", !state.pins.length);
  setIf($("#pin-clear"), "disabled", !state.pins.length);
  const full = state.pins.length >= MAX_PINS || state.pins.some((x) => samePin(x, current));
  setIf($("#pin-current"), "disabled", full);
  for (const p of panels) if (p.pinButton) setIf(p.pinButton, "disabled", full);
}
function setPins(pins) {
  state.pins = pins.slice(0, MAX_PINS);
  syncAll();
  onStateChange();
}
function pinCurrent() {
  const m = pinOf(state);
  if (state.pins.some((x) => samePin(x, m))) return;
  if (state.pins.length >= MAX_PINS) return showNotices([`At most ${MAX_PINS} pinned models; remove one first.`]);
  setPins([...state.pins, m]);
}
// GGX, Beckmann and Blinn-Phong at the current α (Blinn-Phong's α is its Beckmann-
// equivalent; another family's α = r² of the roughness it names), D(θ) on a log axis: the
// tails side by side in one click.
function compareTails() {
  const r = familyRoughness(state) ?? (isPerceptual(state) ? state.roughness : null);
  const alpha = r === null ? state.alpha : Number(Math.max(r ** 2, reg.params.get("alpha").lo).toPrecision(3));
  const pins = ["ggx", "beckmann", "blinn_phong"].filter((n) => choiceOf("ndf", n)).map((ndf) => {
    const s = structuredClone(state);
    s.model = fam.default;
    s.ndf = ndf;
    choiceDefaults(s);
    Object.assign(s, { alpha, anisotropic: false, perceptual: false, pins: [] });
    fixApplicability(s);
    return pinOf(s);
  });
  if (ctx.locals.has("ndf.log")) state["ndf.log"] = true;
  setPins(pins);
}

// ------------------------------------------------------------- the loop ----
function syncLocals() {
  for (const [key, loc] of ctx.locals) {
    if (loc.field.type === "boolean") loc.input.checked = !!state[key];
    else loc.input.value = String(state[key]);
    loc.input.parentElement.hidden = !fieldApplies(loc.view, loc.field, state);
  }
  for (const v of ctx.panelList) document.getElementById(`show-${v.name}`).checked = state.show.includes(v.name);
  $("#compare").hidden = !state.vary;
  $("#compare-text").textContent = state.vary
    ? `Comparing ${state.vary} = ${state.values.split(",").join(", ")} (one curve each, where a panel can overlay curves).` : "";
}
function syncAll() {
  syncSidebar();
  syncLocals();
  syncPinList();
}

function onStateChange() {
  // α_y or the anisotropy can make an isotropic_only choice (Hammon's G2) stop applying
  const notes = fixApplicability(state);
  if (notes.length) {
    showNotices(notes);
    syncChoices();
  }
  syncDerived();
  syncPinList();
  syncActiveRows();
  for (const p of panels) {
    setIf(p.section, "hidden", !p.shown());
    p.syncModel();
    scheduler.touch(p);
  }
  syncGpu();
  scheduleUrlWrite();
  for (const loc of ctx.locals.values()) setIf(loc.input.parentElement, "hidden", !fieldApplies(loc.view, loc.field, state));
}

/** A slider held: the heavy images come coarser until it is let go, and the readouts
 * (headings) change a few times a second. */
function onHold(held) {
  if (ctx.held === held) return;
  ctx.held = held;
  if (held) {
    // a heading whose readout wraps anew while held would resize its plot (a full Plotly
    // redraw in the drag, the held canvas dropped): it keeps its height until the release
    const heights = panels.map((p) => (p.inView ? p.heading.offsetHeight : 0));
    panels.forEach((p, k) => {
      if (heights[k]) p.heading.style.height = `${heights[k]}px`;
      p.grab();
    });
    return;
  }
  releaseUrlWrite();
  for (const p of panels) {
    p.heading.style.height = "";
    p.release();
    scheduler.touch(p);
  }
}

// Panels are fetched only when in the viewport: some of their area in it (a panel whose
// edge only touches the viewport "intersects" with none; the 1 % threshold says when
// it scrolls in).
const inViewObserver = new IntersectionObserver((entries) => {
  for (const e of entries) {
    const p = panels.find((x) => x.section === e.target);
    if (!p) continue;
    p.inView = e.isIntersecting && e.intersectionRatio > 0;
    scheduler.touch(p);
  }
}, { threshold: [0, 0.01] });

// Plotly's plots fit their boxes when the layout changes (a panel shown, the sidebar
// wraps); a chart follows its own box (chart.js).
const resizeObserver = new ResizeObserver((entries) => {
  for (const { target: div, contentRect: { width, height } } of entries) {
    // the size Plotly drew at: its SVG's (none before the first draw, none on a chart)
    const svg = div.querySelector(":scope > .plot-container svg.main-svg");
    if (!svg || div.offsetParent === null || width < 10 || height < 10) continue;
    const drawnW = Number(svg.getAttribute("width")), drawnH = Number(svg.getAttribute("height"));
    if (Math.abs(drawnW - width) < 1 && Math.abs(drawnH - height) < 1) continue;
    Promise.resolve(Plotly.Plots.resize(div)).catch(() => {});
  }
});

function report(panel) {
  return (kind, text) => {
    if (kind === "busy") return panel.setStatus("loading", text);
    if (panel.status.classList.contains("loading") && !panel.inflight) panel.setStatus(null);
    if (kind === "note" || kind === "error") showNotices([text]);
  };
}

async function boot() {
  let viewList;
  try {
    let models, materials;
    // without the materials (an older server) the page offers the model families alone
    [models, viewList, materials] = await Promise.all([getJSON("/models"), getJSON("/views"),
      getJSON("/materials").catch(() => null)]);
    setModels(models);
    setMaterials(materials);
    setFamilies(models);
  } catch (e) {
    booting = false;
    $("#boot-status").textContent = `Could not load the models: ${e.message}`;
    $("#boot-status").classList.add("failed");
    return;
  }
  const rank = (v) => (PANEL_ORDER.includes(v.name) ? PANEL_ORDER.indexOf(v.name) : PANEL_ORDER.length);
  ctx.views = viewList.map((v, i) => ({ ...v, i })).sort((a, b) => rank(a) - rank(b) || a.i - b.i);
  ctx.panelList = panelList(ctx.views);
  const box = $("#panels");
  panels = ctx.views.map((view) => {
    const p = new Panel(view, { onChange: onStateChange, onPin: pinCurrent, onTails: compareTails });
    box.append(p.section);
    return p;
  });
  for (const p of panels) p.report = report(p);
  for (const p of panels) {
    if (!HINTS[p.name]?.lightDrag) continue;
    lightDrag(p.div, { hold: onHold, set: (theta, phi) => {
      if (state.theta_i_deg === theta && state.phi_i_deg === phi) return;
      Object.assign(state, { theta_i_deg: theta, phi_i_deg: phi });
      for (const k of ["theta_i_deg", "phi_i_deg"]) controls.get(k)?.set(state[k]);
      onStateChange();
    } });
  }
  panelBar(ctx.panelList, (name, on) => {
    state.show = ctx.panelList.map((v) => v.name).filter((n) => (n === name ? on : state.show.includes(n)));
    onStateChange();
    const section = name === "gpu" ? gpu?.section : panels.find((x) => x.name === name)?.section;
    if (on) section?.scrollIntoView({ behavior: "smooth", block: "nearest" });
  });
  Object.assign(ctx.defaultState, modelDefaults(), { model: fam.default, families: allFamilyDefaults(),
    pins: [], vary: null, values: null, extra: {},
    show: ctx.panelList.map((v) => v.name).filter((n) => HINTS[n]?.shown) });
  for (const [key, loc] of ctx.locals) ctx.defaultState[key] = PAGE_DEFAULTS[loc.view]?.[loc.field.name] ?? loc.field.default;
  if (reg.models.version) $("#version").textContent = `v${reg.models.version}`;
  buildSidebar({ change: onStateChange, hold: onHold, notices: showNotices, pin: pinCurrent,
                 clearPins: () => setPins([]) });
  window.__brdf.declareExtra([USER_BRDF_KEY]);
  const { s, notes } = stateFromSearch(location.search);
  Object.assign(state, s);
  // a link to the user's own BRDF is a link to the GPU panel, which draws it
  if (state.extra[USER_BRDF_KEY] && !state.show.includes("gpu")) {
    state.show = ctx.panelList.map((v) => v.name).filter((n) => n === "gpu" || state.show.includes(n));
  }
  showNotices(notes);
  syncAll();
  $("#boot-status").hidden = true;
  for (const p of panels) {
    resizeObserver.observe(p.div);
    inViewObserver.observe(p.section);
  }
  booting = false;
  syncGpu();
  if (state.extra[USER_BRDF_KEY]) gpu.user.fromLink(state.extra[USER_BRDF_KEY]);
  onStateChange();
}

// ------------------------------------------------------------ GPU panel ----
// The live sphere (js/gpu/), a panel of the PANELS bar (views.js PAGE_PANELS): made when
// first shown (its WebGL context and shader cost nothing until then); its drag writes
// the light at the release; where WebGL2 is missing the server's sphere panel is shown.
let gpu = null;
function syncGpu() {
  if (booting) return;
  const on = state.show.includes("gpu");
  if (on && !gpu) {
    const next = ctx.panelList.slice(ctx.panelList.findIndex((v) => v.name === "gpu") + 1);
    const before = next.map((v) => panels.find((p) => p.name === v.name)?.section).find(Boolean) ?? null;
    gpu = mountGpu($("#panels"), before);
  }
  if (!gpu) return;
  setIf(gpu.section, "hidden", !on);
  if (!on) return;
  if (gpu.failed) showServerSphere();
  gpu.sync(state);
}
function mountGpu(box, before) {
  const g = new GpuPanel({
    onLight: (theta, phi) => {
      Object.assign(state, { theta_i_deg: theta, phi_i_deg: phi });
      for (const k of ["theta_i_deg", "phi_i_deg"]) controls.get(k)?.set(state[k]);
      onStateChange();
    },
    onFallback: () => { if (!booting && state.show.includes("gpu")) showServerSphere(); },
    onLink: (key, text) => {
      if ((state.extra[key] ?? null) !== text) window.__brdf.setExtra({ [key]: text });
    },
  });
  box.insertBefore(g.section, before);
  window.__gpu = g.hook();
  window.__gpuPanel = g;
  window.__userBrdf = g.user.hook();
  // the user's BRDF on the curve panels, through each panel's own overlay (usercurves.js)
  const panelOf = (name) => panels.find((x) => x.name === name);
  window.__userCurves = new UserCurves(g.user, {
    figure: (name) => panelOf(name)?.figure ?? null,
    params: (name) => panelOf(name)?.params(state) ?? {},
    defaults: (name) => Object.fromEntries((panelOf(name)?.view.fields ?? []).map((f) => [f.name, f.default])),
    overlay: (name, figure) => panelOf(name)?.overlay(figure),
  }).hook();
  return g;
}
function showServerSphere() {
  if (state.show.includes("sphere")) return;
  state.show = [...state.show, "sphere"];
  syncLocals();
  onStateChange();
}

// --------------------------------------------------------------- chrome ----
$("#notice-close").addEventListener("click", () => { $("#notice").hidden = true; });
$("#compare-stop").addEventListener("click", () => {
  state.vary = null;
  state.values = null;
  syncAll();
  onStateChange();
});
$("#reset").addEventListener("click", () => {
  if (!reg.models) return;
  Object.assign(state, structuredClone(ctx.defaultState));
  showNotices([]);
  syncAll();
  onStateChange();
});
$("#copy-link").addEventListener("click", async () => {
  const btn = $("#copy-link");
  if (await copyText(location.href)) flash(btn, "Copied ✓");
  else {
    showNotices([`Link to this state: ${location.href}`]);
    flash(btn, "Link below");
  }
});

// Test and benchmark hook: the state, and what is still to fetch or draw.
window.__brdf = {
  drawEvent: "brdf-drawn",          // fired on a plot div after each finished draw
  get state() { return state; },
  get models() { return reg.models; },
  get families() { return fam.list; },
  pending: () => (booting ? 1 : 0) + urlPending() + scheduler.pending(panels),
  panels: () => panels.map((p) => ({ name: p.name, inflight: !!p.inflight, dirty: p.dirty, drawn: p.drawn,
                                     error: p.error, visible: p.shown(), inView: p.inView, takesModel: p.takesModel(),
                                     current: p.drawnKey === p.request().key })),
  url: (name) => panels.find((x) => x.name === name)?.url(),
  request: (name) => panels.find((x) => x.name === name)?.request(),
  panel: (name) => panels.find((x) => x.name === name),
  // For the data module: a figure of the data over a panel's, drawn as the panel draws
  overlay: (name, figure) => panels.find((x) => x.name === name)?.overlay(figure),
  // For another module (data overlays): query parameters it owns, kept in the page URL
  // and sent to every panel whose view declares them. Declare before the page boots (at
  // module load) so that a link carrying them is read, not flagged as unknown.
  declareExtra: (keys) => { for (const k of keys) ctx.extraKeys.add(k); },
  setExtra: (params) => {
    for (const [k, v] of Object.entries(params)) {
      ctx.extraKeys.add(k);
      if (v === null || v === undefined) delete state.extra[k];
      else state.extra[k] = String(v);
    }
    onStateChange();
  },
};

boot();
