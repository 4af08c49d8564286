/* One slider builder and one slider mapping, for the explorer and the embeds.
 *
 * A parameter (GET /api/v1/models: name, label, lo, hi, lo_open, default, scale, unit)
 * gets a number box and a range input. Log-scale parameters (α) map the slider
 * piecewise-linearly in log(value), with most of the travel on the range people use;
 * linear ones step in round decimals.
 */
import { el, richText, setIf } from "../base/dom.js";

const LOG_TICKS = 1000;            // resolution of a log-scale slider
const INVALID_DELAY_MS = 450;      // typing "0." on the way to "0.05" is not an error yet
// Presentation hint (ranges and scales come from the API): the part of a log-scale
// parameter's range that gets most of its slider's travel.
const SLIDER_FOCUS = { alpha: [0.01, 0.3, 0.65], alpha_y: [0.01, 0.3, 0.65] };

export const inRange = (p, x) => (p.lo_open ? x > p.lo : x >= p.lo) && x <= p.hi;
export const rangeText = (p) => `${p.lo_open ? "(" : "["}${p.lo}, ${p.hi}]`;

function linearStep(p) {
  const span = p.hi - p.lo;
  return span > 0 ? 10 ** Math.floor(Math.log10(span / 100)) : 1;
}
const decimalsOf = (step) => Math.max(0, -Math.floor(Math.log10(step) + 1e-9));

/** Lowest value a slider reaches (an open or zero lower end of a log scale needs one). */
export function sliderLo(p) {
  if (p.scale === "log") return p.lo > 0 ? p.lo : p.hi * 1e-4;
  return p.lo_open ? p.lo + linearStep(p) : p.lo;
}

export function clampParam(p, x) {
  if (x > p.hi) return p.hi;
  if (p.lo_open ? x <= p.lo : x < p.lo) return p.lo_open ? sliderLo(p) : p.lo;
  return x;
}

