/* Export buttons (SVG, PNG, CSV, embed code) for one figure, on the explorer, the
 * embeds and the gallery.
 *
 * SVG and PNG come at a slide's size, whatever the panel's: 1600 × 1000 CSS pixels
 * (16:10, a slide's content area), PNG at 2 pixels per CSS pixel (sharp on a projector).
 * The server renders them (kaleido) with the figure's own stand-alone layout (title on
 * top, legend clear of the axis titles); without a renderer there (503) this browser
 * renders the drawn plot at the same size instead. The file is named after the figure
 * and every parameter that differs from the defaults, so two slides never share a name.
 */
import { API, el, apiMessage, query, saveBlob, copyText, flash } from "../base/dom.js";

export const SLIDE = { width: 1600, height: 1000, pngScale: 2 };
const EMBED = { width: 640, height: 440 };

/** "lobe_alpha=0.2_theta_i_deg=50.png": the kind, then each non-default parameter. */
export function exportName(kind, params, format) {
  const parts = Object.entries(params).filter(([, v]) => v !== undefined && v !== null && v !== "")
    .map(([k, v]) => `${k}=${String(v).replace(/[^A-Za-z0-9.,+-]/g, "-")}`);
  return `${[kind, ...parts].join("_")}.${format}`;
}

/** Download one export of a view: format "svg" | "png" | "csv"; params: the figure's
 * query without its defaults; figure: what Plotly draws in this browser when the server
 * cannot (a plot it drew, or a figure {data, layout}). */
export async function exportFigure(format, kind, params, figure) {
  const { width, height } = SLIDE;
  const scale = format === "png" ? SLIDE.pngScale : 1;
  const extra = format === "csv" ? {} : { width, height, scale };
  const url = `${API}/figures/${kind}.${format}?${query({ ...params, ...extra })}`;
  const filename = exportName(kind, params, format);
  let res;
  try {
    res = await fetch(url);
  } catch {
    throw new Error("Cannot reach the server.");
  }
  if (res.ok) {
    saveBlob(await res.blob(), filename);
    return { how: "server", message: "" };
  }
  const body = await res.json().catch(() => null);
  if (res.status === 503 && format !== "csv" && figure && window.Plotly) {
    await Plotly.downloadImage(figure, { format, width, height, scale, filename: filename.replace(/\.\w+$/, "") });
    return { how: "browser", message: `${apiMessage(body, res)} (Exported in your browser instead.)` };
  }
  throw new Error(apiMessage(body, res));
}

export function embedSnippet(kind, params, title) {
  const src = `${location.origin}/embed/${kind}?${query(params)}`;
  const safeTitle = String(title || kind).replace(/[<>&"]/g, "");
  return `<iframe src="${src}" width="${EMBED.width}" height="${EMBED.height}" `
    + `title="${safeTitle}" loading="lazy" style="border:0;max-width:100%"></iframe>`;
}

/* The buttons. get() returns {kind, params, figure, title}; report(kind, text) shows a
 * status: "busy", "note", "error", or null to clear. */
export function exportBar(get, report) {
  const bar = el("div", { class: "export-bar", role: "group", "aria-label": "Export this figure" });
  for (const format of ["svg", "png", "csv"]) {
    const name = format.toUpperCase();
    const b = el("button", { type: "button", class: "export", "data-format": format, text: name,
                             "aria-label": `Download as ${name}`,
                             title: format === "csv" ? "Download the numbers behind the figure (CSV, units in the header)"
                               : `Download the figure as ${name}, ${SLIDE.width} × ${SLIDE.height} (a slide)` });
    b.addEventListener("click", async () => {
      const { kind, params, figure, title } = get();
      b.disabled = true;
      report("busy", `exporting ${name}…`);
      try {
        const r = await exportFigure(format, kind, params, figure);
        report(r.how === "browser" ? "note" : null, r.message);
        if (r.how !== "browser") flash(b, "✓");
        b.setAttribute("aria-label", `${name} of ${title || kind}: downloaded`);
      } catch (e) {
        report("error", `Export failed: ${e.message}`);
      } finally {
        b.disabled = false;
      }
    });
    bar.append(b);
  }
  const embed = el("button", { type: "button", class: "export", "data-format": "embed", text: "</>",
                               title: "Copy an <iframe> snippet showing this figure in its current state",
                               "aria-label": "Copy embed code" });
  embed.addEventListener("click", async () => {
    const { kind, params, title } = get();
    const snippet = embedSnippet(kind, params, title);
    if (await copyText(snippet)) {
      flash(embed, "Copied ✓");
      report(null, "");
    } else {
      report("note", snippet);
    }
  });
  bar.append(embed);
  return bar;
}
