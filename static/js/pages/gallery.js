/* The gallery: GET /api/v1/gallery lists the cards; each is drawn live when it
 * scrolls into view, two at a time, with a progress line while they load. A card shows
 * what its entry carries (app/gallery/cards.py): a Plotly figure (a view's, a data set's
 * on a view, the conventions'); a fit (its POST, then the fitted model over the data);
 * an excerpt of generated shader code; or a LUT's PNG with the error its JSON states. */
import { API, el, richText, apiMessage } from "../base/dom.js";
import { exportBar } from "../panels/exports.js";
import { fitLayout, PLOT_CONFIG } from "../panels/layout.js";

const PARALLEL = 2;               // figures fetched at once (the server has few cores)
const EXCERPT_LINES = 26;         // of generated code: the model's f(l, v) and its comment
const SYMBOLS = { alpha: "α", f0: "F₀", kd: "k_d" };
const AXIS_WORDS = { mu: "μ = cos θ_v", sqrt_mu: "√μ", alpha: "α" };   // a LUT's axes, as its caption names them
const CONFIG = { ...PLOT_CONFIG, modeBarButtonsToRemove: [...PLOT_CONFIG.modeBarButtonsToRemove, "toImage"] };
const grid = document.getElementById("gallery-grid");
const status = document.getElementById("gallery-status");
let total = 0, done = 0, failed = 0, running = 0;
const queue = [];

function progress() {
  if (done + failed < total) {
    status.textContent = `Drawing cards: ${done} of ${total}…`;
    status.className = "gallery-status loading";
  } else {
    status.textContent = failed ? `${failed} of ${total} cards could not be drawn.` : `${total} cards.`;
    status.className = `gallery-status${failed ? " failed" : ""}`;
  }
}

/** A GET that must answer 2xx; the API's message otherwise. */
async function get(url, accept) {
  const res = await fetch(url, { headers: { Accept: accept } });
  if (!res.ok) throw new Error(apiMessage(await res.json().catch(() => null), res));
  return res;
}

async function plot(item, url) {
  const body = await (await get(url, "application/json")).json();
  await Plotly.react(item.div, body.data, fitLayout(body.layout || {}), CONFIG);   // the card's heading is the title
}

/** The fitted parameters with their standard errors, and the fit's own verdict. */
function fitLine(r) {
  const params = Object.entries(r.params).map(([k, v]) =>
    `${SYMBOLS[k] || k} = ${v.toPrecision(3)} ± ${r.stderr[k].toPrecision(1)}`).join(", ");
  const misfit = r.misfit && r.misfit.relative_rms > r.misfit.threshold
    ? ` Relative RMS error ${(100 * r.misfit.relative_rms).toFixed(1)} % > ${100 * r.misfit.threshold} %: the fit warns that the model does not describe the data.`
    : "";
  return `Fitted (${r.measure.name} measure, ${r.points.count} points, ${r.seconds.toFixed(2)} s): ${params}.${misfit}`;
}

