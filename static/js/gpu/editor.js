/* The .brdf editor: a plain textarea (the page's CSP and its no-vendoring rule leave out
 * editor libraries) whose text is compiled as the user types, debounced, with the line
 * numbers beside it and the lines an error names marked. It knows nothing of GLSL:
 * apply(text) (userbrdf.js) parses, compiles and draws, and keeps the last good BRDF
 * drawn when the text is broken; this module only shows what it answers.
 */
import { el } from "../base/dom.js";

/** Quiet time after the last keystroke before the text is compiled: a compile and the
 * one-pixel probe cost a few ms on a GPU, ~30 ms on a software one; at every keystroke
 * they would also flash an error for each half-typed word. */
export const DEBOUNCE_MS = 300;

/** What the editor holds before any file is opened: the format in a dozen lines. */
export const TEMPLATE = `analytic
# A Disney BRDF Explorer .brdf: edit it and the sphere redraws.
# Lambert plus a Blinn-Phong lobe, normalised as in Real-Time
# Rendering 3rd ed., eq. 7.49. BRDF returns f, no cosine.
::begin parameters
color albedo 0.7 0.45 0.3
float n 1 500 50
float ks 0 1 0.2
::end parameters
::begin shader
const float PI = 3.14159265358979;

vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y)
{
    vec3 H = normalize(L + V);
    float lobe = (n + 8) / (8 * PI) * pow(max(0, dot(N, H)), n);
    return albedo / PI + vec3(ks * lobe);
}
::end shader
`;

export class BrdfEditor {
  /** apply(text) → Promise of {ok} or {ok: false, message, lines: [line numbers]}, or
   * {stale: true} when a newer text overtook it. */
  constructor({ apply }) {
    this.apply = apply;
    this.area = el("textarea", { id: "gpu-brdf-editor", class: "gpu-editor-text", spellcheck: "false", autocomplete: "off",
                                 autocapitalize: "off", wrap: "off", rows: "18", "aria-label": "The .brdf text",
                                 "aria-describedby": "gpu-editor-message" });
    this.gutter = el("pre", { class: "gpu-editor-lines", "aria-hidden": "true" });
    this.status = el("p", { class: "gpu-message error", id: "gpu-editor-message", role: "status", "aria-live": "polite", hidden: true });
    this.section = el("details", { class: "gpu-editor", id: "gpu-editor" },
      el("summary", { text: "Your .brdf's text — it redraws as you type" }),
      el("div", { class: "gpu-editor-body" }, this.gutter, this.area), this.status);
    Object.assign(this, { timer: 0, turn: 0, marked: new Set(), shownLines: -1, appliedText: null });
    this.area.value = TEMPLATE;
    this.number();
    this.area.addEventListener("input", () => this.changed());
    this.area.addEventListener("scroll", () => { this.gutter.scrollTop = this.area.scrollTop; });
  }

  /** Opened, the text in view and focused (the panel's "Write or edit" button). */
  reveal() {
    this.section.open = true;
    this.area.focus({ preventScroll: true });
    this.section.scrollIntoView({ block: "nearest" });
  }

  /** Whether what is shown (drawing or error) answers the text as it is now. */
  get settled() { return this.appliedText === this.area.value; }

  /** A text opened elsewhere (a file, the link): shown, not compiled again; with the
   * error it failed with, if it did (a file to be fixed here). */
  show(text, message = null, lines = []) {
    clearTimeout(this.timer);
    this.turn++;
    this.area.value = this.appliedText = text;
    this.tell(message, lines);
  }

  changed() {
    this.number();
    clearTimeout(this.timer);
    this.timer = setTimeout(() => this.run(), DEBOUNCE_MS);
  }

  async run() {
    const turn = ++this.turn;
    const text = this.area.value;
    const answer = await this.apply(text);
    if (turn !== this.turn || answer.stale) return;        // the user typed on meanwhile
    this.appliedText = text;
    this.tell(answer.ok ? null : answer.message, answer.ok ? [] : answer.lines);
  }

  /** The error (or none) under the text, its lines marked in the gutter. */
  tell(message, lines) {
    this.status.hidden = !message;
    this.status.textContent = message ? `${message}\nThe last version that compiled stays drawn.` : "";
    this.marked = new Set(lines);
    this.shownLines = -1;
    this.number();
  }

  /** The gutter's line numbers, rebuilt when the count or the marks change. */
  number() {
    const count = this.area.value.split("\n").length;
    if (count === this.shownLines) return;
    this.shownLines = count;
    this.gutter.textContent = "";
    for (let i = 1; i <= count; i++) {
      this.gutter.append(this.marked.has(i) ? el("span", { class: "gpu-editor-bad", text: String(i) }) : String(i), "\n");
    }
    this.gutter.scrollTop = this.area.scrollTop;
  }
}
