/* BRDF Lobe Explorer: the page.
 *
 * Everything the page shows follows from one object, `state`:
 *   controls --(input events)--> state --> URL (history.replaceState)
 *                                     \--> panels (one fetch in flight per panel)
 * The controls themselves are built from GET /api/v1/models: menus from the option
 * choices, number boxes and sliders from the Params (range, default, label, scale).
 * The panels are built from GET /api/v1/views: one per view the API has (a view added
 * there gets a panel, its toggles and its exports with no change here); a panel that
 * is hidden is never fetched.
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
  const TRUE_WORDS = new Set(["1", "true", "yes", "on"]);

  // Presentation hints per view; everything else about a panel comes from the API.
  //   shown: visible by default; primary: drawn first (the one a slider is watched on);
  //   slice: its phi_deg follows the plane of incidence when anisotropic;
  //   keys: the URL names of its own toggles where they predate generic panels.
  const PANEL_HINTS = {
    lobe: { title: "BRDF lobe", sub: "in the plane of incidence", primary: true, shown: true,
            keys: { log: "log", cosine: "cosine" }, labels: { cosine: "× cos θ_i" } },
    ndf: { title: "Normal distribution", sub: "D(θ_m)", shown: true, slice: true,
           labels: { cosine: "× cos θ_m" } },
    g1: { title: "Smith masking", sub: "Λ and G_1", shown: true, slice: true },
    albedo: { title: "Directional albedo", sub: "E(μ)", shown: true, slice: true },
    lobe3d: { title: "3-D lobe", sub: "f over the hemisphere of v", wide: true },
    g2: { title: "Masking-shadowing", sub: "G_2(θ_l, θ_v)" },
    fresnel: { title: "Fresnel", sub: "F(θ_d)" },
    sphere: { title: "Lit sphere", sub: "f·cos θ_l under one light (θ_i, φ_i)" },
    slice: { title: "θ_h / θ_d slice", sub: "the Disney explorer's image", labels: { cosine: "× cos θ_l" } },
    samples: { title: "Importance sampling", sub: "directions drawn for v" },
  };
  const PANEL_ORDER = ["lobe", "ndf", "g1", "albedo"];   // first; then the API's order
  const FIELD_LABELS = { log: "log scale", cosine: "× cos θ", display: "display",
                         exposure: "exposure (stops)" };
  // Fields that set resolution or accuracy: the page leaves them at the API's defaults.
  const SKIP_FIELDS = new Set(["n", "n_theta", "n_phi", "mu", "tol"]);

  // D, Λ/G1 and E(μ) are taken at one azimuth: that of the plane of incidence when
  // anisotropic; for an isotropic surface every azimuth is the same (API default).
  function sliceAzimuth(s) {
    return isAnisotropic(s) ? { phi_deg: s.phi_i_deg } : {};
  }

  // A panel's own field (a toggle, a menu, a number in its header): state key and id.
  // "view.field" cannot collide with a model parameter (no dots in those).
  const localKey = (view, field) => (PANEL_HINTS[view]?.keys || {})[field] || `${view}.${field}`;
  const localId = (view, field) => (PANEL_HINTS[view]?.keys || {})[field] || `${view}-${field.replace(/_/g, "-")}`;

  // ------------------------------------------------------------------ state ------
  const state = {};                 // THE single source of truth
  let defaultState = {};
  let models = null;
  const params = new Map();         // name -> Param (model, geometry and choice params)
  let views = [];                   // GET /api/v1/views, in panel order
  const locals = new Map();         // state key -> {view, field, input} of panel fields
  const controls = new Map();       // name -> {param, box, slider, row, msg, map}
  let groups = [];                  // [{name, label, default, choices}]
  let booting = true;
  const embed = new URLSearchParams(location.search).get("embed") === "1";

  const $ = (sel, root = document) => root.querySelector(sel);
  const { el, richText, apiMessage } = window.BRDF;

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
    return !!s.anisotropic && anisoAllowed(s) && !isPerceptual(s);
  }

  // The other way to give the roughness (when the API has it): perceptual r with
  // α = r² and an anisotropy k, instead of α_x, α_y; the API takes one form or the
  // other, never both. Its presence in the URL (?roughness=) selects it.
  const PERCEPTUAL = { params: ["roughness", "anisotropy"], replaces: ["alpha", "alpha_y"] };
  const perceptualAllowed = () => params.has("roughness");
  const isPerceptual = (s) => !!s.perceptual && perceptualAllowed();

  function appliesTo(choice, ndf) {
    return !choice.applies_to || choice.applies_to.includes(ndf);
  }

  // The continuous parameters that belong in a query for state s, in a fixed order.
  function activeParams(s) {
    const out = [];
    for (const p of models.params) {
      if (p.name === "alpha_y" && !isAnisotropic(s)) continue;
      if (PERCEPTUAL.params.includes(p.name) && !isPerceptual(s)) continue;
      if (PERCEPTUAL.replaces.includes(p.name) && isPerceptual(s)) continue;
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
      if (p.name === "alpha_y" || p.name === "roughness" || s[p.name] !== p.default) {
        q.set(p.name, String(s[p.name]));
      }
    }
    for (const [key, loc] of locals) {
      if (s[key] !== loc.field.default) q.set(key, String(s[key]));
    }
    const shown = views.filter((v) => s.show.includes(v.name)).map((v) => v.name);
    if (shown.join(",") !== defaultState.show.join(",")) q.set("show", shown.join(",") || "none");
    if (s.vary) {
      q.set("vary", s.vary);
      q.set("values", s.values);
    }
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
    s.perceptual = perceptualAllowed() && q.has("roughness");
    for (const [key, loc] of locals) {
      const raw = q.get(key);
      if (raw === null) continue;
      const f = loc.field;
      if (f.type === "boolean") s[key] = TRUE_WORDS.has(raw.toLowerCase());
      else if (f.enum) {
        if (f.enum.includes(raw)) s[key] = raw;
        else notes.push(`${key}=${raw} is not one of ${f.enum.join(", ")}; using ${f.default}.`);
      } else {
        const x = Number(raw);
        if (raw.trim() !== "" && Number.isFinite(x) && x >= f.minimum && x <= f.maximum) s[key] = x;
        else notes.push(`${key}=${raw} is not a number in [${f.minimum}, ${f.maximum}]; using ${f.default}.`);
      }
    }
    if (q.has("show")) {
      const names = q.get("show").split(",").map((x) => x.trim()).filter(Boolean);
      const unknown = names.filter((n) => n !== "none" && !views.some((v) => v.name === n));
      if (unknown.length) notes.push(`show=${unknown.join(",")}: no such panel.`);
      s.show = views.map((v) => v.name).filter((n) => names.includes(n));
    }
    if (TRUE_WORDS.has((q.get("lobe3d") || "").toLowerCase()) && !s.show.includes("lobe3d")) {
      s.show = views.map((v) => v.name).filter((n) => n === "lobe3d" || s.show.includes(n));
    }
    if (q.get("vary") && q.get("values")) {
      s.vary = q.get("vary");
      s.values = q.get("values");
    }
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
      if (p.name === "roughness") {
        surface.push(el("label", { class: "toggle aniso", for: "perceptual",
                                   title: "Give the roughness as perceptual r (α = r², Burley 2012) and an anisotropy k" },
          el("input", { type: "checkbox", id: "perceptual", name: "perceptual" }),
          el("span", {}, richText("perceptual roughness r (α = r²)"))));
      }
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
    const list = el("div", { class: "panel-list" });
    for (const v of views) {
      const h = PANEL_HINTS[v.name] || {};
      list.append(el("label", { class: "toggle", for: `show-${v.name}`, title: v.summary },
        el("input", { type: "checkbox", id: `show-${v.name}`, name: `show-${v.name}` }),
        el("span", {}, richText(h.title ? `${h.title}${h.sub ? ` — ${h.sub}` : ""}` : v.summary))));
    }
    form.append(section("Panels", list));

    const perceptual = $("#perceptual");
    if (perceptual) {
      perceptual.addEventListener("change", () => {
        state.perceptual = perceptual.checked;
        // start from the same α, so nothing jumps
        const r = params.get("roughness");
        if (perceptual.checked) state.roughness = Math.min(r.hi, Math.max(r.lo, Number(Math.sqrt(state.alpha).toPrecision(3))));
        else state.alpha = Number((state.roughness ** 2).toPrecision(3));
        syncAllControls();
        onStateChange();
      });
    }
    const aniso = $("#anisotropic");
    if (aniso) {
      aniso.addEventListener("change", () => {
        state.anisotropic = aniso.checked;
        if (aniso.checked) state.alpha_y = state.alpha;   // starts isotropic: nothing jumps
        syncAllControls();
        onStateChange();
      });
    }
    for (const v of views) {
      const box = document.getElementById(`show-${v.name}`);
      box.addEventListener("change", () => {
        state.show = views.map((x) => x.name).filter((n) =>
          n === v.name ? box.checked : state.show.includes(n));
        onStateChange();
        const section = document.querySelector(`.panel[data-panel="${v.name}"]`);
        if (section && box.checked) section.scrollIntoView({ behavior: "smooth", block: "nearest" });
      });
    }
    $("#compare-stop").addEventListener("click", () => {
      state.vary = null;
      state.values = null;
      for (const p of panels) p.noOverlay = false;
      syncAllControls();
      onStateChange();
    });
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
    const perceptual = $("#perceptual");
    if (perceptual) perceptual.checked = isPerceptual(state);
    const aniso = $("#anisotropic");
    if (aniso) {
      aniso.parentElement.hidden = isPerceptual(state);
      aniso.disabled = !anisoAllowed(state);
      aniso.checked = isAnisotropic(state);
      aniso.parentElement.title = aniso.disabled ? `${state.ndf} is isotropic only` : "";
    }
    for (const [key, loc] of locals) {
      if (loc.field.type === "boolean") loc.input.checked = !!state[key];
      else loc.input.value = String(state[key]);
    }
    for (const v of views) document.getElementById(`show-${v.name}`).checked = state.show.includes(v.name);
    const compare = $("#compare");
    compare.hidden = !state.vary;
    $("#compare-text").textContent = state.vary ? `Comparing ${state.vary} = ${state.values.split(",").join(", ")} (one curve each, where a panel can overlay curves).` : "";
  }

  // --------------------------------------------------------------- panels ------
  let panels = [];
  const panelsBox = $("#panels");

  // The view's fields a panel sets itself (toggles, menus, bounded numbers); the
  // geometry (θ_i, φ_i) and a slice azimuth come from the sidebar's state instead.
  function panelFields(view) {
    const geometry = new Set(models.geometry.map((p) => p.name));
    const hint = PANEL_HINTS[view.name] || {};
    return view.fields.filter((f) => !SKIP_FIELDS.has(f.name) && !geometry.has(f.name)
      && !(hint.slice && f.name === "phi_deg")
      && (f.type === "boolean" || f.enum || (f.type === "number" && Number.isFinite(f.minimum)
                                             && Number.isFinite(f.maximum))));
  }

  function fieldLabel(view, f) {
    const hint = PANEL_HINTS[view.name] || {};
    if (hint.labels && hint.labels[f.name]) return hint.labels[f.name];
    if (FIELD_LABELS[f.name]) return FIELD_LABELS[f.name];
    // phi_d_deg -> φ_d (°)
    return f.name.replace(/_deg$/, " (°)").replace(/^phi/, "φ").replace(/^theta/, "θ");
  }

  function localControl(view, f) {
    const key = localKey(view.name, f.name), id = localId(view.name, f.name);
    let input, label;
    if (f.type === "boolean") {
      input = el("input", { type: "checkbox", id });
      label = el("label", { class: "toggle", for: id, title: f.description },
                 input, el("span", {}, richText(fieldLabel(view, f))));
      input.addEventListener("change", () => { state[key] = input.checked; onStateChange(); });
    } else if (f.enum) {
      input = el("select", { id, class: "mini" });
      for (const x of f.enum) input.append(el("option", { value: x, text: x }));
      label = el("label", { class: "mini-field", for: id, title: f.description },
                 el("span", {}, richText(fieldLabel(view, f))), input);
      input.addEventListener("change", () => { state[key] = input.value; onStateChange(); });
    } else {
      input = el("input", { type: "number", id, class: "mini", min: f.minimum, max: f.maximum,
                            step: "any", inputmode: "decimal" });
      label = el("label", { class: "mini-field", for: id, title: f.description },
                 el("span", {}, richText(fieldLabel(view, f))), input);
      input.addEventListener("input", () => {
        const x = input.value.trim() === "" ? NaN : Number(input.value);
        const ok = Number.isFinite(x) && x >= f.minimum && x <= f.maximum;
        if (ok) input.removeAttribute("aria-invalid");
        else input.setAttribute("aria-invalid", "true");
        if (ok) { state[key] = x; onStateChange(); }
      });
      input.addEventListener("change", () => {
        input.value = String(state[key]);
        input.removeAttribute("aria-invalid");
      });
    }
    locals.set(key, { view: view.name, field: f, input });
    return label;
  }

  function buildPanels() {
    panelsBox.textContent = "";
    locals.clear();
    panels = views.map((view) => {
      const hint = PANEL_HINTS[view.name] || {};
      const hid = `h-${view.name}`;
      const heading = el("h2", { id: hid }, richText(hint.title || view.name));
      if (hint.sub) heading.append(" ", el("span", { class: "sub" }, richText(hint.sub)));
      const tools = el("div", { class: "panel-tools" }, ...panelFields(view).map((f) => localControl(view, f)));
      const status = el("div", { class: "panel-status", role: "status", "aria-live": "polite" });
      const div = el("div", { class: "plot", id: `plot-${view.name}` });
      const section = el("section", { class: `panel${hint.wide ? " panel-wide" : ""}`,
                                      "data-panel": view.name, "aria-labelledby": hid, hidden: true },
        el("header", { class: "panel-head" }, heading, el("div", { class: "panel-actions" }, tools)),
        el("div", { class: "plot-wrap" }, div, status));
      const panel = {
        view, name: view.name, hint, section, div, status, heading,
        inflight: false, dirty: false, noOverlay: false,
        doneKey: null, drawn: false, error: null, loadingTimer: 0,
      };
      const bar = window.BRDF.exportBar(
        () => ({ kind: view.name, params: compact(figureParams(panel, state)), div,
                 title: heading.textContent }),
        (kind, text) => exportReport(panel, kind, text));
      bar.classList.add("panel-export");
      section.querySelector(".panel-actions").append(bar);
      panelsBox.append(section);
      return panel;
    });
  }

  function exportReport(panel, kind, text) {
    if (kind === "busy") return setStatus(panel, "loading", text);
    if (panel.status.classList.contains("loading") && !panel.inflight) setStatus(panel, null);
    if (kind === "note" || kind === "error") showNotices([text]);
  }

  const isVisible = (panel) => state.show.includes(panel.name);

  // The parameters of a panel's figure: the model, the view's own fields, and the
  // comparison (vary, values) where this panel can overlay curves.
  function figureParams(panel, s) {
    const q = { ...modelQuery(s) };
    const geometry = new Set(models.geometry.map((p) => p.name));
    for (const f of panel.view.fields) {
      if (geometry.has(f.name)) q[f.name] = s[f.name];
    }
    if (panel.hint.slice) Object.assign(q, sliceAzimuth(s));
    for (const [key, loc] of locals) {
      if (loc.view === panel.name && s[key] !== loc.field.default) q[loc.field.name] = s[key];
    }
    if (overlaid(panel, s)) {
      q.vary = s.vary;
      q.values = s.values;
    }
    return q;
  }

  // A query without the values that are the API's defaults anyway (a shorter link or
  // embed code for the same figure); alpha_y and roughness stay: their presence matters.
  function compact(q) {
    const out = {};
    for (const [k, v] of Object.entries(q)) {
      const g = groups.find((x) => x.name === k);
      const p = params.get(k);
      if (k !== "alpha_y" && k !== "roughness" && ((g && v === g.default) || (p && v === p.default))) continue;
      out[k] = v;
    }
    return out;
  }

  const overlaid = (panel, s) => !!s.vary && !panel.noOverlay && panel.view.vary.includes(s.vary);

  function panelUrl(panel) {
    const q = window.BRDF.query(figureParams(panel, state));
    return `${API}/figures/${panel.name}${overlaid(panel, state) ? ".json" : ""}?${q}`;
  }

  // Plotly keeps zoom and camera while this stays the same: per panel and per toggle.
  function uirevision(panel) {
    const own = [...locals].filter(([, l]) => l.view === panel.name && l.field.type === "boolean")
      .map(([k]) => `${k}:${state[k]}`);
    return [panel.name, ...own, overlaid(panel, state) ? state.vary : ""].join("|");
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
      if (!panel.hint.primary) await primaryDrawn();
      url = panelUrl(panel);
      if (url === panel.doneKey) return;
      const uirev = uirevision(panel);
      let res;
      try {
        res = await fetch(url, { headers: { Accept: "application/json" } });
      } catch (e) {
        throw new Error("Cannot reach the server.");
      }
      const body = await res.json().catch(() => null);
      if (res.status === 422 && overlaid(panel, state) && window.BRDF.errorLoc(body).includes("vary")) {
        // This figure (an image, a surface) cannot overlay curves: draw it plain.
        panel.noOverlay = true;
        panel.dirty = true;
        url = null;
        return;
      }
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
      if (panel.hint.primary) releaseWaiters();
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
    return window.BRDF.fitLayout(layout);
  }

  // The lobe is what a slider is watched on: when its request is in flight, the other
  // panels hold their (main-thread) drawing until it has drawn, for at most a moment.
  let waiters = [];
  function primaryDrawn() {
    const primary = panels.find((p) => p.hint.primary);
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
    s.perceptual = false;
    for (const [key, loc] of locals) s[key] = loc.field.default;
    s.show = views.map((v) => v.name).filter((n) => PANEL_HINTS[n] && PANEL_HINTS[n].shown);
    s.vary = null;
    s.values = null;
    return s;
  }

  async function boot() {
    try {
      const get = async (path) => {
        const res = await fetch(`${API}${path}`, { headers: { Accept: "application/json" } });
        const body = await res.json().catch(() => null);
        if (!res.ok || !body) throw new Error(apiMessage(body, res));
        return body;
      };
      let viewList;
      [models, viewList] = await Promise.all([get("/models"), get("/views")]);
      const rank = (v) => (PANEL_ORDER.includes(v.name) ? PANEL_ORDER.indexOf(v.name) : PANEL_ORDER.length);
      views = viewList.map((v, i) => ({ ...v, i })).sort((a, b) => rank(a) - rank(b) || a.i - b.i);
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
    buildPanels();
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
    if (await window.BRDF.copyText(location.href)) {
      window.BRDF.flash(btn, "Copied ✓");
    } else {
      showNotices([`Link to this state: ${location.href}`]);
      window.BRDF.flash(btn, "Link below");
    }
  });

  // Debug/test hook: the state, the number of panels fetching or about to.
  window.__brdf = {
    get state() { return state; },
    get models() { return models; },
    pending: () => (booting ? 1 : 0) + (urlTimer ? 1 : 0)
      + panels.filter((p) => p.inflight || p.dirty).length,
    panels: () => panels.map((p) => ({ name: p.name, inflight: p.inflight, dirty: p.dirty,
                                       drawn: p.drawn, error: p.error, visible: isVisible(p) })),
    url: (name) => { const p = panels.find((x) => x.name === name); return p && panelUrl(p); },
  };

  boot();
})();
