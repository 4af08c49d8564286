/* A Disney BRDF Explorer `.brdf` file, read: its parameter block and its shader.
 *
 *   analytic                              (optional first word: the file's kind)
 *   ::begin parameters
 *   float alphaG 0.001 1 .1               name, minimum, maximum, default
 *   bool useFresnel 0                     name, default (0/1)
 *   color Cd .82 .67 .16                  name, default r g b
 *   ::end parameters
 *   ::begin shader
 *   vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y) { ... }   f, no cosine
 *   ::end shader
 *
 * (the format as the explorer's public documentation describes it). Errors name the line.
 */

/** Largest file accepted, bytes: the analytic files are a few KB; this keeps a dropped
 * image or data file from being compiled as GLSL. */
export const MAX_BYTES = 64 * 1024;

const NAME = /^[A-Za-z_][A-Za-z0-9_]*$/;
const RESERVED = new Set(["L", "V", "N", "X", "Y", "brdf", "BRDF", "main", "color"]);

export class BrdfFileError extends Error {
  constructor(message, line = null) {
    super(line ? `line ${line}: ${message}` : message);
    this.line = line;
  }
}

const num = (word, line, what) => {
  const x = Number(word);
  if (word === undefined || word === "" || !Number.isFinite(x)) throw new BrdfFileError(`${what}: “${word ?? ""}” is not a number`, line);
  return x;
};

function parameter(words, line) {
  const [type, name, ...rest] = words;
  if (!NAME.test(name || "")) throw new BrdfFileError(`“${name ?? ""}” is not a parameter name`, line);
  if (RESERVED.has(name)) throw new BrdfFileError(`“${name}” is taken by the BRDF's own arguments`, line);
  if (type === "float") {
    if (rest.length !== 3) throw new BrdfFileError(`float ${name}: give minimum, maximum and default`, line);
    const [lo, hi, def] = rest.map((w, i) => num(w, line, `float ${name} ${["minimum", "maximum", "default"][i]}`));
    if (!(lo < hi)) throw new BrdfFileError(`float ${name}: the minimum ${lo} is not below the maximum ${hi}`, line);
    return { type, name, lo, hi, default: Math.min(hi, Math.max(lo, def)) };
  }
  if (type === "bool") {
    if (rest.length !== 1) throw new BrdfFileError(`bool ${name}: give its default, 0 or 1`, line);
    return { type, name, default: num(rest[0], line, `bool ${name}`) !== 0 };
  }
  if (type === "color") {
    if (rest.length !== 3) throw new BrdfFileError(`color ${name}: give its default r g b`, line);
    return { type, name, default: rest.map((w) => Math.min(1, Math.max(0, num(w, line, `color ${name}`)))) };
  }
  throw new BrdfFileError(`“${type}”: a parameter is float, bool or color`, line);
}

/** {params: [...], shader: text, shaderLine: the file's line of the shader's first line}. */
export function parseBrdf(text) {
  if (typeof text !== "string") throw new BrdfFileError("not a text file");
  if (new TextEncoder().encode(text).length > MAX_BYTES) throw new BrdfFileError(`the file is over ${MAX_BYTES / 1024} KB`);
  if (text.includes("\0")) throw new BrdfFileError("not a text file (it holds NUL bytes)");
  const lines = text.replace(/\r\n?/g, "\n").split("\n");
  const params = [];
  let block = null, shader = [], shaderLine = null, sawParams = false, sawShader = false;
  lines.forEach((raw, i) => {
    const line = i + 1;
    const t = raw.trim();
    const marker = t.match(/^::\s*(begin|end)\s+(\w+)/);
    if (marker) {
      const [, edge, what] = marker;
      if (!["parameters", "shader"].includes(what)) throw new BrdfFileError(`unknown block “${what}”`, line);
      if (edge === "begin") {
        if (block) throw new BrdfFileError(`::begin ${what} inside ${block}`, line);
        block = what;
        if (what === "shader") { sawShader = true; shaderLine = line + 1; }
        else sawParams = true;
      } else {
        if (block !== what) throw new BrdfFileError(`::end ${what} without its ::begin`, line);
        block = null;
      }
      return;
    }
    if (block === "shader") { shader.push(raw); return; }
    if (block === "parameters") {
      if (!t || t.startsWith("#") || t.startsWith("//")) return;
      const p = parameter(t.split(/\s+/), line);
      if (params.some((q) => q.name === p.name)) throw new BrdfFileError(`${p.name} is declared twice`, line);
      params.push(p);
    }
  });
  if (block) throw new BrdfFileError(`::begin ${block} is never ended`);
  if (!sawShader) throw new BrdfFileError("no ::begin shader … ::end shader block: is this a .brdf file?");
  if (!sawParams && !params.length) { /* a shader without parameters is fine */ }
  if (!/\bvec3\s+BRDF\s*\(/.test(shader.join("\n"))) throw new BrdfFileError("the shader defines no vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y)", shaderLine);
  return { params, shader: shader.join("\n"), shaderLine };
}

/** The default value of every parameter, by name. */
export const defaults = (params) => Object.fromEntries(params.map((p) => [p.name, p.default]));

/** Of `values` (a link's, or the sliders' before an edit), those that fit `params` (same
 * name and type), by name. With `before` (the parameters they were set under), only those
 * whose declaration is unchanged: a default typed anew in the editor is the value wanted. */
export function carried(params, values, before = null) {
  const was = new Map((before || []).map((p) => [p.name, JSON.stringify(p)]));
  const fits = (p, v) => v !== undefined && typeof v === typeof p.default && Array.isArray(v) === Array.isArray(p.default);
  return Object.fromEntries(params.filter((p) => fits(p, values?.[p.name]) && (!before || was.get(p.name) === JSON.stringify(p)))
    .map((p) => [p.name, values[p.name]]));
}
