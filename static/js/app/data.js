/* Your data beside the model: open (or drop) a MERL .binary or CSV file, see it on every
 * panel that can show it, one toggle for (data − model)/model, and fit the model to it.
 *
 * Self-contained (but for panels/layout.js's rangeOverAll, shared with the user BRDF's
 * curves): it talks to the page only through window.__brdf (the state, each panel's
 * request URL) and the "brdf-drawn" event each panel fires after a draw. After a
 * panel draws the model, the same query goes to /api/v1/datasets/{id}/figures/{view},
 * which answers the model's figure with the data added (or the relative error); that
 * figure replaces the panel's until its next draw. The data set's id is kept in
 * sessionStorage (not the URL, whose parameters are the model's); a link may hand one
 * over as ?data=<id> (the gallery's data cards do), read once and taken out of the URL.
 */
import { rangeOverAll } from "../panels/layout.js";

const API = "/api/v1";
//: views the API overlays, and what they need of the data set
const OVERLAID = ["lobe", "lobe3d", "slice", "sphere", "albedo", "ndf", "g1", "fresnel"];
const STORE_KEY = "brdf-data";
const RGB = ["luminance", "r", "g", "b"];
const LABEL = "brdf-data-label";     // the name of the annotation that says what the overlay shows

const data = { id: null, summary: null, channel: "luminance", difference: false };
const seq = new Map();          // panel → number of its latest draw (drops stale answers)
const refused = new Map();      // panel → why it cannot show this data set

function el(tag, attrs = {}, ...children) {
  const node = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (k === "text") node.textContent = v;
    else node.setAttribute(k, v);
  }
  node.append(...children);
  return node;
}

// ------------------------------------------------------------------ the box --
const fileInput = el("input", { type: "file", id: "data-file", hidden: "", "aria-label": "Data file" });
const openButton = el("button", { type: "button", id: "data-open", class: "export",
                                  title: "A MERL .binary file, or a CSV of BRDF samples or of one term; or drop it on the page",
                                  text: "Open data…" });
const clearButton = el("button", { type: "button", id: "data-clear", class: "export", text: "Close", hidden: "" });
const status = el("p", { id: "data-status", class: "data-status", role: "status", "aria-live": "polite",
                         text: "Drop a MERL .binary or CSV file here to compare it with the model." });
const channel = el("select", { id: "data-channel", "aria-label": "Channel" });
const difference = el("input", { type: "checkbox", id: "data-difference" });
const fitButton = el("button", { type: "button", id: "data-fit", class: "export", text: "Fit α, F₀, k_d",
                                 title: "Least squares of the current model's α, F₀ and k_d to the data" });
const fitResult = el("div", { id: "data-fit-result", class: "data-fit", role: "status", "aria-live": "polite" });
const tools = el("div", { class: "data-tools", hidden: "" }, el("label", {}, "Channel ", channel),
                 el("label", {}, difference, " data − model"), fitButton);
const box = el("section", { id: "data-box", class: "data-box", "aria-label": "Data set",
                            style: "border:1px dashed #999;border-radius:6px;padding:6px 8px;margin:0 0 10px;font-size:13px" },
               el("div", {}, openButton, " ", clearButton), status, tools, fitResult);
fileInput.addEventListener("change", () => fileInput.files[0] && upload(fileInput.files[0]));
openButton.addEventListener("click", () => fileInput.click());
clearButton.addEventListener("click", () => forget());
channel.addEventListener("change", () => { data.channel = channel.value; save(); redrawAll(); });
difference.addEventListener("change", () => { data.difference = difference.checked; save(); redrawAll(); });
fitButton.addEventListener("click", () => fit());

function place() {
  const host = document.getElementById("controls");
  host.prepend(box, fileInput);
}

// ------------------------------------------------------------- drag and drop --
let dragDepth = 0;
document.addEventListener("dragenter", (e) => { if (hasFiles(e)) { dragDepth++; box.style.background = "#eef6ff"; } });
document.addEventListener("dragleave", () => { if (--dragDepth <= 0) { dragDepth = 0; box.style.background = ""; } });
document.addEventListener("dragover", (e) => { if (hasFiles(e)) e.preventDefault(); });
document.addEventListener("drop", (e) => {
  if (!hasFiles(e)) return;
  e.preventDefault();
  dragDepth = 0;
  box.style.background = "";
  upload(e.dataTransfer.files[0]);
});
const hasFiles = (e) => [...(e.dataTransfer?.types || [])].includes("Files");

