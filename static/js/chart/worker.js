/* The chart's worker: it holds one chart's OffscreenCanvas and paints on it
 * (painter.js), so the page's main thread neither draws nor copies the pixels to the
 * screen — a panel's redraw costs it a message, and a slider's input events never wait
 * behind four canvases being committed (measured: ~10 ms a frame on the main thread,
 * the input events of a drag late past one 60 Hz frame; none from the worker).
 * Messages: {id, op: "init" | "paint" | "hover" | "zoom" | "pixels", ...}; each is
 * answered {id, result} or {id, error}.
 */
import { Painter } from "./painter.js";

let painter = null;

self.onmessage = ({ data: { id, op, ...args } }) => {
  try {
    if (op === "init") {
      painter = new Painter(args.canvas);
      self.postMessage({ id, result: true });
      return;
    }
    const result = painter[op](args);
    self.postMessage({ id, result }, op === "pixels" ? [result.data.buffer] : []);
  } catch (e) {
    self.postMessage({ id, error: e?.message || String(e) });
  }
};
