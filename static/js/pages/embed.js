/* The embed page, /embed/{kind}?...: one figure, sized to its frame (320 × 240 up).
 *
 * The query string is the figure's query (model + view parameters, as the API takes
 * them) plus page options: controls=1 adds sliders for what shapes this figure (the
 * roughness, the view's angles and toggles); buttons=0 hides the export bar. State
 * lives in the URL, as in the explorer. The controls and the bar take their height
 * first; the plot gets the rest and is re-fitted whenever that changes.
 */
import { API, el, richText, query, copyText, flash } from "../base/dom.js";
import { paramControl } from "../state/sliders.js";
import { exportBar } from "../panels/exports.js";
import { fitLayout, reuseLayout, titleText, PLOT_CONFIG } from "../panels/layout.js";
import { Scheduler } from "../net/scheduler.js";
import { fieldRole, fieldLabel, isHeavy } from "../state/views.js";

const PAGE_OPTIONS = ["controls", "buttons", "embed"];
const TRUE_WORDS = new Set(["1", "true", "yes", "on"]);

const kind = decodeURIComponent(location.pathname.split("/").filter(Boolean).pop() || "");
const search = new URLSearchParams(location.search);
const withControls = search.get("controls") === "1";
const withButtons = search.get("buttons") !== "0";
const params = {};                       // THE state: the figure's query
for (const [k, v] of search) if (!PAGE_OPTIONS.includes(k)) params[k] = v;

const plot = document.getElementById("plot");
const status = document.getElementById("status");
let title = kind, held = false, view = null;

function setStatus(kindOf, text = "") {
  status.className = `panel-status${kindOf ? ` ${kindOf}` : ""}`;
  status.textContent = text;
}

const explorerUrl = () => `/?${query({ ...params, show: kind })}`;

function writeUrl() {
  const q = { ...params };
  if (withControls) q.controls = "1";
  if (!withButtons) q.buttons = "0";
  history.replaceState(null, "", `${location.pathname}?${query(q)}`);
  document.getElementById("open-explorer").href = explorerUrl();
}

// While a slider is held a heavy image comes at half its resolution each way.
function heldResolution() {
  const q = {};
  if (!held || !view || !isHeavy(view)) return q;
  for (const f of view.fields) {
    if (fieldRole(f) === "resolution" && f.type === "integer" && Number.isFinite(f.default) && !(f.name in params)) {
      q[f.name] = Math.max(f.minimum ?? 2, Math.round(f.default / 2));
    }
  }
  return q;
}

// The figure as a scheduler panel: the same fetch-once, draw-per-frame loop as the explorer.
const figure = {
  name: kind, inflight: null, dirty: false, drawing: null, drawnKey: null, drawn: false, timer: 0,
  wanted: () => true,
  request() {
    const url = `${API}/figures/${encodeURIComponent(kind)}${params.vary ? ".json" : ""}?${query({ ...params, ...heldResolution() })}`;
    return { key: url, url, init: { headers: { Accept: "application/json" } } };
  },
  receive(req, res, body) {
    if (!res.ok) throw new Error(body?.detail ? (typeof body.detail === "string" ? body.detail
      : body.detail.map((d) => d.msg || d).join("; ")) : `The server answered ${res.status}.`);
    return { data: body.data, given: body.layout || {} };
  },
  draw({ data, given }) {
    const t = titleText(given);
    if (t && t !== title) {
      title = t;
      document.title = t.replace(/<[^>]*>/g, "");
      plot.setAttribute("aria-label", document.title);
    }
    this.drawn = true;
    setStatus(null);
    return Plotly.react(plot, data, reuseLayout(this, fitLayout(given, { keepTitle: true }), kind),
                        { ...PLOT_CONFIG, modeBarButtonsToRemove: [...PLOT_CONFIG.modeBarButtonsToRemove, "toImage"] });
  },
  fail(message) { setStatus("error", message); },
  busy(text) { clearTimeout(this.timer); setStatus("loading", text); },
  loading(on) {
    clearTimeout(this.timer);
    if (on) this.timer = setTimeout(() => setStatus("loading", "loading…"), 300);
    else if (status.classList.contains("loading")) setStatus(null);
  },
};
const scheduler = new Scheduler();

function onChange() {
  writeUrl();
  scheduler.touch(figure);
}
function onHold(on) {
  held = on;
  if (!on) scheduler.touch(figure);
}