// ------------------------------------------------------------------ upload --
async function upload(file) {
  status.textContent = `Reading ${file.name}…`;
  let res, body;
  try {
    res = await fetch(`${API}/datasets`, { method: "POST", body: file,
                                           headers: { "Content-Type": file.type || "application/octet-stream" } });
    body = await res.json();
  } catch (err) {
    status.textContent = `Could not upload: ${err.message}`;
    return;
  }
  if (!res.ok) {
    status.textContent = `Not read: ${message(body, res)}`;
    return;
  }
  show(body.id, body.summary);
  save();
  redrawAll();
}

function message(body, res) {
  const d = body && body.detail;
  return Array.isArray(d) ? d.map((x) => x.msg).join("; ") : d || `HTTP ${res.status}`;
}

function show(id, summary) {
  Object.assign(data, { id, summary });
  const s = summary;
  const measured = s.fraction_measured !== undefined ? `, ${(100 * s.fraction_measured).toFixed(0)} % measured` : "";
  status.textContent = `${s.format}: ${s.count.toLocaleString("en")} ${s.format === "merl" ? "cells" : "rows"}${measured}, channels ${s.channels.join(", ")}`;
  const options = s.channels.length === 3 ? RGB : s.channels;
  channel.replaceChildren(...options.map((c) => el("option", { value: c, text: c })));
  if (!options.includes(data.channel)) data.channel = options[0];
  channel.value = data.channel;
  difference.checked = data.difference;
  tools.hidden = false;
  fitButton.hidden = s.kind !== "brdf";
  syncFitLabel();
  clearButton.hidden = false;
}

function save() {
  sessionStorage.setItem(STORE_KEY, JSON.stringify({ id: data.id, channel: data.channel, difference: data.difference }));
}

function forget() {
  Object.assign(data, { id: null, summary: null, difference: false });
  sessionStorage.removeItem(STORE_KEY);
  tools.hidden = clearButton.hidden = true;
  fitResult.textContent = "";
  status.textContent = "Data closed.";
  refused.clear();
  location.reload();        // the page draws its own figures again, from its URL
}

/** A link's ?data=<id>: into sessionStorage, and out of the URL before the page reads
 * the URL as the model's state (this module runs before main.js's boot reaches that). */
function handOver() {
  const q = new URLSearchParams(location.search);
  const id = q.get("data");
  if (id === null) return;
  if (/^[0-9a-f]{32}$/.test(id)) sessionStorage.setItem(STORE_KEY, JSON.stringify({ id, channel: "luminance", difference: false }));
  q.delete("data");
  history.replaceState(null, "", location.pathname + (q.size ? `?${q}` : "") + location.hash);
}

async function restore() {
  const saved = JSON.parse(sessionStorage.getItem(STORE_KEY) || "null");
  if (!saved || !saved.id) return;
  const res = await fetch(`${API}/datasets/${saved.id}`);
  if (!res.ok) {           // evicted or the server restarted: say so, once
    sessionStorage.removeItem(STORE_KEY);
    status.textContent = `The last data set is gone from the server (${res.status}); open it again.`;
    return;
  }
  Object.assign(data, { channel: saved.channel, difference: saved.difference });
  show(saved.id, (await res.json()).summary);
  redrawAll();
}

// ------------------------------------------------------------------ overlay --
// "brdf-drawn" does not bubble: listen in the capture phase, on the way down to the plot
document.addEventListener("brdf-drawn", (e) => {
  const name = e.target?.closest?.("[data-panel]")?.dataset.panel;
  if (name && data.id) syncFitLabel();
  if (name) overlay(name, e.target);
}, true);

function redrawAll() {
  for (const name of OVERLAID) {
    const div = document.getElementById(`plot-${name}`);
    if (div && div.data) overlay(name, div);
  }
}

/** Whether a view can show this data set (the API says why not; this spares the request). */
function canShow(name) {
  const s = data.summary;
  if (s.kind === "term") {
    const terms = { ndf: "D", g1: "G1", fresnel: "F", albedo: "E" };
    return name in terms && s.channels.includes(terms[name]);
  }
  // BRDF values: the lobe and the albedo from any; a MERL table also the 3-D lobe, the
  // slice and the sphere (app/datasets/overlay.py: the term views need a term CSV)
  return ["lobe", "albedo"].includes(name) || (s.format === "merl" && ["lobe3d", "slice", "sphere"].includes(name));
}

