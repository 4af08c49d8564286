/* For shader writers (the tools page, tools.js): the model as GLSL / HLSL / Python,
 * measured materials with their RGB Fresnel, and what "roughness" means in each engine.
 * Each section takes the model as a query (tools.js: the page's link, kept to the
 * parameters each endpoint declares) and builds its own nodes.
 */
import { API, el, getJSON, apiMessage, copyText } from "../base/dom.js";

const LANGS = [["glsl", "GLSL"], ["hlsl", "HLSL"], ["python", "Python"]];
const CHANNEL_COLORS = ["#D55E00", "#009E73", "#0072B2"];
const FORM_DASH = { exact: "solid", schlick: "dash", f82_tint: "dot", gulbrandsen: "dashdot" };
const PLOT_CONFIG = { displaylogo: false, responsive: true };

export const card = (id, title, intro, ...kids) =>
  el("section", { class: "tools-card", id, "aria-labelledby": `${id}-h` },
     el("h2", { id: `${id}-h`, text: title }), intro ? el("p", { text: intro }) : null, ...kids);

/** The model as code: one button per language, the code below (and on the clipboard).
 * modelFor(path) -> URLSearchParams of the model for that endpoint. */
export function codeSection(modelFor) {
  const out = el("textarea", { id: "shader-code", class: "tools-code", readonly: "", rows: "14", spellcheck: "false",
                               "aria-label": "generated code" });
  const status = el("p", { class: "tools-status", id: "code-status", role: "status" });
  const buttons = LANGS.map(([lang, label]) => {
    const b = el("button", { type: "button", class: "export", "data-lang": lang, text: label });
    b.addEventListener("click", async () => {
      status.textContent = "generating…";
      status.classList.remove("failed");
      try {
        const q = await modelFor(`${API}/code`);
        q.set("lang", lang);
        const res = await fetch(`${API}/code?${q}`);
        const text = await res.text();
        if (!res.ok) throw new Error(apiMessage(JSON.parse(text), res));
        out.value = text;
        const copied = await copyText(text);
        status.textContent = `${label}: ${text.split("\n").length} lines`
          + (copied ? ", copied to the clipboard" : " (select and copy below)");
      } catch (e) {
        status.textContent = `Could not generate: ${e.message}`;
        status.classList.add("failed");
      }
    });
    return b;
  });
  return card("code", "The model as code",
    "Self-contained GLSL, HLSL or Python of the explorer's model, with its parameters as constants.",
    el("div", { class: "tools-row" }, el("span", { text: "Copy the model as" }), ...buttons), status, out);
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
                   xaxis: { title: { text: "θ_d (degrees)" }, range: [0, 90] }, yaxis: { title: { text: "F" }, range: [0, 1.02] },
                   margin: { l: 55, r: 10, t: 40, b: 45 }, legend: { orientation: "v", x: 1.02, y: 1 } };
  return { traces, layout };
}

function errorTable(body) {
  const head = el("tr", {}, el("th", { text: "form" }),
    ...body.channels.map((c) => el("th", { text: `max |ΔF| ${c.toUpperCase()}` })),
    ...body.channels.map((c) => el("th", { text: `ΔE_avg ${c.toUpperCase()}` })));
  const rows = Object.entries(body.errors).map(([form, e]) => el("tr", {}, el("td", { text: form }),
    ...e.F_max.map((x) => el("td", { text: x.toExponential(2) })), ...e.E_avg.map((x) => el("td", { text: x.toExponential(2) }))));
  return el("table", { class: "tools-table", id: "material-errors" }, head, ...rows);
}

/** A measured material's RGB Fresnel beside Schlick, F82-tint and Gulbrandsen, a lit
 * sphere of it and the fits' errors; `initial`: the slug to show first (the link's). */
