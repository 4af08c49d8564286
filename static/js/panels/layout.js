/* The API's figures are made to stand alone (title on top, legend below the x axis).
 * On a page the figure's box sets the size and a legend sits above the axes, clear of
 * the axis titles at any height. keepTitle: the title stays, in the top margin (embeds).
 */
import { plainIndex } from "../base/dom.js";

export const PLOT_CONFIG = { responsive: true, displaylogo: false, modeBarButtonsToRemove: ["lasso2d", "select2d"] };

/** The figure's title as the server wrote it (Plotly markup and all), or "". */
function plotTitle(layout) {
  const t = layout && layout.title;
  return String((typeof t === "string" ? t : t && t.text) || "");
}

/** The figure title as the page's text, or "": indexed symbols in the page's notation
 * ("θ_v", which richText draws as a subscript; the figure has θ<sub>v</sub> for Plotly),
 * any other markup (<br>) as sent. */
export function titleText(layout) {
  return plainIndex(plotTitle(layout));
}

export function fitLayout(given, { keepTitle = false } = {}) {
  const layout = { ...given };
  delete layout.width;
  delete layout.height;
  layout.autosize = true;
  layout.margin = { ...(layout.margin || {}) };
  const title = layout.title;
  delete layout.title;
  // Plotly places a title of several <br> lines by its first line: the first line is
  // the title and the rest its subtitle, which Plotly stacks below it.
  const text = keepTitle ? plotTitle(given) : "";      // Plotly draws its subscripts
  const [head, ...rest] = text.split(/<br\s*\/?>/i);
  // 26 px: the 13 px title line with its padding; 15 px per 11 px subtitle line
  const top = text ? 26 + 15 * rest.length : 0;
  if (top) {
    layout.title = { ...(typeof title === "string" ? {} : title), text: head,
                     yref: "container", y: 0.99, yanchor: "top", font: { size: 13 } };
    if (rest.length) layout.title.subtitle = { text: rest.join("<br>"), font: { size: 11 } };
  }
  const cartesian = !layout.polar && !layout.scene && Object.keys(layout).some((k) => /^[xy]axis\d*$/.test(k));
  if (layout.polar) {
    layout.margin.t = Math.min(layout.margin.t ?? 24, 24) + top;
    layout.margin.b = Math.max(layout.margin.b ?? 0, 34);
    if (layout.showlegend !== false) {
      layout.legend = { ...(layout.legend || {}), orientation: "h", x: 0.5, xanchor: "center",
                        y: 0, yanchor: "top", bgcolor: "rgba(255,255,255,0)" };
    }
  } else if (layout.scene) {
    layout.margin.t = top;
  } else if (!cartesian) {
    layout.margin.t = 8 + top;          // a table: its top margin held the title
  } else {
    const legendShown = layout.showlegend !== false;
    layout.margin.t = (legendShown ? 30 : 14) + top;
    layout.margin.b = Math.min(layout.margin.b ?? 50, 46);
    if (legendShown) {
      layout.legend = { ...(layout.legend || {}), orientation: "h", x: 1, xanchor: "right",
                        y: 1.01, yanchor: "bottom", bgcolor: "rgba(255,255,255,0)" };
    }
    for (const k of Object.keys(layout)) if (/^[xy]axis\d*$/.test(k)) layout[k] = { ...layout[k], automargin: true };
  }
  return layout;
}

/* Keep the layout object of a plot while only its data moves: Plotly.react then diffs
 * nothing in the layout (no axis re-layout); a layout that really changed (a range, a
 * log axis) is passed as a new object. The comparison is on the fitted layout as sent. */
export const layoutKey = (layout, uirevision) => JSON.stringify(layout) + uirevision;

export function reuseLayout(holder, layout, uirevision) {
  const key = layoutKey(layout, uirevision);
  if (holder.layout && holder.layoutKey === key) return holder.layout;
  holder.layoutKey = key;
  holder.layout = { ...layout, uirevision };
  return holder.layout;
}

/** An overlay names its traces "<quantity> · <model>": the first model keeps one legend
 * entry per quantity (they explain the line styles); each other model gets one entry,
 * its name, and one click shows or hides all its traces. */
const OVERLAY_SEP = " · ";
export function compactLegend(data) {
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

/** The page fixed a figure's value axes to the model's curves; with other curves beside
 * them (a data set's, the user's BRDF's) they range over all (autorange over every trace):
 * a peak far above the model is drawn, not cut off at the model's top. */
export function rangeOverAll(given) {
  const layout = { ...given };
  for (const k of Object.keys(layout)) {
    if (!/^yaxis\d*$/.test(k)) continue;
    const { range, ...axis } = layout[k];
    layout[k] = { ...axis, autorange: true };
  }
  if (layout.polar) {
    const { range, ...radial } = layout.polar.radialaxis || {};
    layout.polar = { ...layout.polar, radialaxis: { ...radial, autorange: true } };
  }
  return layout;
}