async function overlay(name, div) {
  if (!data.id || !OVERLAID.includes(name) || !canShow(name)) return;
  const url = window.__brdf.url(name);
  if (!url || !url.includes(`/figures/${name}?`)) return;          // a comparison (vary): left alone
  const n = (seq.get(name) || 0) + 1;
  seq.set(name, n);
  const query = url.slice(url.indexOf("?") + 1);
  const extra = new URLSearchParams({ difference: String(data.difference) });
  if (data.summary.channels.length === 3) extra.set("channel", data.channel);
  const res = await fetch(`${API}/datasets/${data.id}/figures/${name}?${query}&${extra}`);
  const body = await res.json();
  if (seq.get(name) !== n) return;                                 // drawn again meanwhile
  if (!res.ok) {
    refused.set(name, message(body, res));
    return;
  }
  refused.delete(name);
  // The panel's heading names the model; the plot keeps the page's layout without a
  // title, and says in one corner what it shows; the largest error goes to the box.
  const own = data.difference || ["slice", "sphere"].includes(name);
  const layout = own ? { ...body.layout, height: div.layout.height, width: div.layout.width, margin: div.layout.margin }
                     : rangeOverAll({ ...div.layout });
  const label = data.difference ? "(data − model)/model" : `data ${channelLabel()}`;
  layout.title = { text: "" };
  const image = body.data.find((t) => t.type === "heatmap" && t.colorbar);
  let traces = body.data;
  if (image) {
    // an image says what it shows in its colour bar's title: a label above the plot's
    // corner ran into the y axis title, which reaches past the top of a square image
    // ("data (r): f (1/sr)", one line: each line of the title shortens the bar)
    const bar = image.colorbar, [unit, ...note] = String(bar.title?.text ?? "").split("<br>");
    const text = [`${label}: ${unit}`, ...note].join("<br>");
    traces = body.data.map((t) => (t === image ? { ...t, colorbar: { ...bar, title: { ...bar.title, text } } } : t));
    layout.annotations = (layout.annotations || []).filter((a) => a.name !== LABEL);
  } else {
    // the page's own annotations stay; this module's label of an earlier overlay (another
    // channel's) is replaced, not kept beside the new one
    layout.annotations = [...(own ? layout.annotations || [] : (div.layout.annotations || [])).filter((a) => a.name !== LABEL),
      { name: LABEL, text: label, xref: "paper", yref: "paper", x: 0, y: 1, xanchor: "left", yanchor: "bottom",
        showarrow: false, font: { size: 11, color: "#000" } }];
  }
  await window.__brdf.overlay(name, { data: traces, layout });
  // as text, in the page's notation: Plotly's "θ<sub>o</sub>" (the figure's) reads "θ_o"
  const title = String(body.layout.title.text).replace(/(\p{L})<sub>([\p{L}\p{N}]+)<\/sub>/gu, "$1_$2");
  const largest = title.slice(title.indexOf("largest"));
  div.dataset.overlay = data.difference ? "difference" : "data";
  div.dataset.largest = largest;
  largestList.set(name, largest);
  showLargest();
  div.dispatchEvent(new CustomEvent("brdf-data-drawn", { detail: { largest } }));
}

const channelLabel = () => `(${data.summary.channels.length === 3 ? data.channel : data.summary.channels[0]})`;
const largestList = new Map();
const largestBox = el("ul", { id: "data-largest", style: "margin:4px 0 0;padding-left:16px" });
tools.after(largestBox);

function showLargest() {
  largestBox.replaceChildren(...[...largestList].map(([name, text]) =>
    el("li", { text: `${name}: (data − model)/model ${text}` })));
}

// --------------------------------------------------------------------- fit --
/** Every name a model may have (options, sub-options, parameters of any choice). */
function modelNames() {
  const models = window.__brdf.models;
  const names = new Set([...Object.keys(models.options), ...Object.keys(models.sub_options || {}),
                         ...models.params.map((p) => p.name)]);
  for (const opt of Object.values(models.options)) for (const c of opt.choices) for (const p of c.params) names.add(p.name);
  return names;
}

function modelOfPage() {
  const q = new URLSearchParams(window.__brdf.url("lobe")?.split("?")[1] || "");
  const names = modelNames();
  const model = {};
  names.add("material");
  for (const [k, v] of q) if (names.has(k)) model[k] = Number.isFinite(Number(v)) && v !== "" ? Number(v) : v;
  return model;
}

