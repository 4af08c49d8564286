/* The LUT workbench (the tools page): the lookup tables users ship (split sum, Filament's
 * DFG, Kulla-Conty's E and E_avg) for the explorer's model, drawn with the error GET
 * /api/v1/lut states for each (of the table, after quantisation, after bilinear lookup),
 * downloadable in every format it offers; and a user's own table read (POST
 * /api/v1/lut/check infers its conventions — α map, G2, texel placement, axis order,
 * orientation, split form, channels — with each one's margin, and its lookup error).
 * The options are the ones /openapi.json declares for GET /api/v1/lut.
 */
import { API, el, apiMessage } from "../base/dom.js";
import { card } from "./shader.js";

const OPTIONS = ["kind", "size", "mu_axis", "roughness_axis", "quantisation"];
const PLOT_CONFIG = { displaylogo: false, responsive: true };
const fmt = (x) => Number(x).toExponential(2);

function control(p) {
  const id = `lut-${p.name.replace(/_/g, "-")}`;
  const s = p.schema;
  const input = s.enum
    ? el("select", { id, name: p.name }, ...s.enum.map((v) => el("option", { value: v, text: v })))
    : el("input", { id, name: p.name, type: "number", min: s.minimum, max: s.maximum, step: "1" });
  input.value = String(s.default ?? (s.enum ? s.enum[0] : ""));
  input.title = s.description || "";
  return { name: p.name, input, appliesTo: s["x-applies-to"],
           row: el("label", { for: id }, p.name.replace(/_/g, " "), input) };
}

function drawTable(plot, body) {
  const [rows, cols] = body.axes;
  const title = (c) => `${c} (${body.usage})`;
  if (!cols) {          // one axis: a curve per channel
    const traces = body.channels.map((c, k) => ({ type: "scatter", mode: "lines+markers", name: c,
      x: rows.values, y: body.values.map((v) => v[k]) }));
    return Plotly.react(plot, traces, { title: { text: title(body.channels.join(", ")), x: 0.02, font: { size: 13 } },
      xaxis: { title: { text: rows.name } }, margin: { l: 55, r: 10, t: 40, b: 45 } }, PLOT_CONFIG);
  }
  const n = body.channels.length;
  const traces = body.channels.map((c, k) => ({ type: "heatmap", name: c, x: cols.values, y: rows.values,
    z: body.values.map((row) => row.map((v) => v[k])), xaxis: `x${k ? k + 1 : ""}`, yaxis: `y${k ? k + 1 : ""}`,
    colorscale: "Viridis", colorbar: { x: (k + 1) / n - 0.02, len: 0.9, thickness: 10 } }));
  const layout = { title: { text: `${body.kind}: ${body.usage}`, x: 0.02, font: { size: 13 } },
                   margin: { l: 55, r: 30, t: 40, b: 45 }, annotations: [] };
  body.channels.forEach((c, k) => {
    const s = k ? k + 1 : "";
    layout[`xaxis${s}`] = { domain: [k / n + 0.02, (k + 1) / n - 0.08], title: { text: cols.name }, anchor: `y${s}` };
    layout[`yaxis${s}`] = { title: { text: k ? "" : rows.name }, anchor: `x${s}` };
    layout.annotations.push({ text: c, xref: "paper", yref: "paper", x: (k + 0.5) / n, y: 1.0, showarrow: false,
                              yanchor: "bottom", font: { size: 12 } });
  });
  return Plotly.react(plot, traces, layout, PLOT_CONFIG);
}

function errorTable(body) {
  const head = el("tr", {}, el("th", { text: "error (max over texels)" }), ...body.channels.map((c) => el("th", { text: c })));
  const row = (label, part) => el("tr", {}, el("td", { text: label }),
    ...body.channels.map((c) => el("td", { text: fmt(body.error[part].max[c]) })));
  return el("table", { class: "tools-table", id: "lut-errors" }, head,
            row("the table's values", "table"), row(`stored as ${body.quantisation}`, "quantised"),
            row("read with bilinear lookup", "lookup"));
}

