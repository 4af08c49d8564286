/* For shader writers: the page's model as GLSL / HLSL / Python, measured materials and
 * their RGB Fresnel, and what "roughness" means in each ecosystem.
 *
 * Self-contained: it reads the page's model from window.__brdf (a panel's request URL,
 * kept to the parameters GET /api/v1/code declares in /openapi.json) and writes nothing
 * of the page's state. Plotly is the page's global.
 */
const API = "/api/v1";
const LANGS = [["glsl", "GLSL"], ["hlsl", "HLSL"], ["python", "Python"]];
const FRESNEL_PARAMS = ["fresnel", "f0", "f90", "fresnel_p", "ior", "k"];
const CHANNEL_COLORS = ["#D55E00", "#009E73", "#0072B2"];
const FORM_DASH = { exact: "solid", schlick: "dash", f82_tint: "dot", gulbrandsen: "dashdot" };

let codeParams = null;

function el(tag, attrs = {}, ...children) {
  const node = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (k === "text") node.textContent = v;
    else node.setAttribute(k, v);
  }
  for (const c of children) node.append(c);
  return node;
}

async function getJson(url) {
  const res = await fetch(url, { headers: { Accept: "application/json" } });
  const body = await res.json();
  if (!res.ok) throw new Error(body.detail?.[0]?.msg || `HTTP ${res.status}`);
  return body;
}

/** The page's model as the query GET /api/v1/code takes (material added when chosen). */
async function modelQuery(material) {
  if (!codeParams) {
    const spec = await getJson("/openapi.json");
    codeParams = new Set(spec.paths[`${API}/code`].get.parameters.map((p) => p.name));
  }
  const page = window.__brdf;
  const panels = page?.panels ? page.panels() : [];
  const panel = panels.find((p) => p.visible) || panels[0];
  const source = new URL((panel && page.url(panel.name)) || location.href, location.href).searchParams;
  const q = new URLSearchParams();
  for (const [k, v] of source) if (codeParams.has(k) && k !== "lang") q.set(k, v);
  if (material) {
    for (const name of FRESNEL_PARAMS) q.delete(name);
    q.set("material", material);
  }
  return q;
}

function codeBlock(section, status) {
  const out = el("textarea", { id: "shader-code", readonly: "", rows: "12", spellcheck: "false",
                               "aria-label": "generated code", style: "width: 100%; font-family: monospace;" });
  const buttons = LANGS.map(([lang, label]) => {
    const b = el("button", { type: "button", "data-lang": lang, text: label });
    b.addEventListener("click", async () => {
      status.textContent = "generating…";
      try {
        const q = await modelQuery(section.dataset.material);
        q.set("lang", lang);
        const res = await fetch(`${API}/code?${q}`);
        const text = await res.text();
        if (!res.ok) throw new Error(JSON.parse(text).detail?.[0]?.msg || `HTTP ${res.status}`);
        out.value = text;
        let copied = false;
        try { await navigator.clipboard.writeText(text); copied = true; } catch (e) { copied = false; }
        status.textContent = `${label}: ${text.split("\n").length} lines` +
          (copied ? ", copied to the clipboard" : " (select and copy below)");
      } catch (e) {
        status.textContent = `could not generate: ${e.message}`;
      }
    });
    return b;
  });
  return [el("div", { class: "shader-row" }, el("span", { text: "Copy the model as " }), ...buttons), out];
}

function fresnelFigure(body) {
  const traces = [];
  for (const [form, rgb] of Object.entries(body.F)) {
    body.channels.forEach((ch, c) => {
      traces.push({ type: "scatter", mode: "lines", x: body.theta_deg, y: rgb.map((row) => row[c]),
                    name: `${form} ${ch.toUpperCase()}`, legendgroup: form,
                    line: { color: CHANNEL_COLORS[c], dash: FORM_DASH[form] || "solid", width: form === "exact" ? 2.5 : 1.5 } });
    });
  }
  const layout = { title: { text: `${body.material.name}: Fresnel per RGB channel, exact and the artists' fits`, x: 0.02, font: { size: 14 } },
                   xaxis: { title: { text: "θ_d (degrees)" } }, yaxis: { title: { text: "F" }, range: [0, 1.02] },
                   margin: { l: 55, r: 10, t: 40, b: 45 }, legend: { orientation: "h", y: -0.2 }, height: 380 };
  return { traces, layout };
}

function errorTable(body) {
  const table = el("table", { class: "shader-table", id: "material-errors", style: "border-collapse: collapse;" });
  table.append(el("tr", {}, el("th", { text: "form" }), ...body.channels.map((c) => el("th", { text: `max |ΔF| ${c.toUpperCase()}` })),
                  ...body.channels.map((c) => el("th", { text: `ΔE_avg ${c.toUpperCase()}` }))));
  for (const [form, e] of Object.entries(body.errors)) {
    table.append(el("tr", {}, el("td", { text: form }), ...e.F_max.map((x) => el("td", { text: x.toExponential(2) })),
                    ...e.E_avg.map((x) => el("td", { text: x.toExponential(2) }))));
  }
  return table;
}

