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
  //   keys: the URL names of its own toggles where they predate generic panels;
  //   fields: its own fields to show although SKIP_FIELDS hides them elsewhere (advise's tol);
  //   short: a wide panel one row high (a table of a few rows: two rows left half of it blank);
  //   pin: its figure is made of curves, so POST /figures/{name} can overlay pinned
  //        models (image and surface figures answer 422 there); tails: "compare tails".
  const PANEL_HINTS = {
    lobe: { title: "BRDF lobe", sub: "in the plane of incidence", primary: true, shown: true, pin: true,
            keys: { log: "log", cosine: "cosine" }, labels: { cosine: "× cos θ_i" } },
    ndf: { title: "Normal distribution", sub: "D(θ_m)", shown: true, slice: true, pin: true, tails: true,
           labels: { cosine: "× cos θ_m" } },
    g1: { title: "Smith masking", sub: "Λ and G_1", shown: true, slice: true, pin: true },
    albedo: { title: "Directional albedo", sub: "E(μ)", shown: true, slice: true, pin: true,
              fields: ["tol"] },
    lobe3d: { title: "3-D lobe", sub: "f over the hemisphere of v", wide: true },
    g2: { title: "Masking-shadowing", sub: "G_2(θ_l, θ_v)" },
    fresnel: { title: "Fresnel", sub: "F(θ_d)", pin: true },
    sphere: { title: "Lit sphere", sub: "f·cos θ_l under one light (θ_i, φ_i)" },
    slice: { title: "θ_h / θ_d slice", sub: "the Disney explorer's image", labels: { cosine: "× cos θ_l" } },
    samples: { title: "Importance sampling", sub: "directions drawn for v" },
    checks: { title: "Checks", sub: "identities computed next to the values they must have", wide: true,
              short: true },
    tradeoff: { title: "Speed vs accuracy", sub: "albedo error against cost, per method", wide: true },
    advise: { title: "Model only what the scene needs", sub: "cheaper choices, their error and cost", wide: true,
              short: true, fields: ["tol"] },
  };
  const PANEL_ORDER = ["lobe", "ndf", "g1", "albedo"];   // first; then the API's order
  const FIELD_LABELS = { log: "log scale", cosine: "× cos θ", display: "display",
                         exposure: "exposure (stops)" };
  // Fields that set resolution or accuracy: the page leaves them at the API's defaults.
  const SKIP_FIELDS = new Set(["n", "n_theta", "n_phi", "mu", "tol", "order"]);

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

  // A parameter as the chosen choices define it: two choices may share a name with
  // different ranges and defaults (γ of GTR and of Student-t; η of a dielectric and
  // of a conductor). s may be a state or a query (both carry the choice names).
  function paramFor(name, s) {
    for (const g of groups) {
      const p = (choiceOf(g.name, s[g.name])?.params || []).find((x) => x.name === name);
      if (p) return p;
    }
    return params.get(name);
  }
  // The chosen choices' parameters at their own defaults.
  function choiceDefaults(s) {
    for (const g of groups) for (const p of choiceOf(g.name, s[g.name])?.params || []) s[p.name] = p.default;
  }
  const sameSpec = (a, b) => a.lo === b.lo && a.hi === b.hi && a.default === b.default && !!a.lo_open === !!b.lo_open;
  // Choose `name` in group g: a parameter the new choice shares with other choices
  // under another range or default starts at the new choice's default.
  function switchChoice(g, s, name) {
    const old = choiceOf(g.name, s[g.name]);
    s[g.name] = name;
    for (const p of choiceOf(g.name, name)?.params || []) {
      const prev = (old?.params || []).find((x) => x.name === p.name);
      const shared = g.choices.filter((c) => (c.params || []).some((x) => x.name === p.name)).length > 1;
      if (prev ? !sameSpec(prev, p) : (shared || !inRange(p, s[p.name]))) s[p.name] = p.default;
    }
  }

  // α_x ≠ α_y in either form (an option that is isotropic_only cannot take it).
  function anisoAlpha(s) {
    if (isAnisotropic(s)) return s.alpha_y !== s.alpha;
    return isPerceptual(s) && anisoAllowed(s) && s.anisotropy > 0;
  }

  // A choice applies to the NDF of s (applies_to) and, if isotropic_only, to its α.
  function appliesTo(choice, s) {
    if (choice.applies_to && !choice.applies_to.includes(s.ndf)) return false;
    return !(choice.isotropic_only && anisoAlpha(s));
  }
  function whyNot(choice, s) {
    if (choice.applies_to && !choice.applies_to.includes(s.ndf)) {
      return `only for ${choice.applies_to.join(", ")}`;
    }
    return "isotropic roughness only (α_y = α)";
  }

  // Sub-options (GET /models "sub_options") refine one choice; the API answers 422
  // when one is sent where it does not apply, so it is sent only where it does.
  //   lambda_phi: λ(φ) of a G2 whose choice says needs_phi;
  //   aniso_map: the (r, k) -> (α_x, α_y) map of the perceptual form.
  const subOptions = () => Object.entries(models.sub_options || {}).map(([name, g]) => ({ name, ...g }));
  function subApplies(name, s) {
    if (name === "lambda_phi") return !!choiceOf("g2", s.g2)?.needs_phi;
    if (name === "aniso_map") return isPerceptual(s) && anisoAllowed(s);
    return false;   // an unknown sub-option: its rule is not known here, so never sent
  }

  // The second lobe (alpha2 with weight lobe_mix) takes part only when switched on.
  const SECOND_LOBE = ["alpha2", "lobe_mix"];
  const SECOND_LOBE_START_MIX = 0.5;
  const secondLobeAllowed = () => SECOND_LOBE.every((n) => params.has(n));

  // The continuous parameters that belong in a query for state s, in a fixed order.
  function activeParams(s) {
    const out = [];
    for (const p of models.params) {
      if (p.name === "alpha_y" && !isAnisotropic(s)) continue;
      if (PERCEPTUAL.params.includes(p.name) && !isPerceptual(s)) continue;
      if (PERCEPTUAL.replaces.includes(p.name) && isPerceptual(s)) continue;
      if (p.name === "anisotropy" && !anisoAllowed(s)) continue;
      if (SECOND_LOBE.includes(p.name) && !s.secondLobe) continue;
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
    for (const g of subOptions()) if (subApplies(g.name, s)) q[g.name] = s[g.name];
    for (const p of activeParams(s)) q[p.name] = s[p.name];
    return q;
  }

  // Parameters whose presence in a query says something (anisotropic, perceptual form,
  // second lobe on): kept even at their default value.
  const PRESENCE = new Set(["alpha_y", "roughness", "alpha2"]);

  // State -> page URL: API names, only non-default values (alpha_y whenever
  // anisotropic: its presence is what says "anisotropic"), and one `pin` per pinned
  // model (see encodePin).
  function stateToSearch(s) {
    const q = new URLSearchParams();
    for (const g of groups) if (s[g.name] !== g.default) q.set(g.name, s[g.name]);
    for (const g of subOptions()) {
      if (subApplies(g.name, s) && s[g.name] !== g.default) q.set(g.name, s[g.name]);
    }
    for (const p of [...activeParams(s), ...models.geometry]) {
      if (PRESENCE.has(p.name) || s[p.name] !== p.default) {
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
    for (const pin of s.pins) q.append("pin", encodePin(pin));
    if (embed) q.set("embed", "1");
    // ':' and ',' may stand as they are in a query (RFC 3986 3.4): readable pins and lists
    const str = q.toString().replace(/%3A/gi, ":").replace(/%2C/gi, ",");
    return str ? `?${str}` : "";
  }

  // Page URL -> state. Values the API would reject are corrected (and said so), so a
  // hand-edited link always opens a working page.
  function stateFromSearch(search) {
    const q = new URLSearchParams(search);
    const s = structuredClone(defaultState);
    const notes = [];
    for (const g of [...groups, ...subOptions()]) {
      const v = q.get(g.name);
      if (v === null) continue;
      if (g.choices.some((c) => c.name === v)) s[g.name] = v;
      else notes.push(`${g.name}=${v} is not one of ${g.choices.map((c) => c.name).join(", ")}; using ${g.default}.`);
    }
    choiceDefaults(s);
    for (const name of params.keys()) {
      const p = paramFor(name, s);
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
    s.secondLobe = secondLobeAllowed() && q.has("alpha2");
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
    s.pins = [];
    for (const raw of q.getAll("pin")) {
      const { pin, note } = decodePin(raw);
      if (note) notes.push(note);
      if (pin && !s.pins.some((x) => samePin(x, pin)) && s.pins.length < MAX_PINS) s.pins.push(pin);
    }
    return { s, notes };
  }

  // ---------------------------------------------------------------- pins ------
  // A pinned model is kept as its non-default model parameters, the API's names and
  // values (a POST /figures/{kind} "models" entry as it stands). In the URL each pin
  // is one `pin` parameter, its entries name:value joined by commas, e.g.
  //   ?pin=ndf:beckmann,alpha:0.2&pin=ndf:blinn_phong,alpha:0.2
  // (names and choice values are [a-z0-9_], numbers are plain decimals, so neither
  // ':' nor ',' can occur inside one). A pin always names its ndf; the rest are the
  // values that differ from the API's defaults.
  const MAX_PINS = 6;                // a legend of 7 curves is still readable

  // The choices named in a raw pin (to check its numbers against their own ranges).
  function pinChoices(raw) {
    const out = {};
    for (const part of raw.split(",")) {
      const [k, v] = part.split(":");
      if (groups.some((g) => g.name === k)) out[k] = (v || "").trim();
    }
    return out;
  }

  function encodePin(pin) {
    const parts = Object.entries(pin).map(([k, v]) => `${k}:${v}`);
    return parts.join(",");
  }

  // The state a pin stands for: the defaults with the pin's values; the forms that
  // are chosen by presence (alpha_y, roughness, alpha2) follow from its keys.
  function pinState(pin) {
    const s = structuredClone(defaultState);
    for (const g of groups) if (pin[g.name]) s[g.name] = pin[g.name];
    choiceDefaults(s);
    Object.assign(s, pin);
    s.anisotropic = "alpha_y" in pin;
    s.perceptual = "roughness" in pin;
    s.secondLobe = "alpha2" in pin;
    s.pins = [];
    return s;
  }

  // The model of state s, without the values that are the API's defaults anyway.
  const modelOf = (s) => compact(modelQuery(s));
  // A pin names its NDF always (a link stays the same model if the default changes).
  const pinOf = (s) => ({ ndf: s.ndf, ...modelOf(s) });
  const samePin = (a, b) => encodePin(a) === encodePin(b);

  // One `pin` value -> {pin} or {note} saying why it was left out.
  function decodePin(raw) {
    const bad = (why) => ({ pin: null, note: `pin=${raw}: ${why}; left out.` });
    const pin = {};
    {
      for (const part of raw.split(",")) {
        const i = part.indexOf(":");
        if (i < 1) return bad(`“${part}” is not name:value`);
        const k = part.slice(0, i).trim(), v = part.slice(i + 1).trim();
        const g = [...groups, ...subOptions()].find((x) => x.name === k);
        const p = params.has(k) ? paramFor(k, pinChoices(raw)) : null;
        if (g) {
          if (!g.choices.some((c) => c.name === v)) return bad(`${k}=${v} is not one of ${g.choices.map((c) => c.name).join(", ")}`);
          pin[k] = v;
        } else if (p && !models.geometry.some((x) => x.name === k)) {
          const x = v === "" ? NaN : Number(v);
          if (!Number.isFinite(x) || !inRange(p, x)) return bad(`${k}=${v} is not a number in ${rangeText(p)}`);
          pin[k] = x;
        } else {
          return bad(`${k} is not a model parameter`);
        }
      }
    }
    const s = pinState(pin);
    const notes = fixApplicability(s);
    if (notes.length) return bad(notes[0]);
    // back to its canonical form: parameters that do not take part are dropped
    return { pin: pinOf(s), note: null };
  }

  // A short name for a pinned model: its NDF and roughness always, then what else
  // differs from the defaults.
  function pinLabel(pin) {
    const s = pinState(pin);
    const q = modelQuery(s);
    const parts = [q.ndf];
    if (isPerceptual(s)) parts.push(`r=${q.roughness}`);
    else parts.push(isAnisotropic(s) ? `α=${q.alpha}×${q.alpha_y}` : `α=${q.alpha}`);
    for (const [k, v] of Object.entries(pin)) {
      if (["ndf", "alpha", "alpha_y", "roughness"].includes(k)) continue;
      parts.push(groups.some((g) => g.name === k) ? String(v) : `${k}=${v}`);
    }
    return parts.join(", ");
  }

  // A masking or G2 (any choice with applies_to or isotropic_only) that does not apply
  // to the NDF or to anisotropic α is replaced by the group's default, or else the
  // first choice that applies.
  function fixApplicability(s) {
    const notes = [];
    for (const g of groups) {
      const c = choiceOf(g.name, s[g.name]);
      if (!c || appliesTo(c, s)) continue;
      const alt = [choiceOf(g.name, g.default), ...g.choices].find((x) => x && appliesTo(x, s));
      if (alt) {
        const what = c.applies_to && !c.applies_to.includes(s.ndf) ? `does not apply to ${s.ndf}`
          : "is for isotropic roughness only";
        notes.push(`${g.label} “${c.label}” ${what}; using “${alt.label}”.`);
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

  function paramControl(p, key = p.name) {
    const id = key === p.name ? controlId(p.name) : key;
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
    const c = { key, param: p, box, slider, row, msg, map, invalid: false, invalidTimer: 0 };

    slider.addEventListener("input", () => {
      setParam(c, map.fromSlider(slider.value), "slider");
    });
    box.addEventListener("input", () => {
      const raw = box.value.trim();
      const x = raw === "" ? NaN : Number(raw);
      if (!Number.isFinite(x)) return showInvalid(c, "Enter a number.");
      if (!inRange(p, x)) return showInvalid(c, `Must be in ${rangeText(p)}.`);
      setParam(c, x, "box");
    });
    box.addEventListener("change", () => {   // leaving an invalid box restores the value
      if (c.invalid) syncControl(c);
    });
    box.addEventListener("keydown", (ev) => {
      if (ev.key !== "ArrowUp" && ev.key !== "ArrowDown") return;
      ev.preventDefault();
      const dir = ev.key === "ArrowUp" ? 1 : -1;
      const next = map.nudge(state[p.name], dir, ev.shiftKey);
      setParam(c, p.scale === "log" ? map.fromSlider(next) : next, "key");
    });
    controls.set(key, c);
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
      switchChoice(g, state, sel.value);
      const notes = fixApplicability(state);
      if (notes.length) showNotices(notes);
      syncAllControls();
      onStateChange();
    });
    const info = el("p", { class: "choice-info", id: `${g.name}-info` });
    const paramsBox = el("div", { class: "choice-params" });
    // One control per parameter; a name that two choices define differently (γ, η)
    // gets one control per choice, each with its own range (id "<choice>-<name>").
    const allParams = groups.flatMap((x) => x.choices.flatMap((c) => c.params || []));
    for (const c of g.choices) {
      for (const p of c.params || []) {
        const differs = allParams.some((x) => x.name === p.name && !sameSpec(x, p));
        const key = differs ? `${c.name}-${p.name}` : p.name;
        if (controls.has(key)) continue;
        paramsBox.append(paramControl(p, key));
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
      if (p.name === "alpha2" && secondLobeAllowed()) {
        surface.push(el("label", { class: "toggle aniso", for: "second-lobe",
                                   title: "Add a second specular lobe of the same NDF: (1 − w) f(α) + w f(α₂) (Kulla & Conty 2017)" },
          el("input", { type: "checkbox", id: "second-lobe", name: "second-lobe" }),
          el("span", {}, richText("second lobe (α_2, weight w)"))));
      }
      surface.push(paramControl(p));
      if (p.name === "anisotropy" && models.sub_options?.aniso_map) {
        surface.push(subSelect({ name: "aniso_map", ...models.sub_options.aniso_map }));
      }
    }
    form.append(section("Surface", ...surface));
    form.append(section("Incidence", ...models.geometry.map((p) => paramControl(p))));
    if (others.length) form.append(section("Shadowing & Fresnel", ...others.map(choiceSelect)));
    const g2Box = form.querySelector('.choice[data-group="g2"] .choice-params');
    if (g2Box && models.sub_options?.lambda_phi) {
      g2Box.append(subSelect({ name: "lambda_phi", ...models.sub_options.lambda_phi }));
    }
    form.append(section("Compare (pinned models)",
      el("p", { class: "pin-help", id: "pin-help",
                text: "Pin keeps the current model as a curve on the D, G₁, lobe, albedo and Fresnel panels while the controls move on." }),
      el("ul", { class: "pin-list", id: "pin-list", "aria-label": "Pinned models" }),
      el("div", { class: "pin-actions" },
        el("button", { type: "button", id: "pin-current", class: "small-btn", text: "Pin current model" }),
        el("button", { type: "button", id: "pin-clear", class: "small-btn", text: "Clear pins" }))));
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
    const second = $("#second-lobe");
    if (second) {
      second.addEventListener("change", () => {
        state.secondLobe = second.checked;
        // a weight of 0 would show nothing: switching the lobe on gives it a share
        if (second.checked && state.lobe_mix === 0) state.lobe_mix = SECOND_LOBE_START_MIX;
        syncAllControls();
        onStateChange();
      });
    }
    $("#pin-current").addEventListener("click", pinCurrent);
    $("#pin-clear").addEventListener("click", () => setPins([]));
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

  // A menu for a sub-option (lambda_phi, aniso_map): shown only where it applies.
  function subSelect(g) {
    const sel = el("select", { id: g.name, name: g.name });
    for (const c of g.choices) sel.append(el("option", { value: c.name, text: c.label, title: c.description || "" }));
    sel.addEventListener("change", () => {
      state[g.name] = sel.value;
      syncAllControls();
      onStateChange();
    });
    return el("div", { class: "choice sub-choice", "data-sub": g.name, title: `applies with ${g.applies_with || "?"}` },
      el("label", { for: g.name, class: "choice-label" }, richText(g.label || g.name)),
      sel, el("p", { class: "choice-info", id: `${g.name}-info` }));
  }

  // ----------------------------------------------------------- pin actions ------
  function setPins(pins) {
    state.pins = pins.slice(0, MAX_PINS);
    syncAllControls();
    onStateChange();
  }
  function pinCurrent() {
    const m = pinOf(state);
    if (state.pins.some((x) => samePin(x, m))) return;
    if (state.pins.length >= MAX_PINS) {
      showNotices([`At most ${MAX_PINS} pinned models; remove one first.`]);
      return;
    }
    setPins([...state.pins, m]);
  }
  // GGX, Beckmann and Blinn-Phong at the current α (Blinn-Phong's α is its
  // Beckmann-equivalent), D(θ) on a log axis: the tails side by side in one click.
  const TAIL_NDFS = ["ggx", "beckmann", "blinn_phong"];
  function compareTails() {
    const alpha = isPerceptual(state) ? Number((state.roughness ** 2).toPrecision(3)) : state.alpha;
    const pins = TAIL_NDFS.filter((n) => choiceOf("ndf", n)).map((ndf) => {
      const s = structuredClone(state);
      s.ndf = ndf;
      choiceDefaults(s);
      Object.assign(s, { alpha, anisotropic: false, perceptual: false, pins: [] });
      fixApplicability(s);
      return pinOf(s);
    });
    const logKey = localKey("ndf", "log");
    if (locals.has(logKey)) state[logKey] = true;
    setPins(pins);
  }

  function setParam(c, value, source) {
    state[c.param.name] = value;
    clearInvalid(c);
    if (source !== "box") c.box.value = String(value);
    if (source !== "slider") c.slider.value = c.map.toSlider(value);
    onStateChange();
  }

  function syncControl(c) {
    c.box.value = String(state[c.param.name]);
    c.slider.value = c.map.toSlider(state[c.param.name]);
    clearInvalid(c);
  }

  // Only the parameters that take part (α_y when anisotropic, a choice's params when
  // that choice is selected) are shown and enabled.
  function syncActiveRows() {
    const active = new Set([...activeParams(state), ...models.geometry]);
    for (const c of controls.values()) {
      const on = active.has(c.param);
      c.row.hidden = !on;
      c.box.disabled = c.slider.disabled = !on;
    }
  }

  // Menus <- state: the selected choice, which choices apply, the choice's note.
  function syncChoices() {
    for (const g of groups) {
      const sel = document.getElementById(g.name);
      sel.value = state[g.name];
      for (const opt of sel.options) {
        const c = choiceOf(g.name, opt.value);
        opt.disabled = !appliesTo(c, state);
        opt.title = opt.disabled ? `Not available: ${whyNot(c, state)}` : (c.description || "");
      }
      const c = choiceOf(g.name, state[g.name]);
      const info = document.getElementById(`${g.name}-info`);
      if (info.dataset.choice === state[g.name]) continue;
      info.dataset.choice = state[g.name];
      info.textContent = "";
      if (c && c.description) info.append(el("span", {}, richText(c.description)));
      if (c && c.reference) info.append(el("span", { class: "ref", text: c.reference }));
      info.hidden = !info.textContent;
    }
  }

  // Controls <- state (after load, reset, or a change that moves other controls).
  function syncAllControls() {
    for (const c of controls.values()) syncControl(c);
    syncActiveRows();
    syncChoices();
    for (const g of subOptions()) {
      const sel = document.getElementById(g.name);
      if (!sel) continue;
      sel.value = state[g.name];
      sel.closest(".sub-choice").hidden = !subApplies(g.name, state);
      const info = document.getElementById(`${g.name}-info`);
      const c = g.choices.find((x) => x.name === state[g.name]);
      info.textContent = c?.description || "";
      info.hidden = !info.textContent;
    }
    const second = $("#second-lobe");
    if (second) second.checked = !!state.secondLobe;
    syncDerived();
    syncPinList();
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
    syncLocalVisibility();
    for (const v of views) document.getElementById(`show-${v.name}`).checked = state.show.includes(v.name);
    const compare = $("#compare");
    compare.hidden = !state.vary;
    $("#compare-text").textContent = state.vary ? `Comparing ${state.vary} = ${state.values.split(",").join(", ")} (one curve each, where a panel can overlay curves).` : "";
  }

  // Blinn-Phong's α is the Beckmann-equivalent α_b; its Phong exponent
  // α_p = 2/α_b² − 2 (Walter et al. 2007, eq. 33) is shown beside the roughness.
  const DERIVED = { blinn_phong: (alpha) => `α_p = 2/α² − 2 = ${fmtNum(2 / alpha ** 2 - 2)}` };
  function fmtNum(x) {
    return Math.abs(x) >= 1e4 ? x.toExponential(2).replace("e+", "e") : String(Number(x.toPrecision(4)));
  }
  function syncLocalVisibility() {
    for (const loc of locals.values()) loc.input.parentElement.hidden = !fieldApplies(loc.view, loc.field, state);
  }

  function syncDerived() {
    let out = $("#derived");
    if (!out) out = el("p", { class: "derived", id: "derived", "aria-live": "polite" });
    const f = DERIVED[state.ndf];
    const row = controls.get(isPerceptual(state) ? "roughness" : "alpha")?.row;
    if (!f || !row) { out.hidden = true; return; }
    const alpha = isPerceptual(state) ? state.roughness ** 2 : state.alpha;
    out.textContent = f(alpha);
    out.title = choiceOf("ndf", state.ndf)?.derived_doc?.alpha_p || "";
    out.hidden = false;
    if (out.parentElement !== row) row.append(out);
  }

  function syncPinList() {
    const list = $("#pin-list");
    if (!list) return;
    list.textContent = "";
    const current = pinOf(state);
    state.pins.forEach((pin, i) => {
      const label = pinLabel(pin);
      const rm = el("button", { type: "button", class: "pin-remove", "aria-label": `Remove pin ${label}`,
                                title: "Remove this pinned model", text: "×" });
      rm.addEventListener("click", () => setPins(state.pins.filter((_, j) => j !== i)));
      list.append(el("li", { class: samePin(pin, current) ? "pin is-current" : "pin", "data-pin": encodePin(pin) },
        el("span", { class: "pin-label", title: encodePin(pin) }, richText(label)), rm));
    });
    list.hidden = !state.pins.length;
    $("#pin-clear").disabled = !state.pins.length;
    $("#pin-current").disabled = state.pins.length >= MAX_PINS || state.pins.some((x) => samePin(x, current));
    for (const panel of panels) {
      if (panel.pinButton) panel.pinButton.disabled = $("#pin-current").disabled;
    }
  }

  // --------------------------------------------------------------- panels ------
  let panels = [];
  const panelsBox = $("#panels");

  // The view's fields a panel sets itself (toggles, menus, bounded numbers); the
  // geometry (θ_i, φ_i) and a slice azimuth come from the sidebar's state instead.
  function panelFields(view) {
    const geometry = new Set(models.geometry.map((p) => p.name));
    const hint = PANEL_HINTS[view.name] || {};
    const own = new Set(hint.fields || []);     // fields this panel shows although SKIP_FIELDS has them
    return view.fields.filter((f) => (own.has(f.name) || !SKIP_FIELDS.has(f.name)) && !geometry.has(f.name)
      && !(hint.slice && f.name === "phi_deg")
      && (f.type === "boolean" || f.enum || ((f.type === "number" || f.type === "integer")
                                             && Number.isFinite(f.minimum) && Number.isFinite(f.maximum))));
  }

  // A panel field that matters only for some values of another (the schema's
  // x-applies-to: samples and seed for the Monte Carlo methods) is hidden, and not sent,
  // elsewhere: the API refuses it there rather than ignore it.
  function fieldApplies(viewName, f, s) {
    return Object.entries(f.applies_to || {}).every(([other, allowed]) => {
      const key = localKey(viewName, other);
      const view = views.find((v) => v.name === viewName);
      const value = key in s ? s[key] : view?.fields.find((x) => x.name === other)?.default;
      return allowed.includes(value);
    });
  }

  function fieldLabel(view, f) {
    const hint = PANEL_HINTS[view.name] || {};
    if (hint.labels && hint.labels[f.name]) return hint.labels[f.name];
    if (FIELD_LABELS[f.name]) return FIELD_LABELS[f.name];
    // phi_d_deg -> φ_d (°)
    return f.name.replace(/_deg$/, " (°)").replace(/^phi/, "φ").replace(/^theta/, "θ").replace(/^alpha/, "α");
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
      const integer = f.type === "integer";
      input = el("input", { type: "number", id, class: "mini", min: f.minimum, max: f.maximum,
                            step: integer ? 1 : "any", inputmode: integer ? "numeric" : "decimal" });
      label = el("label", { class: "mini-field", for: id, title: f.description },
                 el("span", {}, richText(fieldLabel(view, f))), input);
      input.addEventListener("input", () => {
        const x = input.value.trim() === "" ? NaN : Number(input.value);
        const ok = Number.isFinite(x) && x >= f.minimum && x <= f.maximum && (!integer || Number.isInteger(x));
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
      const section = el("section", { class: `panel${hint.wide ? " panel-wide" : ""}${hint.short ? " panel-short" : ""}`,
                                      "data-panel": view.name, "aria-labelledby": hid, hidden: true },
        el("header", { class: "panel-head" }, heading, el("div", { class: "panel-actions" }, tools)),
        el("div", { class: "plot-wrap" }, div, status));
      const panel = {
        view, name: view.name, hint, section, div, status, heading,
        inflight: false, dirty: false, noOverlay: false, noPin: false, pinButton: null,
        doneKey: null, drawn: false, error: null, loadingTimer: 0,
      };
      const bar = window.BRDF.exportBar(
        () => ({ kind: view.name, params: compact(figureParams(panel, state)), div,
                 title: heading.textContent }),
        (kind, text) => exportReport(panel, kind, text));
      bar.classList.add("panel-export");
      const actions = section.querySelector(".panel-actions");
      if (hint.pin || hint.tails) {
        const pinBar = el("div", { class: "pin-bar", role: "group", "aria-label": "Compare models" });
        if (hint.pin) {
          panel.pinButton = el("button", { type: "button", class: "export pin-btn", "data-action": "pin",
                                           title: "Keep the current model as a curve (pinned models are drawn on every curve panel)",
                                           text: "Pin" });
          panel.pinButton.addEventListener("click", pinCurrent);
          pinBar.append(panel.pinButton);
        }
        if (hint.tails) {
          const tails = el("button", { type: "button", class: "export pin-btn", "data-action": "tails",
                                       title: "Pin GGX, Beckmann and Blinn-Phong at the current α and show D on a log scale",
                                       text: "Compare tails" });
          tails.addEventListener("click", compareTails);
          pinBar.append(tails);
        }
        // one unit with the export buttons: they wrap to a new line together
        actions.append(el("div", { class: "panel-buttons" }, pinBar, bar));
      } else {
        actions.append(bar);
      }
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
    return { ...modelQuery(s), ...viewParams(panel, s) };
  }
  // The parameters of a panel's figure that are not the model's (the "view" of a POST).
  function viewParams(panel, s) {
    const q = {};
    const geometry = new Set(models.geometry.map((p) => p.name));
    for (const f of panel.view.fields) {
      if (geometry.has(f.name)) q[f.name] = s[f.name];
    }
    if (panel.hint.slice) Object.assign(q, sliceAzimuth(s));
    for (const [key, loc] of locals) {
      if (loc.view === panel.name && s[key] !== loc.field.default && fieldApplies(panel.name, loc.field, s)) {
        q[loc.field.name] = s[key];
      }
    }
    if (overlaid(panel, s)) {
      q.vary = s.vary;
      q.values = s.values;
    }
    return q;
  }

  // A query without the values that are the API's defaults anyway (a shorter link or
  // embed code for the same figure); alpha_y, roughness, alpha2 stay: their presence matters.
  function compact(q) {
    const out = {};
    for (const [k, v] of Object.entries(q)) {
      const g = [...groups, ...subOptions()].find((x) => x.name === k);
      const p = paramFor(k, q);
      if (!PRESENCE.has(k) && ((g && v === g.default) || (p && v === p.default))) continue;
      out[k] = v;
    }
    return out;
  }

  const overlaid = (panel, s) => !!s.vary && !panel.noOverlay && panel.view.vary.includes(s.vary)
    && !pinned(panel, s);
  // Pinned models are drawn (instead of a vary comparison) on the panels that can.
  const pinned = (panel, s) => s.pins.length > 0 && !!panel.hint.pin && !panel.noPin;

  // POST /figures/{kind}: the pinned models and the current one (once, if it is also
  // pinned), labelled as in the pin list, the current one marked "now".
  function compareBody(panel, s) {
    const current = pinOf(s);
    const models_ = [...s.pins];
    const labels = s.pins.map((pin) => (samePin(pin, current) ? `${pinLabel(pin)} (now)` : pinLabel(pin)));
    if (!s.pins.some((pin) => samePin(pin, current))) {
      models_.push(current);
      labels.push(`now: ${pinLabel(current)}`);
    }
    return { models: models_, view: compact(viewParams(panel, s)), labels };
  }

  // The request behind a panel: {key, url, init}; key is what the panel last drew
  // (a GET's URL, or a POST's URL and body).
  function panelRequest(panel) {
    const accept = { Accept: "application/json" };
    if (pinned(panel, state)) {
      const url = `${API}/figures/${panel.name}`;
      const body = JSON.stringify(compareBody(panel, state));
      return { key: `POST ${url} ${body}`, url,
               init: { method: "POST", headers: { ...accept, "Content-Type": "application/json" }, body } };
    }
    const url = panelUrl(panel);
    return { key: url, url, init: { headers: accept } };
  }

  function panelUrl(panel) {
    const q = window.BRDF.query(figureParams(panel, state));
    return `${API}/figures/${panel.name}${overlaid(panel, state) ? ".json" : ""}?${q}`;
  }

  // Plotly keeps zoom and camera while this stays the same: per panel and per toggle.
  function uirevision(panel) {
    const own = [...locals].filter(([, l]) => l.view === panel.name && l.field.type === "boolean")
      .map(([k]) => `${k}:${state[k]}`);
    return [panel.name, ...own, overlaid(panel, state) ? state.vary : "",
            pinned(panel, state) ? "pins" : ""].join("|");
  }

  function schedule(panel) {
    panel.section.hidden = !isVisible(panel);
    if (!isVisible(panel)) return;
    if (panel.inflight) { panel.dirty = true; return; }
    if (panelRequest(panel).key === panel.doneKey) return;   // nothing this panel shows has changed
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
      const req = panelRequest(panel);
      url = req.key;
      if (url === panel.doneKey) return;
      const uirev = uirevision(panel);
      let res;
      try {
        res = await fetch(req.url, req.init);
      } catch (e) {
        throw new Error("Cannot reach the server.");
      }
      const body = await res.json().catch(() => null);
      if (res.status === 422 && req.init.method === "POST"
          && /cannot be compared/.test(apiMessage(body, res))) {
        // This figure cannot overlay models after all: draw the current one alone.
        panel.noPin = true;
        panel.dirty = true;
        url = null;
        return;
      }
      if (res.status === 422 && overlaid(panel, state) && window.BRDF.errorLoc(body).includes("vary")) {
        // This figure (an image, a surface) cannot overlay curves: draw it plain.
        panel.noOverlay = true;
        panel.dirty = true;
        url = null;
        return;
      }
      if (!res.ok) throw new Error(apiMessage(body, res));
      if (!body || !Array.isArray(body.data)) throw new Error("The server sent no figure.");
      if (req.init.method === "POST") compactLegend(body.data);
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

  // An overlay names its traces "<quantity> · <model>": with several quantities per
  // model (G1 and Λ; F, exact F and their difference) the legend would fill the panel.
  // The first model keeps one entry per quantity (they explain the line styles); each
  // other model gets one entry, its name, and one click shows or hides all its traces.
  const OVERLAY_SEP = " · ";
  function compactLegend(data) {
    let first = null;
    const named = new Set();
    for (const t of data) {
      const i = typeof t.name === "string" ? t.name.lastIndexOf(OVERLAY_SEP) : -1;
      if (i < 0) continue;
      const model = t.name.slice(i + OVERLAY_SEP.length);
      t.legendgroup = model;
      if (first === null) first = model;
      if (model === first) continue;
      if (named.has(model)) t.showlegend = false;
      else { named.add(model); t.name = model; }
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
    // α_y or the anisotropy can make an isotropic_only choice (Hammon's G2) stop applying
    const notes = fixApplicability(state);
    if (notes.length) showNotices(notes);
    syncChoices();
    syncDerived();
    syncLocalVisibility();
    syncPinList();
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
    for (const g of subOptions()) s[g.name] = g.default;
    choiceDefaults(s);
    s.anisotropic = false;
    s.perceptual = false;
    s.secondLobe = false;
    s.pins = [];
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
    request: (name) => { const p = panels.find((x) => x.name === name); return p && panelRequest(p); },
  };

  boot();
})();