// ---------------------------------------------------------------- controls ----
function numberControl(p) {
  const c = paramControl(p, { id: `c-${p.name.replace(/_/g, "-")}`, compact: true, onHold,
                              onValue: (x) => { params[p.name] = String(x); onChange(); } });
  c.set(params[p.name] !== undefined ? Number(params[p.name]) : p.default);
  return c.row;
}

function toggleControl(f, label) {
  const id = `c-${f.name.replace(/_/g, "-")}`;
  const box = el("input", { type: "checkbox", id });
  box.checked = f.name in params ? TRUE_WORDS.has(String(params[f.name]).toLowerCase()) : !!f.default;
  box.addEventListener("change", () => { params[f.name] = box.checked ? "true" : "false"; onChange(); });
  return el("label", { class: "toggle", for: id, title: f.description || "" }, box, el("span", {}, richText(label)));
}

function choiceControl(f) {
  const id = `c-${f.name.replace(/_/g, "-")}`;
  const sel = el("select", { id, class: "mini" });
  for (const c of f.enum) sel.append(el("option", { value: c, text: c }));
  sel.value = params[f.name] ?? f.default;
  sel.addEventListener("change", () => { params[f.name] = sel.value; onChange(); });
  return el("label", { class: "mini-field", for: id, title: f.description || "" }, el("span", {}, richText(f.name)), sel);
}

async function buildControls() {
  const [models, views] = await Promise.all(["/models", "/views"].map(async (path) => {
    const res = await fetch(`${API}${path}`);
    if (!res.ok) throw new Error(`${path}: HTTP ${res.status}`);
    return res.json();
  }));
  view = views.find((v) => v.name === kind) || null;
  const kids = [];
  // the roughness always shapes the figure (in whichever form the URL gives it; another
  // family's own roughness parameter, which takes no alpha)
  const family = (models.models || []).find((f) => f.name === params.model && !f.default);
  const roughName = family?.roughness_param ?? (params.roughness !== undefined ? "roughness" : "alpha");
  const rough = (family || models).params.find((p) => p.name === roughName);
  if (rough) kids.push(numberControl(rough));
  const geometry = new Map(models.geometry.map((p) => [p.name, p]));
  for (const f of view ? view.fields : []) {
    if (fieldRole(f) === "resolution" || f.name === params.vary) continue;
    if (f.type === "boolean") kids.push(toggleControl(f, fieldLabel(view, f)));
    else if (f.enum) kids.push(choiceControl(f));
    else if (geometry.has(f.name)) kids.push(numberControl({ ...geometry.get(f.name), default: f.default }));
    else if (f.type === "number" && Number.isFinite(f.minimum) && Number.isFinite(f.maximum)) {
      kids.push(numberControl({ name: f.name, label: f.name.replace(/_deg$/, " (°)"), lo: f.minimum, hi: f.maximum,
                                default: f.default, description: f.description, scale: "linear" }));
    }
  }
  const form = document.getElementById("embed-controls");
  form.append(...kids);
  form.hidden = false;
}

function buildButtons() {
  const bar = document.getElementById("embed-bar");
  const exports = exportBar(() => ({ kind, params: { ...params }, figure: plot, title }), (k, text) => {
    if (k === "busy") setStatus("loading", text);
    else if (k === "error" || k === "note") setStatus("note", text);
    else setStatus(null);
  });
  bar.insertBefore(exports, document.getElementById("copy-link"));
  document.getElementById("copy-link").addEventListener("click", async (ev) => {
    const url = `${location.origin}${explorerUrl()}`;
    if (await copyText(url)) flash(ev.target, "Copied ✓");
    else setStatus("note", url);
  });
  bar.hidden = false;
}

// The plot fills what the controls and the bar leave, and follows when that changes.
new ResizeObserver(() => {
  if (plot.layout) Promise.resolve(Plotly.Plots.resize(plot)).catch(() => {});
}).observe(plot);

if (withButtons) buildButtons();
writeUrl();
if (withControls) buildControls().catch((e) => setStatus("error", `Controls: ${e.message}`));
scheduler.touch(figure);

// Test hook, as in the explorer.
window.__embed = { pending: () => scheduler.pending([figure]), params, drawn: () => figure.drawn };