function logMap(p) {
  const u0 = Math.log(sliderLo(p)), u3 = Math.log(p.hi);
  let knots = [[0, u0], [1, u3]];
  const f = SLIDER_FOCUS[p.name];
  if (f) {
    const u1 = Math.log(f[0]), u2 = Math.log(f[1]);
    if (u0 < u1 && u1 < u2 && u2 < u3) {
      const t1 = (1 - f[2]) * (u1 - u0) / ((u1 - u0) + (u3 - u2));
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
  const toSlider = (v) => Math.round(LOG_TICKS * interp(Math.log(Math.max(v, sliderLo(p))), 1, 0));
  const fromSlider = (x) => {
    if (Number(x) <= 0) return sliderLo(p);
    if (Number(x) >= LOG_TICKS) return p.hi;
    return clampParam(p, Number(Math.exp(interp(Number(x) / LOG_TICKS, 0, 1)).toPrecision(3)));
  };
  return {
    min: 0, max: LOG_TICKS, step: 1, toSlider, fromSlider,
    nudge: (v, dir, big) => fromSlider(Math.min(LOG_TICKS, Math.max(0, toSlider(v) + dir * (big ? 50 : 5)))),
  };
}

function linearMap(p) {
  const step = linearStep(p), dec = decimalsOf(step);
  const snap = (x) => clampParam(p, Number((Math.round((x - p.lo) / step) * step + p.lo).toFixed(dec)));
  return {
    min: p.lo, max: p.hi, step, toSlider: (v) => v, fromSlider: (x) => snap(Number(x)),
    nudge: (v, dir, big) => snap(v + dir * step * (big ? 10 : 1)),
  };
}

/** The slider mapping of a parameter: value <-> slider position, and arrow-key steps. */
export const sliderMap = (p) => (p.scale === "log" ? logMap(p) : linearMap(p));

const SUPERSCRIPT = { "-": "⁻", 0: "⁰", 1: "¹", 2: "²", 3: "³", 4: "⁴", 5: "⁵", 6: "⁶", 7: "⁷", 8: "⁸", 9: "⁹" };
function fmtEnd(v, p) {
  if (p.scale === "log" && v > 0 && v < 0.01) {
    return `10${String(Math.round(Math.log10(v))).split("").map((ch) => SUPERSCRIPT[ch] ?? ch).join("")}`;
  }
  return `${v}${p.unit || ""}`;
}

/* A number box and a slider for parameter p.
 *   id: the box's element id (the slider's is `${id}-slider`)
 *   onValue(x, source): a valid value was entered ("slider" | "box" | "key")
 *   onHold(held): the slider is held (pointer down) or let go
 *   compact: one line (the embeds), without the range ends
 * Returns {row, box, slider, map, set(x)}: set shows x without calling onValue.
 */
export function paramControl(p, { id, onValue, onHold = () => {}, compact = false }) {
  const map = sliderMap(p);
  const box = el("input", { type: "number", id, name: p.name, min: p.lo, max: p.hi, step: "any",
                            inputmode: "decimal", "aria-describedby": `${id}-msg` });
  const slider = el("input", { type: "range", id: `${id}-slider`, min: map.min, max: map.max, step: map.step });
  const msg = el("div", { class: "param-msg", id: `${id}-msg`, hidden: true });
  const label = el("label", { for: id, title: p.description || "" }, richText(p.label));
  const sliderLabel = el("label", { for: `${id}-slider`, class: "sr-only",
                                    text: `${p.label} slider${p.scale === "log" ? " (log scale)" : ""}` });
  const unit = p.unit ? el("span", { class: "unit", text: p.unit }) : null;
  // the box in a block of its own (style.css .field): its text, rewritten at every move
  // of the slider, then lays out the box alone, not the page; so the slider in the
  // embeds' one-line row (a flex row, whose items lay out with it)
  const field = el("span", { class: "field" }, box);
  const row = compact
    ? el("div", { class: "embed-param", "data-param": p.name }, label, sliderLabel,
         el("span", { class: "field" }, slider), el("span", { class: "box" }, field, unit), msg)
    : el("div", { class: "param", "data-param": p.name },
        el("div", { class: "param-head" }, label, el("span", { class: "box" }, field, unit)),
        sliderLabel, slider,
        el("div", { class: "range-ends", "aria-hidden": "true" },
          el("span", { text: fmtEnd(p.scale === "log" ? sliderLo(p) : p.lo, p) }),
          el("span", { text: fmtEnd(p.hi, p) })),
        msg);
  let value = p.default, invalidTimer = 0;
  const clearInvalid = () => {
    clearTimeout(invalidTimer);
    box.removeAttribute("aria-invalid");
    setIf(msg, "hidden", true);
  };
  const showInvalid = (text) => {
    clearTimeout(invalidTimer);
    invalidTimer = setTimeout(() => {
      box.setAttribute("aria-invalid", "true");
      msg.textContent = text;
      msg.hidden = false;
    }, INVALID_DELAY_MS);
  };
  const set = (x, source) => {
    value = x;
    clearInvalid();
    if (source !== "box") box.value = String(x);
    if (source !== "slider") slider.value = map.toSlider(x);
  };
  const emit = (x, source) => { set(x, source); onValue(x, source); };

  slider.addEventListener("input", () => emit(map.fromSlider(slider.value), "slider"));
  slider.addEventListener("pointerdown", () => onHold(true));
  // "change" ends a drag (and every keyboard step); pointerup alone misses a release
  // outside the window
  for (const ev of ["change", "pointerup", "pointercancel"]) slider.addEventListener(ev, () => onHold(false));
  box.addEventListener("input", () => {
    const raw = box.value.trim();
    const x = raw === "" ? NaN : Number(raw);
    if (!Number.isFinite(x)) return showInvalid("Enter a number.");
    if (!inRange(p, x)) return showInvalid(`Must be in ${rangeText(p)}.`);
    emit(x, "box");
  });
  box.addEventListener("change", () => set(value));   // leaving an invalid box restores the value
  box.addEventListener("keydown", (ev) => {
    if (ev.key !== "ArrowUp" && ev.key !== "ArrowDown") return;
    ev.preventDefault();
    emit(map.nudge(value, ev.key === "ArrowUp" ? 1 : -1, ev.shiftKey), "key");
  });
  return { row, box, slider, map, set };
}