export async function materialSection(modelFor, initial) {
  const select = el("select", { id: "shader-material", "aria-label": "material preset" });
  select.append(el("option", { value: "", text: "— choose a material —" }));
  const plot = el("div", { id: "material-plot", class: "tools-plot" });
  const sphere = el("div", { id: "material-sphere", class: "tools-sphere" });
  const errors = el("div", { id: "material-table" });
  const status = el("p", { class: "tools-status", role: "status" });
  try {
    const list = await getJSON("/materials");
    for (const [kind, label] of [["conductor", "Metals (RGB n, k)"], ["dielectric", "Dielectrics (index)"]]) {
      const options = list.materials.filter((x) => x.kind === kind).map((m) => el("option", { value: m.slug, text: m.name }));
      select.append(el("optgroup", { label }, ...options));
    }
    status.textContent = `Materials: ${list.source}; ${list.license}.`;
  } catch (e) {
    status.textContent = `Materials unavailable: ${e.message}`;
    status.classList.add("failed");
  }
  const show = async () => {
    const slug = select.value;
    plot.hidden = sphere.hidden = !slug;
    if (!slug) { errors.replaceChildren(); return; }
    try {
      const q = await modelFor(`${API}/materials/fresnel`);
      q.set("material", slug);
      const qs = await modelFor(`${API}/materials/sphere`);
      qs.set("material", slug);
      const [body, lit] = await Promise.all([getJSON(`/materials/fresnel?${q}`), getJSON(`/materials/sphere?${qs}`)]);
      const fig = fresnelFigure(body);
      await Plotly.react(plot, fig.traces, fig.layout, PLOT_CONFIG);
      await Plotly.react(sphere, [{ type: "image", z: lit.rgb, hoverinfo: "skip" }],
        { title: { text: `${body.material.name}, lit at 45° (sRGB; max L/E ${lit.max.toFixed(2)})`, x: 0.02, font: { size: 13 } },
          xaxis: { visible: false }, yaxis: { visible: false, scaleanchor: "x" }, margin: { l: 10, r: 10, t: 40, b: 10 } },
        { ...PLOT_CONFIG, staticPlot: true });
      errors.replaceChildren(el("p", { text: "Error of each fit against the exact Fresnel, and its error in E_avg of the model's lobe:" }),
                             errorTable(body));
      errors.dataset.material = slug;
    } catch (e) {
      status.textContent = `Material: ${e.message}`;
      status.classList.add("failed");
    }
  };
  select.addEventListener("change", show);
  if (initial && [...select.options].some((o) => o.value === initial)) select.value = initial;
  plot.hidden = sphere.hidden = true;
  const section = card("materials", "Measured materials",
    "The exact RGB Fresnel of a measured metal or dielectric, and how closely the artists' fits (Schlick, F82-tint, "
    + "Gulbrandsen) follow it. In the explorer, choose the material in the Model menu to draw every panel with it.",
    el("div", { class: "tools-row" }, el("label", { for: "shader-material", text: "Material" }), select), status,
    el("div", { class: "tools-figures" }, plot, sphere), errors);
  return { section, show };
}

/** One roughness r: the α each ecosystem means, with its lobe, and the table of them. */
export function conventionsSection() {
  const slider = el("input", { type: "range", id: "conventions-roughness", min: "0", max: "1", step: "0.01", value: "0.5",
                               "aria-label": "roughness r" });
  const value = el("output", { for: "conventions-roughness", text: "0.50" });
  const plot = el("div", { id: "conventions-plot", class: "tools-plot tall" });
  const table = el("table", { class: "tools-table", id: "conventions-table" });
  let timer = 0;
  const draw = async () => {
    const r = slider.value;
    value.textContent = Number(r).toFixed(2);
    const [fig, rows] = await Promise.all([getJSON(`/conventions/figure?roughness=${r}`), getJSON(`/conventions?roughness=${r}`)]);
    await Plotly.react(plot, fig.data, { ...fig.layout, height: undefined, autosize: true }, PLOT_CONFIG);
    table.replaceChildren(el("tr", {}, el("th", { text: "ecosystem" }), el("th", { text: "α" }), el("th", { text: "k (G)" }),
                             el("th", { text: "note" })),
      ...rows.map((row) => el("tr", {}, el("td", { text: row.ecosystem }), el("td", { text: row.alpha.toPrecision(4) }),
                              el("td", { text: row.k === undefined ? "" : row.k.toPrecision(4) }),
                              el("td", { class: "note", text: row.note }))));
    plot.dataset.roughness = r;
  };
  slider.addEventListener("input", () => { clearTimeout(timer); timer = setTimeout(draw, 120); });
  const section = card("conventions", "Which roughness? α per ecosystem",
    "The same roughness slider value means a different α in each engine and paper: the α each one takes, and the lobe it draws.",
    el("div", { class: "tools-row" }, el("label", { for: "conventions-roughness", text: "Roughness r" }), slider, value),
    plot, table);
  return { section, draw };
}