/** From the comment above the model's f(l, v) (brdf_local) through its closing line. */
function excerpt(text) {
  const lines = text.split("\n");
  let start = lines.findIndex((l) => /^\s*\S.*\bbrdf_local\s*\(/.test(l) && !/^\s*(\/\/|#)/.test(l));
  if (start < 0) start = 0;
  while (start > 0 && /^\s*(\/\/|#)/.test(lines[start - 1])) start -= 1;
  return { shown: lines.slice(start, start + EXCERPT_LINES).join("\n"), from: start + 1, total: lines.length };
}

const DRAW = {
  figure: (item) => plot(item, item.entry.figure),
  async fit(item) {
    const { url, body, figure } = item.entry.fit;
    const res = await fetch(url, { method: "POST", body: JSON.stringify(body),
                                   headers: { "Content-Type": "application/json", Accept: "application/json" } });
    const result = await res.json().catch(() => null);
    if (!res.ok) throw new Error(apiMessage(result, res));
    await plot(item, `${figure}&${new URLSearchParams(result.model)}`);
    item.result.replaceChildren(richText(fitLine(result)));
  },
  async excerpt(item) {
    const text = await (await get(item.entry.excerpt.href, "text/plain")).text();
    const { shown, from, total: lines } = excerpt(text);
    item.div.textContent = shown;
    item.result.textContent = `Lines ${from}–${from + shown.split("\n").length - 1} of ${lines}; the whole file at the links below.`;
  },
  async image(item) {
    const img = item.div;
    img.src = item.entry.image.src;
    await img.decode().catch(() => { throw new Error("the table's PNG could not be read"); });
    const s = await (await get(item.entry.image.summary, "application/json")).json();
    const max = (part) => s.error[part].max_overall.toExponential(1);
    const span = (axis) => `${AXIS_WORDS[axis.name] || axis.name} ${axis.values[0].toFixed(2)} to ${axis.values.at(-1).toFixed(2)}`;
    item.result.replaceChildren(richText(`Rows, top to bottom: ${span(s.axes[0])}; columns, left to right: ${span(s.axes[1])}. `
      + `Largest error over the ${s.size} × ${s.size} texels: ${max("table")} in the values, `
      + `${max("quantised")} stored as ${s.quantisation}, ${max("lookup")} read with bilinear filtering.`));
  },
};

async function drawOne(item) {
  try {
    await DRAW[item.draws](item);
    item.card.classList.add("drawn");
    done += 1;
  } catch (e) {
    if (item.div.tagName === "IMG") {               // an image holds no text: a plain frame says it
      const frame = el("div", { class: "plot", id: item.div.id });
      item.div.replaceWith(frame);
      item.div = frame;
    }
    item.div.textContent = `Could not draw this card: ${e.message}`;
    item.card.classList.add("failed");
    failed += 1;
  }
  progress();
}

function pump() {
  while (running < PARALLEL && queue.length) {
    running += 1;
    drawOne(queue.shift()).finally(() => { running -= 1; pump(); });
  }
}

/** Each plot div's card item, for the observer that draws it when it scrolls near. */
const items = new WeakMap();

const observer = new IntersectionObserver((entries) => {
  for (const e of entries) {
    if (!e.isIntersecting) continue;
    observer.unobserve(e.target);
    queue.push(items.get(e.target));
    pump();
  }
}, { rootMargin: "300px" });

/** What the card draws: the first of these its entry carries. */
const drawsOf = (entry) => ["fit", "excerpt", "image", "figure"].find((k) => entry[k]);

/** The drawing area: a plot, a code block or an image, each in the same-sized frame. */
function canvas(entry, draws) {
  if (draws === "excerpt") return el("pre", { class: "gallery-code", id: `plot-${entry.id}`, tabindex: "0", "aria-label": `${entry.title}: an excerpt` });
  if (draws === "image") return el("img", { class: "gallery-image", id: `plot-${entry.id}`, alt: entry.title });
  return el("div", { class: "plot gallery-plot", id: `plot-${entry.id}`, role: "img", "aria-label": entry.title });
}

/** A view's card: the explorer link and the export buttons (SVG, PNG, CSV, embed). */
function viewLinks(entry, div, note) {
  const bar = exportBar(() => ({ kind: entry.kind, params: entry.state, figure: div, title: entry.title }), (kind, text) => {
    note.textContent = kind === "busy" || kind === "note" || kind === "error" ? text : "";
    note.hidden = !note.textContent;
  });
  return el("div", { class: "gallery-links" }, el("a", { href: entry.explorer, class: "open" }, "Open in the explorer →"), bar);
}

/** Any other card: where the capability lives in the product, and the raw API answers. */
function capabilityLinks(entry) {
  return el("div", { class: "gallery-links" }, el("a", { href: entry.open.href, class: "open" }, entry.open.label),
    el("span", { class: "gallery-api" }, "API:",
       ...entry.links.map((l) => el("a", { href: l.href, type: l.type, text: l.label }))));
}

function card(entry) {
  const draws = drawsOf(entry);
  const div = canvas(entry, draws);
  const hid = `g-${entry.id}`;
  const item = { entry, div, draws, card: null, result: el("p", { class: "gallery-result", role: "status" }) };
  const note = el("p", { class: "gallery-note", role: "status", hidden: true });
  item.card = el("figure", { class: "gallery-card", id: entry.id, "aria-labelledby": hid, "data-kind": entry.kind },
    el("h2", { id: hid }, richText(entry.title)),
    el("div", { class: "plot-wrap" }, div),
    el("figcaption", {},
      el("p", {}, richText(entry.caption)),
      item.result,
      el("p", { class: "gallery-source", text: entry.source }),
      entry.explorer ? viewLinks(entry, div, note) : capabilityLinks(entry),
      note));
  items.set(div, item);
  return item.card;
}

async function boot() {
  try {
    const res = await fetch(`${API}/gallery`, { headers: { Accept: "application/json" } });
    const body = await res.json().catch(() => null);
    if (!res.ok || !Array.isArray(body)) throw new Error(apiMessage(body, res));
    total = body.length;
    for (const entry of body) {
      const c = card(entry);
      grid.append(c);
      observer.observe(c.querySelector(`#plot-${CSS.escape(entry.id)}`));
    }
    progress();
  } catch (e) {
    status.textContent = `Could not load the gallery: ${e.message}`;
    status.className = "gallery-status failed";
  }
}

window.__gallery = { pending: () => total === 0 || done + failed < total, done: () => done, failed: () => failed,
                     inFlight: () => running + queue.length };     // cards being drawn now, or queued to be
boot();