async function materialBlock(section, status) {
  const select = el("select", { id: "shader-material", "aria-label": "material preset" });
  select.append(el("option", { value: "", text: "— the page's Fresnel —" }));
  const plot = el("div", { id: "material-plot" });
  const sphere = el("div", { id: "material-sphere" });
  const errors = el("div", { id: "material-table" });
  const source = el("p", { class: "shader-source" });
  try {
    const list = await getJson(`${API}/materials`);
    for (const kind of ["conductor", "dielectric"]) {
      const group = el("optgroup", { label: kind === "conductor" ? "Metals (RGB n, k)" : "Dielectrics (index)" });
      for (const m of list.materials.filter((x) => x.kind === kind)) group.append(el("option", { value: m.slug, text: m.name }));
      select.append(group);
    }
    source.textContent = `Materials: ${list.source}; ${list.license}.`;
  } catch (e) {
    status.textContent = `materials unavailable: ${e.message}`;
  }
  select.addEventListener("change", async () => {
    section.dataset.material = select.value;
    if (!select.value) {
      window.Plotly.purge(plot);
      window.Plotly.purge(sphere);
      errors.replaceChildren();
      return;
    }
    try {
      const q = await modelQuery(select.value);
      const [body, lit] = await Promise.all([getJson(`${API}/materials/fresnel?${q}`),
                                             getJson(`${API}/materials/sphere?${q}`)]);
      const fig = fresnelFigure(body);
      await window.Plotly.react(plot, fig.traces, fig.layout, { displaylogo: false, responsive: true });
      await window.Plotly.react(sphere, [{ type: "image", z: lit.rgb, hoverinfo: "skip" }],
        { title: { text: `${body.material.name}, lit at 45° (sRGB; max L/E ${lit.max.toFixed(2)})`, x: 0.02, font: { size: 14 } },
          xaxis: { visible: false }, yaxis: { visible: false, scaleanchor: "x" }, width: 360, height: 380,
          margin: { l: 10, r: 10, t: 40, b: 10 } }, { displaylogo: false, staticPlot: true });
      errors.replaceChildren(el("p", { text: "Error of each fit against the exact Fresnel, and its error in E_avg of the page's lobe:" }),
                             errorTable(body));
    } catch (e) {
      status.textContent = `material: ${e.message}`;
    }
  });
  return [source, el("div", { class: "shader-row" }, el("label", { for: "shader-material", text: "Material " }), select),
          el("div", { style: "display: flex; flex-wrap: wrap; gap: 1em; align-items: flex-start;" },
             el("div", { style: "flex: 1 1 520px; min-width: 0;" }, plot), sphere), errors];
}

function conventionsBlock() {
  const slider = el("input", { type: "range", id: "conventions-roughness", min: "0", max: "1", step: "0.01", value: "0.5",
                               "aria-label": "roughness" });
  const value = el("output", { for: "conventions-roughness", text: "0.50" });
  const plot = el("div", { id: "conventions-plot" });
  const table = el("table", { class: "shader-table", id: "conventions-table",
                              style: "border-collapse: collapse; font-size: 0.9em;" });
  let timer = null;
  const draw = async () => {
    const r = slider.value;
    value.textContent = Number(r).toFixed(2);
    const [fig, rows] = await Promise.all([getJson(`${API}/conventions/figure?roughness=${r}`),
                                           getJson(`${API}/conventions?roughness=${r}`)]);
    await window.Plotly.react(plot, fig.data, fig.layout, { displaylogo: false, responsive: true });
    table.replaceChildren(el("tr", {}, el("th", { text: "ecosystem" }), el("th", { text: "α" }), el("th", { text: "k (G)" }),
                             el("th", { text: "note" })));
    for (const row of rows) {
      table.append(el("tr", {}, el("td", { text: row.ecosystem }), el("td", { text: row.alpha.toPrecision(4) }),
                      el("td", { text: row.k === undefined ? "" : row.k.toPrecision(4) }), el("td", { text: row.note })));
    }
  };
  slider.addEventListener("input", () => { clearTimeout(timer); timer = setTimeout(draw, 120); });
  return { nodes: [el("div", { class: "shader-row" }, el("label", { for: "conventions-roughness", text: "Roughness r " }), slider, value),
                   plot, table], draw };
}

async function mount() {
  // Closed, it is one line under the figures (the column is the window's height and the
  // panels take the rest); open, its body scrolls within 70 % of the window.
  const main = document.querySelector("main");
  const section = el("details", { id: "shader-tools", class: "shader-tools", "aria-label": "For shader writers",
                                  style: "flex: none; padding: 0.3em 1em; border-top: 1px solid #ddd;" });
  const body = el("div", { style: "max-height: 70vh; overflow: auto; padding-bottom: 1em;" });
  section.append(el("summary", { text: "For shader writers: the model as code, measured materials, roughness conventions",
                                 style: "cursor: pointer; font-weight: 600;" }), body);
  const status = el("p", { class: "shader-status", role: "status", text: "" });
  body.append(...codeBlock(section, status), status);
  body.append(el("h3", { text: "Measured materials" }), ...(await materialBlock(section, status)));
  const conventions = conventionsBlock();
  body.append(el("h3", { text: "Which roughness? α per ecosystem" }), ...conventions.nodes);
  if (main) main.after(section); else document.body.append(section);
  // Plotly sizes a plot by its container: draw once the section is open, not while hidden
  section.addEventListener("toggle", async () => {
    if (section.open && !section.dataset.ready) {
      await conventions.draw();
      section.dataset.ready = "1";
    }
  });
}

mount();
