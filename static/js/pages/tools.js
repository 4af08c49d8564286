/* The shader-tools page (/tools?<the explorer's query>): the model as code,
 * measured materials, roughness conventions and the LUT workbench, on a page of their own
 * so that they never cover the explorer's plots. The model is the link's: the explorer's
 * "Shader tools" link carries its state; each endpoint gets the parameters it declares
 * in /openapi.json.
 */
import { $ } from "../base/dom.js";
import { codeSection, materialSection, conventionsSection } from "./shader.js";
import { lutSection } from "./lut.js";

const link = new URLSearchParams(location.search);
// the explorer's own parameters (panels, pins, embedding), not the model's
const PAGE_ONLY = new Set(["show", "vary", "values", "pin", "embed", "lobe3d"]);

async function boot() {
  const spec = await fetch("/openapi.json").then((r) => r.json());
  /** The link's model parameters that GET `path` declares. */
  const modelFor = async (path) => {
    const declared = new Set((spec.paths[path]?.get?.parameters || []).map((p) => p.name));
    const q = new URLSearchParams();
    for (const [k, v] of link) if (declared.has(k) && !PAGE_ONLY.has(k)) q.set(k, v);
    return q;
  };
  const model = [...link].filter(([k]) => !PAGE_ONLY.has(k) && !k.includes("."));
  $("#tools-model").textContent = model.length
    ? `The model: ${model.map(([k, v]) => `${k}=${v}`).join(", ")} (from the explorer's link).`
    : "The model: the explorer's defaults (open this page from the explorer's “Shader tools” link to carry its model).";
  $("#back-to-explorer").href = `/${location.search}`;
  const main = $("#tools");
  const materials = await materialSection(modelFor, link.get("material"));
  const conventions = conventionsSection();
  main.append(codeSection(modelFor), materials.section, conventions.section, await lutSection(modelFor, spec));
  await Promise.all([conventions.draw(), materials.show()]);
  main.dataset.ready = "1";
  // a link to one section (/tools#lut, the gallery's): the sections did not exist at load
  if (location.hash) document.getElementById(location.hash.slice(1))?.scrollIntoView();
}

boot();
