/* The embed page, /embed/{kind}?...: one figure, sized to its iframe.
 *
 * The query string is the figure's query (model + view parameters, as the API takes
 * them) plus three page options: controls=1 adds sliders for the parameters that shape
 * this figure (α, and the view's own angles and toggles); buttons=0 hides the export
 * bar. State lives in the URL, as in the explorer.
 */
"use strict";

(() => {
  const { API, el, richText, apiMessage, query } = window.BRDF;
  const PAGE_OPTIONS = ["controls", "buttons", "embed"];
  const SKIP_FIELDS = new Set(["n", "n_theta", "n_phi", "mu", "tol"]);
  const LOADING_DELAY_MS = 300;
  const PLOT_CONFIG = { responsive: true, displaylogo: false,
                        modeBarButtonsToRemove: ["lasso2d", "select2d", "toImage"] };

  const kind = decodeURIComponent(location.pathname.split("/").filter(Boolean).pop() || "");
  const search = new URLSearchParams(location.search);
  const withControls = search.get("controls") === "1";
  const withButtons = search.get("buttons") !== "0";
  const params = {};                       // THE state: the figure's query
  for (const [k, v] of search) if (!PAGE_OPTIONS.includes(k)) params[k] = v;

  const plot = document.getElementById("plot");
  const status = document.getElementById("status");
  let inflight = false, dirty = false, drawnKey = null, loadingTimer = 0, title = kind;

  function setStatus(kindOf, text = "") {
    status.className = `panel-status${kindOf ? ` ${kindOf}` : ""}`;
    status.textContent = text;
  }

  function figureUrl() {
    return `${API}/figures/${encodeURIComponent(kind)}${params.vary ? ".json" : ""}?${query(params)}`;
  }

  function writeUrl() {
    const q = { ...params };
    if (withControls) q.controls = "1";
    if (!withButtons) q.buttons = "0";
    history.replaceState(null, "", `${location.pathname}?${query(q)}`);
    document.getElementById("open-explorer").href = explorerUrl();
  }

  function explorerUrl() {
    return `/?${query({ ...params, show: kind })}`;
  }

  // One request in flight; a change meanwhile is fetched when it lands.
  async function draw() {
    if (inflight) { dirty = true; return; }
    const url = figureUrl();
    if (url === drawnKey) return;
    inflight = true;
    loadingTimer = setTimeout(() => setStatus("loading", "loading…"), LOADING_DELAY_MS);
    try {
      let res;
      try {
        res = await fetch(url, { headers: { Accept: "application/json" } });
      } catch {
        throw new Error("Cannot reach the server.");
      }
      const body = await res.json().catch(() => null);
      if (!res.ok) throw new Error(apiMessage(body, res));
      const given = body.layout || {};
      const layout = { ...window.BRDF.fitLayout(given, { keepTitle: true }), uirevision: kind };
      const t = given.title && (given.title.text || given.title);
      if (t) {
        title = String(t);
        document.title = title.replace(/<[^>]*>/g, "");
        plot.setAttribute("aria-label", document.title);
      }
      await Plotly.react(plot, body.data, layout, PLOT_CONFIG);
      drawnKey = url;
      setStatus(null);
    } catch (e) {
      setStatus("error", e.message || String(e));
    } finally {
      clearTimeout(loadingTimer);
      if (status.classList.contains("loading")) setStatus(null);
      inflight = false;
      if (dirty) { dirty = false; draw(); }
    }
  }

  function onChange() {
    writeUrl();
    draw();
  }

  // ---------------------------------------------------------------- controls ----
  // A slider with its number box; both write params[name] (validated against the range).
  function numberControl(name, label, lo, hi, def, description, logScale) {
    const id = `c-${name.replace(/_/g, "-")}`;
    const toSlider = (v) => (logScale ? Math.log10(v) : v);
    const fromSlider = (x) => (logScale ? Number((10 ** x).toPrecision(3)) : Number(Number(x).toFixed(2)));
    const value = params[name] !== undefined ? Number(params[name]) : def;
    const box = el("input", { type: "number", id, min: lo, max: hi, step: "any", inputmode: "decimal",
                              value: String(value) });
    const slider = el("input", { type: "range", id: `${id}-slider`,
                                 min: toSlider(logScale ? Math.max(lo, 1e-4) : lo), max: toSlider(hi),
                                 step: logScale ? 0.01 : (hi - lo) / 180, value: String(toSlider(value)),
                                 "aria-label": `${label} slider` });
    const set = (v, from) => {
      params[name] = String(v);
      if (from !== "box") box.value = String(v);
      if (from !== "slider") slider.value = String(toSlider(v));
      onChange();
    };
    slider.addEventListener("input", () => set(fromSlider(slider.value), "slider"));
    box.addEventListener("input", () => {
      const x = Number(box.value);
      const ok = box.value.trim() !== "" && Number.isFinite(x) && x >= lo && x <= hi;
      box.toggleAttribute("aria-invalid", !ok);
      if (ok) set(x, "box");
    });
    box.addEventListener("change", () => { box.value = params[name] ?? String(def); box.removeAttribute("aria-invalid"); });
    return el("div", { class: "embed-param" },
      el("label", { for: id, title: description || "" }, richText(label)), slider, box);
  }

  function toggleControl(name, label, def, description) {
    const id = `c-${name.replace(/_/g, "-")}`;
    const box = el("input", { type: "checkbox", id });
    box.checked = params[name] !== undefined ? ["1", "true", "yes", "on"].includes(String(params[name]).toLowerCase()) : !!def;
    box.addEventListener("change", () => { params[name] = box.checked ? "true" : "false"; onChange(); });
    return el("label", { class: "toggle", for: id, title: description || "" }, box, el("span", {}, richText(label)));
  }

  function choiceControl(name, label, choices, def, description) {
    const id = `c-${name.replace(/_/g, "-")}`;
    const sel = el("select", { id, class: "mini" });
    for (const c of choices) sel.append(el("option", { value: c, text: c }));
    sel.value = params[name] ?? def;
    sel.addEventListener("change", () => { params[name] = sel.value; onChange(); });
    return el("label", { class: "mini-field", for: id, title: description || "" }, el("span", {}, richText(label)), sel);
  }

  async function buildControls() {
    const [models, views] = await Promise.all(["/models", "/views"].map(async (path) => {
      const res = await fetch(`${API}${path}`);
      if (!res.ok) throw new Error(`${path}: HTTP ${res.status}`);
      return res.json();
    }));
    const view = views.find((v) => v.name === kind);
    const form = document.getElementById("embed-controls");
    const kids = [];
    // The roughness always shapes the figure (in whichever form the URL gives it).
    const rough = models.params.find((p) => p.name === (params.roughness !== undefined ? "roughness" : "alpha"));
    if (rough) kids.push(numberControl(rough.name, rough.label, rough.lo, rough.hi, rough.default,
                                       rough.description, rough.scale === "log"));
    const geometry = new Map(models.geometry.map((p) => [p.name, p]));
    for (const f of view ? view.fields : []) {
      if (SKIP_FIELDS.has(f.name) || f.name === params.vary) continue;
      const g = geometry.get(f.name);
      if (f.type === "boolean") kids.push(toggleControl(f.name, f.name === "cosine" ? "× cos θ" : f.name === "log" ? "log scale" : f.name, f.default, f.description));
      else if (f.enum) kids.push(choiceControl(f.name, f.name, f.enum, f.default, f.description));
      else if (g) kids.push(numberControl(f.name, g.label, g.lo, g.hi, f.default, g.description, false));
      else if (f.type === "number" && Number.isFinite(f.minimum) && Number.isFinite(f.maximum)) {
        kids.push(numberControl(f.name, f.name.replace(/_deg$/, " (°)"), f.minimum, f.maximum, f.default, f.description, false));
      }
    }
    form.append(...kids);
    form.hidden = false;
  }

  // ------------------------------------------------------------------ buttons ----
  function buildButtons() {
    const bar = document.getElementById("embed-bar");
    const exports = window.BRDF.exportBar(
      () => ({ kind, params: { ...params }, div: plot, title }),
      (k, text) => {
        if (k === "busy") setStatus("loading", text);
        else if (k === "error" || k === "note") setStatus("note", text);
        else setStatus(null);
      });
    bar.insertBefore(exports, document.getElementById("copy-link"));
    document.getElementById("copy-link").addEventListener("click", async (ev) => {
      const url = `${location.origin}${explorerUrl()}`;
      if (await window.BRDF.copyText(url)) window.BRDF.flash(ev.target, "Copied ✓");
      else setStatus("note", url);
    });
    bar.hidden = false;
  }

  if (withButtons) buildButtons();
  writeUrl();
  if (withControls) buildControls().catch((e) => setStatus("error", `Controls: ${e.message}`));
  draw();

  // Test hook, as in the explorer.
  window.__embed = { pending: () => (inflight || dirty ? 1 : 0), params, drawn: () => drawnKey !== null };
})();
