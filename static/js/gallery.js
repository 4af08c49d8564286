/* The gallery: GET /api/v1/gallery lists the figures; each is drawn live when it
 * scrolls into view, two at a time, with a progress line while they load. */
import { API, el, richText, apiMessage } from "./dom.js";
import { exportBar } from "./exports.js";
import { fitLayout, PLOT_CONFIG } from "./layout.js";

const PARALLEL = 2;               // figures fetched at once (the server has few cores)
const CONFIG = { ...PLOT_CONFIG, modeBarButtonsToRemove: [...PLOT_CONFIG.modeBarButtonsToRemove, "toImage"] };
const grid = document.getElementById("gallery-grid");
const status = document.getElementById("gallery-status");
let total = 0, done = 0, failed = 0, running = 0;
const queue = [];

function progress() {
  if (done + failed < total) {
    status.textContent = `Drawing figures: ${done} of ${total}…`;
    status.className = "gallery-status loading";
  } else {
    status.textContent = failed ? `${failed} of ${total} figures could not be drawn.` : `${total} figures.`;
    status.className = `gallery-status${failed ? " failed" : ""}`;
  }
}

async function drawOne(item) {
  try {
    const res = await fetch(item.entry.figure, { headers: { Accept: "application/json" } });
    const body = await res.json().catch(() => null);
    if (!res.ok) throw new Error(apiMessage(body, res));
    await Plotly.react(item.div, body.data, fitLayout(body.layout || {}), CONFIG);   // the card's heading is the title
    item.card.classList.add("drawn");
    done += 1;
  } catch (e) {
    item.div.textContent = `Could not draw this figure: ${e.message}`;
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

function card(entry) {
  const div = el("div", { class: "plot gallery-plot", id: `plot-${entry.id}`, role: "img", "aria-label": entry.title });
  const hid = `g-${entry.id}`;
  const item = { entry, div, card: null };
  const note = el("p", { class: "gallery-note", role: "status", hidden: true });
  const bar = exportBar(() => ({ kind: entry.kind, params: entry.state, div, title: entry.title }), (kind, text) => {
    note.textContent = kind === "busy" || kind === "note" || kind === "error" ? text : "";
    note.hidden = !note.textContent;
  });
  item.card = el("figure", { class: "gallery-card", id: entry.id, "aria-labelledby": hid },
    el("h2", { id: hid }, richText(entry.title)),
    el("div", { class: "plot-wrap" }, div),
    el("figcaption", {},
      el("p", {}, richText(entry.caption)),
      el("p", { class: "gallery-source", text: entry.source }),
      el("div", { class: "gallery-links" }, el("a", { href: entry.explorer, class: "open" }, "Open in the explorer →"), bar),
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
      observer.observe(c.querySelector(".gallery-plot"));
    }
    progress();
  } catch (e) {
    status.textContent = `Could not load the gallery: ${e.message}`;
    status.className = "gallery-status failed";
  }
}

window.__gallery = { pending: () => total === 0 || done + failed < total, done: () => done, failed: () => failed };
boot();