// Parameters of a chosen Fresnel that a fit leaves where they are: Schlick's grazing value
// and exponent shape the approximation, not the material; freed, they run to their bounds
// (measured on a MERL file of a Schlick model: f90 → 1, p → 1, the residual unchanged).
const FIT_HELD = new Set(["f90", "fresnel_p"]);
const SYMBOLS = { alpha: "α", alpha_y: "α_y", alpha2: "α₂", lobe_mix: "w", kd: "k_d", f0: "F₀", ior: "η", k: "κ",
                  gamma: "γ", p: "p" };

/** The parameters a fit of `model` frees: the roughness (and its second lobe's), the
 * diffuse weight, the NDF's shape and every parameter of the chosen Fresnel (η and κ for a
 * conductor) that describes the material; none of the Fresnel's when a measured material sets it. */
function freeOf(model) {
  const models = window.__brdf.models;
  const choice = (group) => models.options[group]?.choices.find((c) => c.name === (model[group] ?? models.options[group].default));
  const free = ["alpha"];
  if (model.alpha_y !== undefined) free.push("alpha_y");
  if (model.alpha2 !== undefined) free.push("alpha2", "lobe_mix");
  free.push("kd", ...(choice("ndf")?.params || []).map((p) => p.name));
  if (model.material === undefined) free.push(...(choice("fresnel")?.params || []).map((p) => p.name).filter((n) => !FIT_HELD.has(n)));
  return free;
}

function syncFitLabel() {
  if (!window.__brdf?.models) return;          // the page not booted yet: labelled after its first draw
  const free = freeOf(modelOfPage());
  fitButton.textContent = `Fit ${free.map((n) => SYMBOLS[n] || n).join(", ")}`;
  fitButton.title = `Least squares of ${free.join(", ")} to the data; the rest of the model is held as it is`;
}

async function fit() {
  const model = modelOfPage();
  const free = freeOf(model);
  fitResult.textContent = "Fitting…";
  const res = await fetch(`${API}/fit`, { method: "POST", headers: { "Content-Type": "application/json" },
    body: JSON.stringify({ data: data.id, model, free, measure: "log",
                           channel: data.summary.channels.length === 3 ? data.channel : null }) });
  const body = await res.json();
  if (!res.ok) {
    fitResult.textContent = `Fit refused: ${message(body, res)}`;
    return;
  }
  const lines = Object.entries(body.params).map(([k, v]) => `${k} = ${v.toPrecision(4)} ± ${(body.stderr?.[k] ?? NaN).toPrecision(2)}`);
  const held = Object.entries(body.model).filter(([k]) => !free.includes(k)).map(([k, v]) => `${k}=${v}`);
  // what the API says of the fit's quality (warnings when the residual shows the model
  // does not describe the data), a parameter stopped at its range's end, no convergence
  const warnings = [...(body.warnings || []), ...(body.warning ? [body.warning] : [])]
    .map((w) => (typeof w === "string" ? w : w.message || JSON.stringify(w)));
  if (body.at_bound?.length) warnings.push(`${body.at_bound.join(", ")} stopped at the end of its range: the data may want a value the model cannot take.`);
  if (!body.converged) warnings.push(`not converged: ${body.message}`);
  const keep = new URLSearchParams(location.search);          // the panels and view stay
  for (const name of [...modelNames(), "material"]) keep.delete(name);
  for (const [k, v] of Object.entries(body.model)) keep.set(k, v);
  const use = el("a", { id: "data-fit-use", href: `/?${keep}`, text: "Use the fitted model",
                        title: "Load the fitted model into the controls (the data stay open)" });
  fitResult.replaceChildren(
    el("div", { id: "data-fit-params", text: `Fitted: ${lines.join(", ")}` }),
    el("div", { id: "data-fit-held", text: `Held fixed: ${held.join(", ") || "nothing"}` }),
    el("div", { text: `residual ${body.residual.toPrecision(3)} (${body.measure?.name || "log"}), ${body.evaluations} evaluations, ${body.seconds.toFixed(2)} s` }),
    ...warnings.map((w) => el("div", { class: "data-fit-warning", role: "alert", style: "color:#b3261e", text: `Warning: ${w}` })),
    use);
}

window.__brdfData = { get id() { return data.id; }, refused: () => Object.fromEntries(refused) };
handOver();
place();
restore();
