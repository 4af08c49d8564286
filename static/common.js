/* Helpers shared by the explorer (app.js), the embed page (embed.js) and the gallery
 * (gallery.js): DOM building, API error messages, exports and the clipboard.
 * Exposed as window.BRDF; no build step, no inline script (CSP script-src 'self').
 */
"use strict";

window.BRDF = (() => {
  const API = "/api/v1";
  // Default export size of a figure, CSS pixels, and PNG pixels per CSS pixel (2: sharp
  // on a projector or a high-density screen). The page uses the panel's own size.
  const EXPORT = { width: 800, height: 560, pngScale: 2, minSide: 320, maxSide: 2000 };
  const EMBED = { width: 640, height: 440 };

  const el = (tag, attrs = {}, ...kids) => {
    const e = document.createElement(tag);
    for (const [k, v] of Object.entries(attrs)) {
      if (v === null || v === undefined || v === false) continue;
      if (k === "class") e.className = v;
      else if (k === "text") e.textContent = v;
      else e.setAttribute(k, v === true ? "" : v);
    }
    for (const kid of kids) if (kid) e.append(kid);
    return e;
  };

  // "θ_i (incidence)" -> θ<sub>i</sub> (incidence), built from text nodes only.
  function richText(text) {
    const frag = document.createDocumentFragment();
    const re = /([^\s(_]+)_([A-Za-z0-9]+|\{[^}]*\})/g;
    let last = 0, m;
    text = String(text).replace(/<br\s*\/?>/gi, " ").replace(/<[^>]*>/g, "");
    while ((m = re.exec(text))) {
      frag.append(text.slice(last, m.index) + m[1], el("sub", { text: m[2].replace(/[{}]/g, "") }));
      last = re.lastIndex;
    }
    frag.append(text.slice(last));
    return frag;
  }

  // FastAPI's errors: {"detail": "message"} or {"detail": [{loc, msg, ...}, ...]}.
  function apiMessage(body, res) {
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

  function errorLoc(body) {
    const d = body && body.detail;
    return Array.isArray(d) && d[0] && Array.isArray(d[0].loc) ? d[0].loc : [];
  }

  function query(params) {
    const q = new URLSearchParams();
    for (const [k, v] of Object.entries(params)) if (v !== undefined && v !== null) q.set(k, String(v));
    return q.toString();
  }

  function saveBlob(blob, filename) {
    const url = URL.createObjectURL(blob);
    const a = el("a", { href: url, download: filename });
    document.body.append(a);
    a.click();
    a.remove();
    setTimeout(() => URL.revokeObjectURL(url), 10000);
  }

  function clampSide(x) {
    return Math.round(Math.min(EXPORT.maxSide, Math.max(EXPORT.minSide, x || 0)));
  }

  /* Download one export of a view: format "svg" | "png" | "csv".
   *   kind, params: the figure and its query (model + view parameters)
   *   div: the drawn Plotly div (for the in-browser fallback and its size)
   * SVG and PNG come from the server (kaleido); when it answers 503 (no Chromium there)
   * Plotly renders them in this browser instead. Resolves to {how, message}.
   */
  async function exportFigure(format, kind, params, div) {
    const width = clampSide(div && div._fullLayout ? div._fullLayout.width : EXPORT.width);
    const height = clampSide(div && div._fullLayout ? div._fullLayout.height : EXPORT.height);
    const extra = format === "csv" ? {} : { width, height, scale: format === "png" ? EXPORT.pngScale : 1 };
    const url = `${API}/figures/${kind}.${format}?${query({ ...params, ...extra })}`;
    const filename = `${kind}.${format}`;
    let res;
    try {
      res = await fetch(url);
    } catch (e) {
      throw new Error("Cannot reach the server.");
    }
    if (res.ok) {
      const name = /filename="([^"]+)"/.exec(res.headers.get("Content-Disposition") || "");
      saveBlob(await res.blob(), name ? name[1] : filename);
      return { how: "server", message: "" };
    }
    const body = await res.json().catch(() => null);
    if (res.status === 503 && format !== "csv" && div && window.Plotly) {
      await Plotly.downloadImage(div, { format, width, height, filename: kind,
                                        scale: format === "png" ? EXPORT.pngScale : 1 });
      return { how: "browser", message: `${apiMessage(body, res)} (Exported in your browser instead.)` };
    }
    throw new Error(apiMessage(body, res));
  }

  function embedSnippet(kind, params, title) {
    const src = `${location.origin}/embed/${kind}?${query(params)}`;
    const safeTitle = String(title || kind).replace(/[<>&"]/g, "");
    return `<iframe src="${src}" width="${EMBED.width}" height="${EMBED.height}" ` +
           `title="${safeTitle}" loading="lazy" style="border:0;max-width:100%"></iframe>`;
  }

  // Clipboard where allowed (secure context, permission); otherwise the caller shows
  // the text. Resolves true when copied.
  async function copyText(text) {
    try {
      await navigator.clipboard.writeText(text);
      return true;
    } catch {
      return false;
    }
  }

  // A short confirmation on a button, then its own label again.
  function flash(button, text, ms = 1500) {
    const old = button.dataset.label || button.textContent;
    button.dataset.label = old;
    button.textContent = text;
    clearTimeout(button._flash);
    button._flash = setTimeout(() => { button.textContent = old; }, ms);
  }

  // Export buttons (SVG, PNG, CSV, embed code) for one figure. `get` returns
  // {kind, params, div, title}; `report(kind, text)` shows a status ("busy", "ok",
  // "error", or null to clear).
  function exportBar(get, report) {
    const bar = el("div", { class: "export-bar", role: "group", "aria-label": "Export this figure" });
    for (const format of ["svg", "png", "csv"]) {
      const b = el("button", { type: "button", class: "export", "data-format": format,
                               title: format === "csv" ? "Download the numbers behind the figure (CSV, units in the header)"
                                                       : `Download the figure as ${format.toUpperCase()}` ,
                               text: format.toUpperCase() });
      b.addEventListener("click", async () => {
        const { kind, params, div, title } = get();
        b.disabled = true;
        report("busy", `exporting ${format.toUpperCase()}…`);
        try {
          const r = await exportFigure(format, kind, params, div);
          report(r.how === "browser" ? "note" : null, r.message);
          if (r.how !== "browser") flash(b, "✓");
          b.setAttribute("aria-label", `${format.toUpperCase()} of ${title || kind}: downloaded`);
        } catch (e) {
          report("error", `Export failed: ${e.message}`);
        } finally {
          b.disabled = false;
        }
      });
      b.setAttribute("aria-label", `Download as ${format.toUpperCase()}`);
      bar.append(b);
    }
    const embed = el("button", { type: "button", class: "export", "data-format": "embed",
                                 title: "Copy an <iframe> snippet showing this figure in its current state",
                                 "aria-label": "Copy embed code", text: "</>" });
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

  /* The API's figures are made to stand alone (title on top, legend below the x axis).
   * On a page the figure's box sets the size, and a legend sits above the axes, clear
   * of the axis titles at any height. keepTitle: the title stays, in the top margin.
   */
  function fitLayout(given, { keepTitle = false } = {}) {
    const layout = { ...given };
    delete layout.width;
    delete layout.height;
    layout.autosize = true;
    layout.margin = { ...(layout.margin || {}) };
    const title = layout.title;
    delete layout.title;
    // Plotly places a title of several <br> lines by its first line: at the top of the
    // container the others push the first out of view. So the first line is the title
    // and the rest its subtitle, which Plotly stacks below it; the margin fits them.
    const text = keepTitle && title ? String(typeof title === "string" ? title : title.text || "") : "";
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
      // a table: its top margin held the title, which a panel shows in its heading
      layout.margin.t = 8 + top;
    } else {
      const legendShown = layout.showlegend !== false;
      layout.margin.t = (legendShown ? 30 : 14) + top;
      layout.margin.b = Math.min(layout.margin.b ?? 50, 46);
      if (legendShown) {
        layout.legend = { ...(layout.legend || {}), orientation: "h", x: 1, xanchor: "right",
                          y: 1.01, yanchor: "bottom", bgcolor: "rgba(255,255,255,0)" };
      }
      for (const k of Object.keys(layout)) {
        if (/^[xy]axis\d*$/.test(k)) layout[k] = { ...layout[k], automargin: true };
      }
    }
    return layout;
  }

  return { API, EXPORT, fitLayout, el, richText, apiMessage, errorLoc, query, exportFigure, embedSnippet,
           copyText, flash, exportBar, saveBlob };
})();
