/* DOM building, the API's error messages, the clipboard: shared by every page. */

export const API = "/api/v1";

export function el(tag, attrs = {}, ...kids) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (v === null || v === undefined || v === false) continue;
    if (k === "class") e.className = v;
    else if (k === "text") e.textContent = v;
    else e.setAttribute(k, v === true ? "" : v);
  }
  for (const kid of kids) if (kid) e.append(kid);
  return e;
}

export const $ = (sel, root = document) => root.querySelector(sel);

/** node[key] = value, only if it differs: an attribute set to the value it has is still a
 * change for the browser (style invalidated, the layer repainted), and a slider's input
 * event re-states dozens of them. */
export function setIf(node, key, value) {
  if (node[key] !== value) node[key] = value;
}

// A symbol with an index: one or two letters (θ, α, G, F0 is not one), then "_" and a
// short index ("θ_i", "G_1", "E_avg", "α_{x,y}"). Anything longer is a name and stays
// a name: "height_correlated", "lambda_phi", "theta_i_deg".
const INDEXED = /(^|[^\p{L}\p{N}_])(\p{L}{1,2})_(\p{L}{1,3}|\p{N}{1,2}|\{[^}]{1,8}\})(?![\p{L}\p{N}_])/gu;

// Plotly's subscript markup as the figures write an indexed symbol ("θ<sub>v</sub>", so
// that Plotly draws it), back to the page's notation "θ_v": a figure's title or a trace's
// name read as text says what it said before, and richText draws the index again.
const SUB_MARKUP = /(\p{L})<sub>([\p{L}\p{N}]+)<\/sub>/gu;

/** "θ<sub>v</sub> (degrees)" -> "θ_v (degrees)"; other text and markup unchanged. */
export const plainIndex = (text) => String(text).replace(SUB_MARKUP, "$1_$2");

/** "θ_i (incidence)" or "θ<sub>i</sub> (incidence)" -> θ<sub>i</sub> (incidence), built
 * from text nodes only (markup in `text` is never parsed as HTML: tags are dropped). */
export function richText(text) {
  const frag = document.createDocumentFragment();
  text = plainIndex(text).replace(/<br\s*\/?>/gi, " ").replace(/<[^>]*>/g, "");
  let last = 0;
  for (const m of text.matchAll(INDEXED)) {
    const start = m.index + m[1].length;
    frag.append(text.slice(last, start) + m[2], el("sub", { text: m[3].replace(/[{}]/g, "") }));
    last = m.index + m[0].length;
  }
  frag.append(text.slice(last));
  return frag;
}

/** Shows `frag` in `node`: where both have the same nodes (a heading whose numbers
 * moved: "GGX α=0.0425" → "GGX α=0.0431"), by rewriting the text that changed in place,
 * which lays out only that text where replacing the nodes restyled and laid out each. */
export function replaceText(node, frag) {
  const old = node.childNodes, nu = frag.childNodes;
  // text, or an element holding one text (<sub>), node for node
  const leaf = (n) => (n.nodeType === Node.TEXT_NODE ? n : n.childNodes.length === 1 && n.firstChild.nodeType === Node.TEXT_NODE ? n.firstChild : null);
  const same = old.length === nu.length && [...nu].every((n, i) => n.nodeName === old[i].nodeName && leaf(n) && leaf(old[i]));
  if (!same) {
    node.textContent = "";
    node.append(frag);
    return;
  }
  nu.forEach((n, i) => {
    const was = leaf(old[i]), text = leaf(n).data;
    if (was.data !== text) was.data = text;
  });
}

/** FastAPI's errors: {"detail": "message"} or {"detail": [{loc, msg, ...}, ...]}. */
export function apiMessage(body, res) {
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

export function errorLoc(body) {
  const d = body && body.detail;
  return Array.isArray(d) && d[0] && Array.isArray(d[0].loc) ? d[0].loc : [];
}

export function query(params) {
  const q = new URLSearchParams();
  for (const [k, v] of Object.entries(params)) if (v !== undefined && v !== null) q.set(k, String(v));
  return q.toString();
}

/** GET an API path as JSON; throws with the API's own message. */
export async function getJSON(path) {
  const res = await fetch(`${API}${path}`, { headers: { Accept: "application/json" } });
  const body = await res.json().catch(() => null);
  if (!res.ok || !body) throw new Error(apiMessage(body, res));
  return body;
}

/** Clipboard where allowed (secure context, permission); resolves true when copied. */
export async function copyText(text) {
  try {
    await navigator.clipboard.writeText(text);
    return true;
  } catch {
    return false;
  }
}

const flashTimers = new WeakMap();

/** A short confirmation on a button, then its own label again. */
export function flash(button, text, ms = 1500) {
  const old = button.dataset.label || button.textContent;
  button.dataset.label = old;
  button.textContent = text;
  clearTimeout(flashTimers.get(button));
  flashTimers.set(button, setTimeout(() => { button.textContent = old; }, ms));
}

export function saveBlob(blob, filename) {
  const url = URL.createObjectURL(blob);
  const a = el("a", { href: url, download: filename });
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 10000);
}
