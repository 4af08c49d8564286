/* An axis of a chart: a value range mapped onto a pixel span, linear or log, and its
 * ticks with their labels. A log axis's range is given in decades (log10 of the values),
 * as Plotly's figures give it; `dtick` follows Plotly's meaning: a number (the step, in
 * decades on a log axis) or "D1"/"D2" (every digit / the 2s and 5s between decades).
 */

const SUPERSCRIPT = { "-": "⁻", 0: "⁰", 1: "¹", 2: "²", 3: "³", 4: "⁴", 5: "⁵", 6: "⁶", 7: "⁷", 8: "⁸", 9: "⁹" };
const MINUS = "−";

/** 10ⁿ as a label: "1" and "10" plain, the rest with a superscript power. */
export function powerOfTen(n) {
  if (n === 0) return "1";
  if (n === 1) return "10";
  return `10${String(n).replace(/./g, (c) => SUPERSCRIPT[c] ?? c)}`;
}

/** A tick value as a label, with as many decimals as `step` needs; very small or large
 * values as a × 10ⁿ (Plotly's exponentformat "power"). */
export function tickLabel(v, step) {
  if (v === 0) return "0";
  const a = Math.abs(v);
  if (a < 1e-3 || a >= 1e5) {
    const n = Math.floor(Math.log10(a) + 1e-9);
    const m = v / 10 ** n;
    const digits = Math.max(0, Math.min(3, -Math.floor(Math.log10(Math.abs(step / 10 ** n)) + 1e-9)));
    const mant = m.toFixed(digits).replace(/\.?0+$/, "");
    return `${mant === "1" ? "" : mant === "-1" ? MINUS : `${mant.replace("-", MINUS)}×`}${powerOfTen(n)}`;
  }
  const decimals = Math.max(0, Math.min(12, -Math.floor(Math.log10(step) + 1e-9)));
  return v.toFixed(decimals).replace("-", MINUS);
}

/** A step of 1, 2 or 5 × 10ⁿ giving about `count` intervals over `span`. */
export function niceStep(span, count) {
  const raw = span / Math.max(1, count);
  const p = 10 ** Math.floor(Math.log10(raw));
  const f = raw / p;
  return (f < 1.5 ? 1 : f < 3 ? 2 : f < 7 ? 5 : 10) * p;
}

// a tick at the end of a range within this fraction of a step of it is on the axis
// (the range's ends are computed values: 90 may arrive as 89.99999999999999)
const END_SLACK = 1e-9;
// A given step is kept down to labels this fraction of the spacing apart (a figure's
// 15° steps on a narrow plot); below it the step doubles.
const GIVEN_STEP_CROWDING = 0.6;
// The 2 and 5 between decades are labelled when the gaps they leave (log 5 − log 2 ≈ 0.40
// and 1 − log 5 ≈ 0.30 of a decade) are this fraction of the spacing wide: labels narrower
// than a decade's ("2" against "10⁻²") may sit a little closer.
const DIGIT_GAP = { twoToFive: 0.9, fiveToTen: 0.7 };

export class Scale {
  /** axis: {type, range: [lo, hi] (decades on a log axis), dtick, nticks}; span: [p0, p1]
   * pixels (p1 < p0 for a y axis: up the screen). */
  constructor(axis, span) {
    this.log = axis.type === "log";
    [this.lo, this.hi] = axis.range;
    [this.p0, this.p1] = span;
    this.dtick = axis.dtick;
    this.nticks = axis.nticks;
    this.k = (this.p1 - this.p0) / (this.hi - this.lo || 1);
  }

  /** The pixel of a value (NaN for a value a log axis cannot show). */
  px(v) {
    const u = this.log ? (v > 0 ? Math.log10(v) : NaN) : v;
    return this.p0 + (u - this.lo) * this.k;
  }

  /** The value at a pixel. */
  value(p) {
    const u = this.lo + (p - this.p0) / this.k;
    return this.log ? 10 ** u : u;
  }

  /** [{v, label, minor}] in the range: the labelled ticks for an axis `pixels` long. */
  ticks(pixels, spacing) {
    return this.log ? this.logTicks(pixels, spacing) : this.linearTicks(pixels, spacing);
  }

  linearTicks(pixels, spacing) {
    const span = this.hi - this.lo;
    if (!(span > 0)) return [];
    const count = this.nticks ? Math.min(this.nticks, pixels / spacing) : pixels / spacing;
    let step = typeof this.dtick === "number" && this.dtick > 0 ? this.dtick : niceStep(span, count);
    while (span / step > Math.max(2, pixels / (spacing * GIVEN_STEP_CROWDING))) step *= 2;
    const out = [];
    const slack = step * END_SLACK;
    for (let k = Math.ceil((this.lo - slack) / step); k * step <= this.hi + slack; k++) {
      const v = Math.abs(k * step) < slack ? 0 : k * step;
      out.push({ v, label: tickLabel(v, step) });
    }
    return out;
  }

  logTicks(pixels, spacing) {
    const span = this.hi - this.lo;
    if (!(span > 0)) return [];
    const perDecade = pixels / span;
    const out = [];
    // decades, every one or every n-th where they are crowded
    const every = typeof this.dtick === "number" && this.dtick >= 1 ? Math.round(this.dtick)
      : Math.max(1, Math.ceil(spacing / perDecade));
    for (let n = Math.ceil(this.lo - END_SLACK); n <= this.hi + END_SLACK; n++) {
      if (n % every === 0) out.push({ v: 10 ** n, label: powerOfTen(n) });
    }
    // the digits between decades where there is room ("D2": 2 and 5; "D1": every one)
    const digits = this.dtick === "D1" ? [2, 3, 4, 5, 6, 7, 8, 9] : [2, 5];
    if (every === 1 && (this.dtick === "D1" || this.dtick === "D2" || this.dtick === undefined)
        && perDecade * (Math.log10(5) - Math.log10(2)) > spacing * DIGIT_GAP.twoToFive
        && perDecade * (1 - Math.log10(5)) > spacing * DIGIT_GAP.fiveToTen) {
      for (let n = Math.floor(this.lo) - 1; n <= Math.ceil(this.hi); n++) {
        for (const d of digits) {
          const u = n + Math.log10(d);
          if (u >= this.lo - END_SLACK && u <= this.hi + END_SLACK) out.push({ v: d * 10 ** n, label: String(d), minor: true });
        }
      }
      out.sort((a, b) => a.v - b.v);
    }
    return out;
  }
}
