/* The light dragged on a lit sphere.
 *
 * Where the pointer is on the disk, the surface there faces the light (n = l, the
 * "n = l" marker of the sphere view): θ_i = asin r and φ_i = atan2(y, x) in the image's
 * own axes, which both sphere views lay out as the normal's (x, y) (x right, y up; the
 * environment sphere's image rows run from y = 1 down). Past the rim the light stays on
 * it (θ_i = 90°). While the pointer is down the page is "held", as with a slider: heavy
 * images come coarser and axes stay put; the sidebar's θ_i and φ_i follow the drag.
 * A press off the disk is left to Plotly (zoom, pan).
 */
/** The plot area Plotly drew (its clip rectangle of the xy subplot, in the SVG's
 * pixels), or null before the first draw. */
function plotBox(gd) {
  const rect = gd.querySelector('clipPath.axesclip[id$="xy"] rect');
  const n = (a) => Number(rect?.getAttribute(a));
  const box = { x: n("x"), y: n("y"), w: n("width"), h: n("height") };
  return rect && Object.values(box).every(Number.isFinite) && box.w > 0 && box.h > 0 ? box : null;
}

const DEG = 180 / Math.PI;
const round1 = (v) => Math.round(v * 10) / 10;

/** The pointer in the plot's data coordinates (the axes' ranges as Plotly writes them
 * back into the figure's layout, over the plot area it drew), or null before the first
 * draw. */
function dataAt(div, ev) {
  const xr = div.layout?.xaxis?.range, yr = div.layout?.yaxis?.range, area = plotBox(div);
  const svg = div.querySelector("svg.main-svg");
  if (!Array.isArray(xr) || !Array.isArray(yr) || !area || !svg) return null;
  const at = svg.getBoundingClientRect();
  const u = (ev.clientX - at.left - area.x) / area.w, v = (ev.clientY - at.top - area.y) / area.h;
  return [xr[0] + u * (xr[1] - xr[0]), yr[1] - v * (yr[1] - yr[0])];
}

/** (θ_i, φ_i) in degrees for the light facing the sphere's point (x, y). */
export function lightAt(x, y) {
  const r = Math.min(1, Math.hypot(x, y));
  return [round1(Math.asin(r) * DEG), round1(Math.atan2(y, x) * DEG)];
}

/** Lets the light be dragged on `div`'s sphere: set(θ_i, φ_i) at each move, hold(bool)
 * when the drag starts and ends. */
export function lightDrag(div, { set, hold }) {
  let dragging = false;
  const aim = (ev) => {
    const p = dataAt(div, ev);
    if (p && Number.isFinite(p[0]) && Number.isFinite(p[1])) set(...lightAt(p[0], p[1]));
  };
  div.classList.add("light-drag");
  div.title = "Drag on the sphere to move the light";
  div.addEventListener("pointerdown", (ev) => {
    const p = dataAt(div, ev);
    if (ev.button !== 0 || !p || !(Math.hypot(p[0], p[1]) <= 1)) return;
    ev.preventDefault();              // no mouse events follow: Plotly does not start a zoom
    ev.stopPropagation();
    dragging = true;
    div.setPointerCapture?.(ev.pointerId);
    hold(true);
    aim(ev);
  }, { capture: true });
  div.addEventListener("pointermove", (ev) => {
    if (!dragging) return;
    ev.preventDefault();
    ev.stopPropagation();
    aim(ev);
  }, { capture: true });
  const end = () => {
    if (!dragging) return;
    dragging = false;
    hold(false);
  };
  div.addEventListener("pointerup", end, { capture: true });
  div.addEventListener("pointercancel", end, { capture: true });
}