/** The workbench's section. modelFor(path) -> URLSearchParams of the model for that endpoint. */
export async function lutSection(modelFor, spec) {
  const declared = spec.paths[`${API}/lut`].get.parameters;
  const controls = OPTIONS.map((name) => declared.find((p) => p.name === name)).filter(Boolean).map(control);
  const formats = declared.find((p) => p.name === "format")?.schema.enum.filter((f) => f !== "json") || [];
  const build = el("button", { type: "button", class: "export", id: "lut-build", text: "Build the table" });
  const status = el("p", { class: "tools-status", id: "lut-status", role: "status" });
  const plot = el("div", { id: "lut-plot", class: "tools-plot", hidden: true });
  const errors = el("div", { id: "lut-error-box" });
  const downloads = el("div", { class: "tools-downloads", id: "lut-downloads" });
  const upload = el("input", { type: "file", id: "lut-upload", accept: ".png,.json,image/png,application/json" });
  const checked = el("div", { id: "lut-check", role: "status" });

  const options = () => {
    const kind = controls.find((c) => c.name === "kind")?.input.value;
    const out = {};
    for (const c of controls) {
      const applies = !c.appliesTo || Object.entries(c.appliesTo).every(([k, allowed]) => k !== "kind" || allowed.includes(kind));
      c.row.hidden = !applies;
      if (applies) out[c.name] = c.input.value;
    }
    return out;
  };
  const fullQuery = async (extra) => {
    const q = await modelFor(`${API}/lut`);
    for (const [k, v] of Object.entries({ ...options(), ...extra })) q.set(k, v);
    return q;
  };
  const run = async () => {
    status.textContent = "building…";
    status.classList.remove("failed");
    build.disabled = true;
    try {
      const q = await fullQuery({ per_texel: "false" });
      const res = await fetch(`${API}/lut?${q}`, { headers: { Accept: "application/json" } });
      const body = await res.json().catch(() => null);
      if (!res.ok || !body) throw new Error(apiMessage(body, res));
      plot.hidden = false;
      await drawTable(plot, body);
      errors.replaceChildren(errorTable(body), el("p", { class: "tools-status", text: body.orientation }));
      downloads.replaceChildren(el("span", { text: "Download:" }));
      for (const f of formats) {
        const url = `${API}/lut?${await fullQuery({ format: f })}`;
        downloads.append(el("a", { class: "export", href: url, download: "", text: f.toUpperCase() }));
      }
      status.textContent = `${body.size} texels per axis, built in ${body.build.seconds.toFixed(2)} s `
        + `(${body.build.evaluations.toLocaleString("en")} evaluations); reference: ${body.error.reference}.`;
      plot.dataset.kind = body.kind;
    } catch (e) {
      status.textContent = `Not built: ${e.message}`;
      status.classList.add("failed");
    } finally {
      build.disabled = false;
    }
  };
  build.addEventListener("click", run);
  for (const c of controls) c.input.addEventListener("change", options);
  upload.addEventListener("change", async () => {
    const file = upload.files[0];
    if (!file) return;
    checked.textContent = `Checking ${file.name}…`;
    const q = await fullQuery({});
    q.delete("size");                      // read from the upload
    const res = await fetch(`${API}/lut/check?${q}`, { method: "POST", body: file,
      headers: { "Content-Type": file.type || (file.name.endsWith(".json") ? "application/json" : "image/png") } });
    const body = await res.json().catch(() => null);
    if (!res.ok || !body) {
      checked.textContent = `Not checked: ${apiMessage(body, res)}`;
      return;
    }
    const max = body.channels.map((c, k) => `${c} ${fmt(body.error.max[k])}`).join(", ");
    const margin = (name) => {
      const m = body.fit.margins[name];
      return m ? ` (next: ${m.runner_up}, ${m.ratio === null ? "exact fit" : `×${m.ratio.toPrecision(3)} worse`})` : "";
    };
    const found = el("table", { class: "tools-table", id: "lut-conventions" },
      el("tr", {}, el("th", { text: "convention" }), el("th", { text: "inferred" }), el("th", { text: "query" })),
      ...Object.entries(body.conventions).map(([name, value]) => el("tr", {},
        el("td", { text: name.replace(/_/g, " ") }), el("td", { text: value + margin(name) }),
        el("td", { text: body.expected[name] ?? "" }))));
    checked.replaceChildren(
      el("p", { text: `${file.name}: ${body.size} texels per axis, ${body.storage}; best of ${body.fit.hypotheses} `
                      + `hypotheses, residual ${fmt(body.fit.residual_rms)} RMS (runner-up ×`
                      + `${body.fit.runner_up.ratio === null ? "∞" : body.fit.runner_up.ratio.toPrecision(3)}). `
                      + `Bilinear lookup error ${max} (the reference's own bound `
                      + `${body.channels.map((c, k) => fmt(body.error.reference_bound[k])).join(", ")}).` }),
      found,
      el("p", { class: body.diagnosis ? "tools-status failed" : "tools-status",
                text: body.diagnosis ? `Diagnosis: ${body.diagnosis}.` : "The table follows the query's conventions." }));
  });
  options();
  return card("lut", "Lookup tables",
    "The tables shaders sample (split sum, Filament's DFG, Kulla-Conty's E and E_avg) for the model's NDF, masking and G2, "
    + "each with its error against the converged integral. Download one, or check your own against it.",
    el("div", { class: "tools-row" }, ...controls.map((c) => c.row), build), status, plot, errors, downloads,
    el("div", { class: "tools-row" }, el("label", { for: "lut-upload", text: "Check your own table (PNG or JSON)" }), upload),
    checked);
}
