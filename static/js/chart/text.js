/* A figure's text as the API writes it (Plotly's markup: <sub>, <sup>, <i>, <b>, <br>
 * and the HTML entities) as page nodes, built from text nodes and those elements only:
 * nothing in it is parsed as HTML.
 */
import { el } from "../base/dom.js";

const TAGS = new Set(["sub", "sup", "i", "b", "em"]);
const ENTITIES = { "&lt;": "<", "&gt;": ">", "&amp;": "&", "&quot;": '"', "&#39;": "'", "&nbsp;": " " };
const unescape = (s) => s.replace(/&(?:lt|gt|amp|quot|#39|nbsp);/g, (e) => ENTITIES[e]);

/** The nodes of `text`: the tags above nested as written, <br> a line break, any other
 * tag dropped. */
export function markup(text) {
  const root = document.createDocumentFragment();
  const stack = [root];
  for (const part of String(text ?? "").split(/(<\/?[a-z]+\s*\/?>)/i)) {
    const tag = /^<(\/?)([a-z]+)\s*\/?>$/i.exec(part);
    if (!tag) {
      if (part) stack[stack.length - 1].append(unescape(part));
      continue;
    }
    const name = tag[2].toLowerCase();
    if (name === "br") stack[stack.length - 1].append(el("br"));
    else if (!TAGS.has(name)) continue;
    else if (!tag[1]) {
      const node = el(name);
      stack[stack.length - 1].append(node);
      stack.push(node);
    } else if (stack.length > 1 && stack[stack.length - 1].nodeName.toLowerCase() === name) stack.pop();
  }
  return root;
}
