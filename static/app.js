/* BRDF Lobe Explorer: the page.
 *
 * Everything the page shows follows from one object, `state`:
 *   controls --(input events)--> state --> URL (history.replaceState)
 *                                     \--> panels (one fetch in flight per panel)
 * The controls themselves are built from GET /api/v1/models: menus from the option
 * choices, number boxes and sliders from the Params (range, default, label, scale).
 *
 * Fetching: each panel has at most one request in flight. A change while one is in
 * flight only marks the panel dirty; when the response has been drawn, the panel
 * fetches again with the newest state (coalescing). So a stale response can never be
 * drawn over a newer one, and a fast slider costs at most one extra request per panel.
 */
"use strict";

(() => {
  const API = "/api/v1";
  const LOADING_DELAY_MS = 300;
  const PRIMARY_WAIT_MS = 250;       // longest a panel waits for the lobe to draw first
  const URL_WRITE_MS = 120;          // Chrome throttles replaceState past ~200 per 10 s
  const INVALID_DELAY_MS = 450;      // typing "0." on the way to "0.05" is not an error yet
  const LOG_TICKS = 1000;            // resolution of a log-scale slider
  const PLOT_CONFIG = {
    responsive: true,
    displaylogo: false,
    modeBarButtonsToRemove: ["lasso2d", "select2d"],
  };
  // Presentation hint only (ranges and scales come from the API): the part of a
  // log-scale parameter's range that gets most of its slider's travel.
  const SLIDER_FOCUS = { alpha: [0.01, 0.3, 0.65], alpha_y: [0.01, 0.3, 0.65] };
  // Page-only toggles kept in the URL next to the model's parameters.
  const FLAGS = ["log", "cosine", "lobe3d"];
  const TRUE_WORDS = new Set(["1", "true", "yes", "on"]);

  // Lobe-panel flags are also API parameters; "lobe3d" only shows the 5th panel.
  const PANELS = [
    { name: "lobe", path: "/figures/lobe", primary: true,
      extra: (s) => ({ theta_i_deg: s.theta_i_deg, phi_i_deg: s.phi_i_deg,
                       log: s.log, cosine: s.cosine }),
      uirev: (s) => `lobe:${s.log}:${s.cosine}` },
    { name: "ndf", path: "/figures/ndf", extra: sliceAzimuth },
    { name: "g1", path: "/figures/g1", extra: sliceAzimuth },
    { name: "albedo", path: "/figures/albedo", extra: sliceAzimuth },
    { name: "lobe3d", path: "/figures/lobe3d",
      extra: (s) => ({ theta_i_deg: s.theta_i_deg, phi_i_deg: s.phi_i_deg, log: s.log }),
      uirev: (s) => `lobe3d:${s.log}`,
      visible: (s) => s.lobe3d },
  ];

  // D, Λ/G1 and E(μ) are taken at one azimuth: that of the plane of incidence when
  // anisotropic; for an isotropic surface every azimuth is the same (API default).
  function sliceAzimuth(s) {
    return isAnisotropic(s) ? { phi_deg: s.phi_i_deg } : {};
  }

  // ------------------------------------------------------------------ state ------
  const state = {};                 // THE single source of truth
  let defaultState = {};
  let models = null;
  const params = new Map();         // name -> Param (model, geometry and choice params)
  const controls = new Map();       // name -> {param, box, slider, row, msg, map}
  let groups = [];                  // [{name, label, default, choices}]
  let booting = true;
  const embed = new URLSearchParams(location.search).get("embed") === "1";

  const $ = (sel, root = document) => root.querySelector(sel);
  const el = (tag, attrs = {}, ...kids) => {
    const e = document.createElement(tag);
    for (const [k, v] of Object.entries(attrs)) {
      if (v === null || v === undefined || v === false) continue;
      if (k === "class") e.className = v;
      else if (k === "text") e.textContent = v;
      else e.setAttribute(k, v === true ? "" : v);
    }
    for (const kid of kids) if (kid) e.append(kid);
    return e;
  };

  // The element id of a parameter's number box: the API name without "_deg".
  const controlId = (name) => name.replace(/_deg$/, "");

  function choiceOf(groupName, choiceName) {
    const g = groups.find((x) => x.name === groupName);
    return g && g.choices.find((c) => c.name === choiceName);
  }

  // α_y takes part when the toggle is on and the NDF can be anisotropic.
  function anisoAllowed(s) {
    const c = choiceOf("ndf", s.ndf);
    return params.has("alpha_y") && !(c && c.anisotropic === false);
  }
  function isAnisotropic(s) {
    return !!s.anisotropic && anisoAllowed(s);
  }

  function appliesTo(choice, ndf) {
    return !choice.applies_to || choice.applies_to.includes(ndf);
  }

  // The continuous parameters that belong in a query for state s, in a fixed order.
  function activeParams(s) {
    const out = [];
    for (const p of models.params) {
      if (p.name === "alpha_y" && !isAnisotropic(s)) continue;
      out.push(p);
    }
    for (const g of groups) {
      const c = choiceOf(g.name, s[g.name]);
      if (c) for (const p of c.params || []) if (!out.some((q) => q.name === p.name)) out.push(p);
    }
    return out;
  }

  function modelQuery(s) {
    const q = {};
    for (const g of groups) q[g.name] = s[g.name];
    for (const p of activeParams(s)) q[p.name] = s[p.name];
    return q;
  }

  // State -> page URL: API names, only non-default values (alpha_y whenever
  // anisotropic: its presence is what says "anisotropic").
  function stateToSearch(s) {
    const q = new URLSearchParams();
    for (const g of groups) if (s[g.name] !== g.default) q.set(g.name, s[g.name]);
    for (const p of [...activeParams(s), ...models.geometry]) {
      if (p.name === "alpha_y" || s[p.name] !== p.default) q.set(p.name, String(s[p.name]));
    }
    for (const f of FLAGS) if (s[f]) q.set(f, "true");
    if (embed) q.set("embed", "1");
    const str = q.toString();
    return str ? `?${str}` : "";
  }

  // Page URL -> state. Values the API would reject are corrected (and said so), so a
  // hand-edited link always opens a working page.
  function stateFromSearch(search) {
    const q = new URLSearchParams(search);
    const s = structuredClone(defaultState);
    const notes = [];
    for (const g of groups) {
      const v = q.get(g.name);
      if (v === null) continue;
      if (choiceOf(g.name, v)) s[g.name] = v;
      else notes.push(`${g.name}=${v} is not one of ${g.choices.map((c) => c.name).join(", ")}; using ${g.default}.`);
    }
    for (const p of params.values()) {
      const raw = q.get(p.name);
      if (raw === null) continue;
      const x = raw.trim() === "" ? NaN : Number(raw);
      if (!Number.isFinite(x)) {
        notes.push(`${p.name}=${raw} is not a number; using ${p.default}.`);
      } else if (!inRange(p, x)) {
        const c = clampParam(p, x);
        notes.push(`${p.name}=${raw} is outside ${rangeText(p)}; using ${c}.`);
        s[p.name] = c;
      } else {
        s[p.name] = x;
      }
    }
    s.anisotropic = params.has("alpha_y") && q.has("alpha_y");
    for (const f of FLAGS) s[f] = TRUE_WORDS.has((q.get(f) || "").toLowerCase());
    notes.push(...fixApplicability(s));
    return { s, notes };
  }

  // A masking (or any choice with applies_to) that does not apply to the NDF is
  // replaced by the group's default, or else the first choice that applies.
  function fixApplicability(s) {
    const notes = [];
    for (const g of groups) {
      const c = choiceOf(g.name, s[g.name]);
      if (!c || appliesTo(c, s.ndf)) continue;
      const alt = [choiceOf(g.name, g.default), ...g.choices].find((x) => x && appliesTo(x, s.ndf));
      if (alt) {
        notes.push(`${g.label} “${c.label}” does not apply to ${s.ndf}; using “${alt.label}”.`);
        s[g.name] = alt.name;
      }
    }
    return notes;
  }

  function inRange(p, x) {
    return (p.lo_open ? x > p.lo : x >= p.lo) && x <= p.hi;
  }
  function rangeText(p) {
    return `${p.lo_open ? "(" : "["}${p.lo}, ${p.hi}]`;
  }
  function clampParam(p, x) {
    if (x > p.hi) return p.hi;
    if (p.lo_open ? x <= p.lo : x < p.lo) return p.lo_open ? sliderLo(p) : p.lo;
    return x;
  }
  // Lowest value a slider reaches (an open or zero lower end of a log scale needs one).
  function sliderLo(p) {
    if (p.scale === "log") return p.lo > 0 ? p.lo : p.hi * 1e-4;
    return p.lo_open ? p.lo + linearStep(p) : p.lo;
  }

  // ---------------------------------------------------------- slider mapping ------
  function linearStep(p) {
    const span = p.hi - p.lo;
    return span > 0 ? 10 ** Math.floor(Math.log10(span / 100)) : 1;
  }
  function decimalsOf(step) {
    return Math.max(0, -Math.floor(Math.log10(step) + 1e-9));
  }

  // Piecewise-linear in log(value): [lo, a] and [b, hi] share what [a, b] leaves.
  function logMap(p) {
    const u0 = Math.log(sliderLo(p));
    const u3 = Math.log(p.hi);
    let knots = [[0, u0], [1, u3]];
    const f = SLIDER_FOCUS[p.name];
    if (f) {
      const u1 = Math.log(f[0]), u2 = Math.log(f[1]);
      if (u0 < u1 && u1 < u2 && u2 < u3) {
        const rest = 1 - f[2], outside = (u1 - u0) + (u3 - u2);
        const t1 = rest * (u1 - u0) / outside;
        knots = [[0, u0], [t1, u1], [t1 + f[2], u2], [1, u3]];
      }
    }
    const interp = (x, from, to) => {
      for (let i = 1; i < knots.length; i++) {
        const a = knots[i - 1], b = knots[i];
        if (x <= b[from] || i === knots.length - 1) {
          const w = (x - a[from]) / (b[from] - a[from]);
          return a[to] + Math.min(1, Math.max(0, w)) * (b[to] - a[to]);
        }
      }
      return knots[knots.length - 1][to];
    };
    return {
      min: 0, max: LOG_TICKS, step: 1,
      toSlider: (v) => Math.round(LOG_TICKS * interp(Math.log(Math.max(v, sliderLo(p))), 1, 0)),
      fromSlider: (x) => {
        const v = Math.exp(interp(Number(x) / LOG_TICKS, 0, 1));
        if (Number(x) <= 0) return sliderLo(p);
        if (Number(x) >= LOG_TICKS) return p.hi;
        return clampParam(p, Number(v.toPrecision(3)));
      },
      nudge: (v, dir, big) => {
        const t = Math.round(LOG_TICKS * interp(Math.log(Math.max(v, sliderLo(p))), 1, 0));
        return Math.min(LOG_TICKS, Math.max(0, t + dir * (big ? 50 : 5)));
      },
    };
  }

  function linearMap(p) {
    const step = linearStep(p), dec = decimalsOf(step);
    const snap = (x) => clampParam(p, Number((Math.round((x - p.lo) / step) * step + p.lo).toFixed(dec)));
    return {
      min: p.lo, max: p.hi, step,
      toSlider: (v) => v,
      fromSlider: (x) => snap(Number(x)),
      nudge: (v, dir, big) => snap(v + dir * step * (big ? 10 : 1)),
    };
  }

  // ------------------------------------------------------------- controls ------
  const form = $("#controls-form");

  function section(title, ...kids) {
    return el("fieldset", { class: "group" }, el("legend", { text: title }), ...kids);
  }

  function paramControl(p) {
    const id = controlId(p.name);
    const map = p.scale === "log" ? logMap(p) : linearMap(p);
    const box = el("input", {
      type: "number", id, name: p.name, min: p.lo, max: p.hi, step: "any",
      inputmode: "decimal", "aria-describedby": `${id}-msg`,
    });
    const slider = el("input", {
      type: "range", id: `${id}-slider`, min: map.min, max: map.max, step: map.step,
    });
    const scaleNote = p.scale === "log" ? " (log scale)" : "";
    const msg = el("div", { class: "param-msg", id: `${id}-msg`, hidden: true });
    const row = el("div", { class: "param", "data-param": p.name },
      el("div", { class: "param-head" },
        el("label", { for: id, title: p.description || "" }, richText(p.label)),
        el("span", { class: "box" }, box, p.unit ? el("span", { class: "unit", text: p.unit }) : null)),
      el("label", { for: `${id}-slider`, class: "sr-only", text: `${p.label} slider${scaleNote}` }),
      slider,
      el("div", { class: "range-ends", "aria-hidden": "true" },
        el("span", { text: fmtEnd(p.scale === "log" ? sliderLo(p) : p.lo, p) }),
        el("span", { text: fmtEnd(p.hi, p) })),
      msg);
    const c = { param: p, box, slider, row, msg, map, invalid: false, invalidTimer: 0 };

    slider.addEventListener("input", () => {
      setParam(p.name, map.fromSlider(slider.value), "slider");
    });
    box.addEventListener("input", () => {
      const raw = box.value.trim();
      const x = raw === "" ? NaN : Number(raw);
      if (!Number.isFinite(x)) return showInvalid(c, "Enter a number.");
      if (!inRange(p, x)) return showInvalid(c, `Must be in ${rangeText(p)}.`);
      setParam(p.name, x, "box");
    });
    box.addEventListener("change", () => {   // leaving an invalid box restores the value
      if (c.invalid) syncControl(p.name);
    });
    box.addEventListener("keydown", (ev) => {
      if (ev.key !== "ArrowUp" && ev.key !== "ArrowDown") return;
      ev.preventDefault();
      const dir = ev.key === "ArrowUp" ? 1 : -1;
      const next = map.nudge(state[p.name], dir, ev.shiftKey);
      setParam(p.name, p.scale === "log" ? map.fromSlider(next) : next, "key");
    });
    controls.set(p.name, c);
    return row;
  }

  // "θ_i (incidence)" -> θ<sub>i</sub> (incidence), built from text nodes only.
  function richText(text) {
    const frag = document.createDocumentFragment();
    const re = /([^\s(_]+)_([A-Za-z0-9]+|\{[^}]*\})/g;
    let last = 0, m;
    text = String(text).replace(/<br\s*\/?>/gi, " ").replace(/<[^>]*>/g, "");
    while ((m = re.exec(text))) {
      frag.append(text.slice(last, m.index) + m[1], el("sub", { text: m[2].replace(/[{}]/g, "") }));
      last = re.lastIndex;
    }
    frag.append(text.slice(last));
    return frag;
  }

  function fmtEnd(v, p) {
    if (p.scale === "log" && v > 0 && v < 0.01) return `10${superscript(Math.round(Math.log10(v)))}`;
    return `${v}${p.unit || ""}`;
  }
  function superscript(n) {
    const map = { "-": "⁻", 0: "⁰", 1: "¹", 2: "²", 3: "³", 4: "⁴", 5: "⁵", 6: "⁶", 7: "⁷", 8: "⁸", 9: "⁹" };
    return String(n).split("").map((ch) => map[ch] ?? ch).join("");
  }

  function showInvalid(c, text, now = false) {
    clearTimeout(c.invalidTimer);
    c.invalid = true;
    const show = () => {
      c.box.setAttribute("aria-invalid", "true");
      c.msg.textContent = text;
      c.msg.hidden = false;
    };
    if (now) show();
    else c.invalidTimer = setTimeout(show, INVALID_DELAY_MS);
  }

  function clearInvalid(c) {
    clearTimeout(c.invalidTimer);
    c.invalid = false;
    c.box.removeAttribute("aria-invalid");
    c.msg.hidden = true;
  }

  function choiceSelect(g) {
    const sel = el("select", { id: g.name, name: g.name });
    for (const c of g.choices) {
      sel.append(el("option", { value: c.name, text: c.label, title: c.description || "" }));
    }
    sel.addEventListener("change", () => {
      state[g.name] = sel.value;
      const notes = fixApplicability(state);
      if (notes.length) showNotices(notes);
      syncAllControls();
      onStateChange();
    });
    const info = el("p", { class: "choice-info", id: `${g.name}-info` });
    const paramsBox = el("div", { class: "choice-params" });
    const seen = new Set();
    for (const c of g.choices) {
      for (const p of c.params || []) {
        if (seen.has(p.name) || controls.has(p.name)) continue;
        seen.add(p.name);
        paramsBox.append(paramControl(p));
      }
    }
    return el("div", { class: "choice", "data-group": g.name },
      el("label", { for: g.name, class: "choice-label" }, richText(g.label || g.name)),
      sel,
      info, paramsBox);
  }

  function buildControls() {
    form.textContent = "";
    controls.clear();
    const ndfGroup = groups.find((g) => g.name === "ndf");
    const others = groups.filter((g) => g.name !== "ndf");

    const surface = [];
    if (ndfGroup) surface.push(choiceSelect(ndfGroup));
    for (const p of models.params) {
      if (p.name === "alpha_y") {
        surface.push(el("label", { class: "toggle aniso", for: "anisotropic" },
          el("input", { type: "checkbox", id: "anisotropic", name: "anisotropic" }),
          el("span", {}, richText("anisotropic (α_x ≠ α_y)"))));
      }
      surface.push(paramControl(p));
    }
    form.append(section("Surface", ...surface));
    form.append(section("Incidence", ...models.geometry.map(paramControl)));
    if (others.length) form.append(section("Shadowing & Fresnel", ...others.map(choiceSelect)));
    form.append(section("View",
      el("label", { class: "toggle", for: "lobe3d" },
        el("input", { type: "checkbox", id: "lobe3d", name: "lobe3d" }),
        el("span", { text: "show the 3-D lobe panel" }))));

    const aniso = $("#anisotropic");
    if (aniso) {
      aniso.addEventListener("change", () => {
        state.anisotropic = aniso.checked;
        if (aniso.checked) state.alpha_y = state.alpha;   // starts isotropic: nothing jumps
        syncAllControls();
        onStateChange();
      });
    }
    for (const f of FLAGS) {
      const box = document.getElementById(f);
      box.addEventListener("change", () => {
        state[f] = box.checked;
        onStateChange();
        const section = document.querySelector(`.panel[data-panel="${f}"]`);
        if (section && box.checked) section.scrollIntoView({ behavior: "smooth", block: "nearest" });
      });
    }
    form.hidden = false;
  }

  function setParam(name, value, source) {
    state[name] = value;
    const c = controls.get(name);
    clearInvalid(c);
    if (source !== "box") c.box.value = String(value);
    if (source !== "slider") c.slider.value = c.map.toSlider(value);
    onStateChange();
  }

  function syncControl(name) {
    const c = controls.get(name);
    if (!c) return;
    c.box.value = String(state[name]);
    c.slider.value = c.map.toSlider(state[name]);
    clearInvalid(c);
  }

  // Only the parameters that take part (α_y when anisotropic, a choice's params when
  // that choice is selected) are shown and enabled.
  function syncActiveRows() {
    const active = new Set([...activeParams(state), ...models.geometry].map((p) => p.name));
    for (const [name, c] of controls) {
      const on = active.has(name);
      c.row.hidden = !on;
      c.box.disabled = c.slider.disabled = !on;
    }
  }

  // Controls <- state (after load, reset, or a change that moves other controls).
  function syncAllControls() {
    for (const name of controls.keys()) syncControl(name);
    syncActiveRows();
    for (const g of groups) {
      const sel = document.getElementById(g.name);
      sel.value = state[g.name];
      for (const opt of sel.options) {
        const c = choiceOf(g.name, opt.value);
        opt.disabled = !appliesTo(c, state.ndf);
        opt.title = opt.disabled ? `Not available for ${state.ndf}` : (c.description || "");
      }
      const c = choiceOf(g.name, state[g.name]);
      const info = document.getElementById(`${g.name}-info`);
      info.textContent = "";
      if (c && c.description) info.append(el("span", {}, richText(c.description)));
      if (c && c.reference) info.append(el("span", { class: "ref", text: c.reference }));
      info.hidden = !info.textContent;
    }
    const aniso = $("#anisotropic");
    if (aniso) {
      aniso.disabled = !anisoAllowed(state);
      aniso.checked = isAnisotropic(state);
      aniso.parentElement.title = aniso.disabled ? `${state.ndf} is isotropic only` : "";
    }
    for (const f of FLAGS) document.getElementById(f).checked = !!state[f];
  }

  // --------------------------------------------------------------- panels ------
  const panels = PANELS.map((spec) => {
    const section = document.querySelector(`.panel[data-panel="${spec.name}"]`);
    return {
      spec, section,
      div: document.getElementById(`plot-${spec.name}`),
      status: section.querySelector(".panel-status"),
      heading: section.querySelector(".panel-head h2"),
      inflight: false, dirty: false,
      doneKey: null, drawn: false, error: null, loadingTimer: 0,
    };
  });

  const isVisible = (panel) => !panel.spec.visible || panel.spec.visible(state);

  function panelUrl(panel) {
    const q = new URLSearchParams();
    const all = { ...modelQuery(state), ...panel.spec.extra(state) };
    for (const [k, v] of Object.entries(all)) if (v !== undefined && v !== null) q.set(k, String(v));
    return `${API}${panel.spec.path}?${q}`;
  }

  function schedule(panel) {
    panel.section.hidden = !isVisible(panel);
    if (!isVisible(panel)) return;
    if (panel.inflight) { panel.dirty = true; return; }
    if (panelUrl(panel) === panel.doneKey) return;   // nothing this panel shows has changed
    fetchAndDraw(panel);
  }

  async function fetchAndDraw(panel) {
    panel.inflight = true;
    panel.loadingTimer = setTimeout(() => setStatus(panel, "loading", "loading…"), LOADING_DELAY_MS);
    let url = null;
    try {
      // The lobe goes first (server time and main-thread drawing); the others follow
      // with whatever the state is by then.
      if (!panel.spec.primary) await primaryDrawn();
      url = panelUrl(panel);
      if (url === panel.doneKey) return;
      const uirev = panel.spec.uirev ? panel.spec.uirev(state) : panel.spec.name;
      let res;
      try {
        res = await fetch(url, { headers: { Accept: "application/json" } });
      } catch (e) {
        throw new Error("Cannot reach the server.");
      }
      const body = await res.json().catch(() => null);
      if (!res.ok) throw new Error(apiMessage(body, res));
      if (!body || !Array.isArray(body.data)) throw new Error("The server sent no figure.");
      const layout = fitLayout(panel, body.layout || {});
      if (layout.uirevision === undefined) layout.uirevision = uirev;
      await Plotly.react(panel.div, body.data, layout, PLOT_CONFIG);
      panel.drawn = true;
      panel.error = null;
      setStatus(panel, null);
    } catch (e) {
      panel.error = e.message || String(e);
      setStatus(panel, "error", panel.error);
    } finally {
      clearTimeout(panel.loadingTimer);
      if (url !== null) panel.doneKey = url;
      if (!panel.error && panel.status.classList.contains("loading")) setStatus(panel, null);
      panel.inflight = false;
      if (panel.spec.primary) releaseWaiters();
      panel.section.classList.toggle("empty", !panel.drawn);
      updateErrorLine();
      if (panel.dirty) {
        panel.dirty = false;
        schedule(panel);
      }
    }
  }

  // The API's figures are made to stand alone; in a panel the heading shows the title,
  // the panel sets the size, and a legend sits above the axes, clear of axis titles.
  function fitLayout(panel, given) {
    const layout = { ...given };
    delete layout.width;
    delete layout.height;
    layout.autosize = true;
    layout.margin = { ...(layout.margin || {}) };
    const title = typeof layout.title === "string" ? layout.title : layout.title && layout.title.text;
    if (title) {
      panel.heading.textContent = "";
      panel.heading.append(richText(title));
      panel.heading.title = panel.heading.textContent;
    }
    delete layout.title;
    const cartesian = !layout.polar && !layout.scene && Object.keys(layout).some((k) => /^[xy]axis\d*$/.test(k));
    if (layout.polar) {
      layout.margin.t = Math.min(layout.margin.t ?? 24, 24);
      layout.margin.b = Math.max(layout.margin.b ?? 0, 34);
      if (layout.showlegend !== false) {
        layout.legend = { ...(layout.legend || {}), orientation: "h", x: 0.5, xanchor: "center",
                          y: 0, yanchor: "top", bgcolor: "rgba(255,255,255,0)" };
      }
    }
    else if (layout.scene) layout.margin.t = 0;
    else if (cartesian) {
      const legendShown = layout.showlegend !== false;
      layout.margin.t = legendShown ? 30 : 14;
      layout.margin.b = Math.min(layout.margin.b ?? 50, 46);
      if (legendShown) {
        layout.legend = { ...(layout.legend || {}), orientation: "h", x: 1, xanchor: "right",
                          y: 1.01, yanchor: "bottom", bgcolor: "rgba(255,255,255,0)" };
      }
      for (const k of Object.keys(layout)) {
        if (/^[xy]axis\d*$/.test(k)) layout[k] = { ...layout[k], automargin: true };
      }
    }
    return layout;
  }

  // The lobe is what a slider is watched on: when its request is in flight, the other
  // panels hold their (main-thread) drawing until it has drawn, for at most a moment.
  let waiters = [];
  function primaryDrawn() {
    const primary = panels.find((p) => p.spec.primary);
    if (!primary || !primary.inflight || !isVisible(primary)) return Promise.resolve();
    return new Promise((resolve) => {
      const done = () => { clearTimeout(timer); resolve(); };
      const timer = setTimeout(() => { waiters = waiters.filter((w) => w !== done); resolve(); },
                               PRIMARY_WAIT_MS);
      waiters.push(done);
    });
  }
  function releaseWaiters() {
    const ws = waiters;
    waiters = [];
    for (const w of ws) w();
  }

  // FastAPI's 422: {"detail": "message"} or {"detail": [{loc, msg, ...}, ...]}.
  function apiMessage(body, res) {
    const d = body && body.detail;
    if (typeof d === "string") return d;
    if (Array.isArray(d) && d.length) {
      return d.map((x) => {
        if (typeof x === "string") return x;
        const loc = (x.loc || []).filter((k) => k !== "query" && k !== "body").join(".");
        const msg = x.msg || JSON.stringify(x);
        return loc && !msg.startsWith(`${loc}:`) ? `${loc}: ${msg}` : msg;
      }).join("; ");
    }
    return `The server answered ${res.status} ${res.statusText || ""}`.trim() + ".";
  }

  function setStatus(panel, kind, text = "") {
    panel.status.className = `panel-status${kind ? ` ${kind}` : ""}`;
    panel.status.textContent = text;
    panel.section.classList.toggle("has-error", kind === "error");
  }

  function updateErrorLine() {
    const line = $("#error-line");
    const errs = [...new Set(panels.filter((p) => p.error && isVisible(p)).map((p) => p.error))];
    line.textContent = errs.length ? `Error: ${errs.join(" · ")}` : "";
    line.hidden = !errs.length;
  }

  // Keep plots fitted to their boxes when the layout changes (panel shown, sidebar
  // wraps); window resizes are also handled by Plotly's own `responsive`.
  const resizeObserver = new ResizeObserver((entries) => {
    for (const entry of entries) {
      const div = entry.target;
      if (!div._fullLayout || div.offsetParent === null) continue;
      const { width, height } = entry.contentRect;
      if (width < 10 || height < 10) continue;
      if (Math.abs(div._fullLayout.width - width) < 1 && Math.abs(div._fullLayout.height - height) < 1) continue;
      Promise.resolve(Plotly.Plots.resize(div)).catch(() => {});
    }
  });

  // ------------------------------------------------------------ plumbing ------
  // URL <- state, at most once per URL_WRITE_MS (leading and trailing edge).
  let urlTimer = 0, lastUrlWrite = -Infinity;
  function writeUrl() {
    urlTimer = 0;
    lastUrlWrite = performance.now();
    const search = stateToSearch(state);
    if (search !== location.search) history.replaceState(null, "", location.pathname + search);
  }
  function scheduleUrlWrite() {
    if (urlTimer) return;
    const wait = lastUrlWrite + URL_WRITE_MS - performance.now();
    if (wait <= 0) writeUrl();
    else urlTimer = setTimeout(writeUrl, wait);
  }

  function onStateChange() {
    scheduleUrlWrite();
    syncActiveRows();
    for (const panel of panels) schedule(panel);
    updateErrorLine();
  }

  function showNotices(notes) {
    const box = $("#notice"), list = $("#notice-list");
    list.textContent = "";
    for (const n of notes) list.append(el("li", { text: n }));
    box.hidden = !notes.length;
  }

  function defaultsFromModels() {
    const s = {};
    for (const g of groups) s[g.name] = g.default;
    for (const p of params.values()) s[p.name] = p.default;
    s.anisotropic = false;
    for (const f of FLAGS) s[f] = false;
    return s;
  }

  async function boot() {
    try {
      const res = await fetch(`${API}/models`, { headers: { Accept: "application/json" } });
      const body = await res.json().catch(() => null);
      if (!res.ok || !body) throw new Error(apiMessage(body, res));
      models = body;
    } catch (e) {
      booting = false;
      $("#boot-status").textContent = `Could not load the models: ${e.message}`;
      $("#boot-status").classList.add("failed");
      return;
    }
    models.params = models.params || [];
    models.geometry = models.geometry || [];
    groups = Object.entries(models.options || {}).map(([name, g]) => ({ name, ...g }));
    for (const p of [...models.params, ...models.geometry]) params.set(p.name, p);
    for (const g of groups) for (const c of g.choices) for (const p of c.params || []) {
      if (!params.has(p.name)) params.set(p.name, p);
    }
    defaultState = defaultsFromModels();
    if (models.version) $("#version").textContent = `v${models.version}`;

    buildControls();
    const { s, notes } = stateFromSearch(location.search);
    Object.assign(state, s);
    showNotices(notes);
    syncAllControls();
    $("#boot-status").hidden = true;
    for (const p of panels) resizeObserver.observe(p.div);
    booting = false;
    onStateChange();
  }

  // ------------------------------------------------------------- chrome ------
  $("#notice-close").addEventListener("click", () => { $("#notice").hidden = true; });
  $("#reset").addEventListener("click", () => {
    if (!models) return;
    Object.assign(state, structuredClone(defaultState));
    showNotices([]);
    syncAllControls();
    onStateChange();
  });
  $("#copy-link").addEventListener("click", async () => {
    const btn = $("#copy-link");
    try {
      await navigator.clipboard.writeText(location.href);
      btn.textContent = "Copied ✓";
    } catch {
      showNotices([`Link to this state: ${location.href}`]);
      btn.textContent = "Link below";
    }
    setTimeout(() => { btn.textContent = "Copy link"; }, 1500);
  });

  // Debug/test hook: the state, the number of panels fetching or about to.
  window.__brdf = {
    get state() { return state; },
    get models() { return models; },
    pending: () => (booting ? 1 : 0) + (urlTimer ? 1 : 0)
      + panels.filter((p) => p.inflight || p.dirty).length,
    panels: () => panels.map((p) => ({ name: p.spec.name, inflight: p.inflight, dirty: p.dirty,
                                       drawn: p.drawn, error: p.error, visible: isVisible(p) })),
    url: (name) => { const p = panels.find((x) => x.spec.name === name); return p && panelUrl(p); },
  };

  boot();
})();
