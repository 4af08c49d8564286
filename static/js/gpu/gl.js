/* WebGL2 plumbing for the GPU views: a context with float render targets, programs
 * compiled with their errors mapped to the user's own line numbers, a full-screen
 * triangle, and a float32 target read back. Nothing here knows what a BRDF is.
 */

/** One triangle covering the viewport (no buffers: positions from gl_VertexID). */
export const FULLSCREEN_VS = `#version 300 es
void main() {
  vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
  gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}`;

/** A WebGL2 context able to render into RGBA32F (EXT_color_buffer_float), or a
 * sentence saying why not. */
export function makeContext(canvas) {
  const gl = canvas.getContext("webgl2", { antialias: false, premultipliedAlpha: false, preserveDrawingBuffer: true });
  if (!gl) return { why: "this browser has no WebGL2" };
  if (!gl.getExtension("EXT_color_buffer_float")) return { why: "this browser's WebGL2 cannot render to float targets (no EXT_color_buffer_float)" };
  return { gl };
}

/** A compile or link failure: `lines` holds [{line, text}] in the caller's numbering. */
export class ShaderError extends Error {
  constructor(message, lines) {
    super(message);
    this.lines = lines;
  }
}

/** GLSL's info log ("ERROR: 0:12: 'x' : undeclared identifier") with each line number
 * moved by `offset` (the lines the caller's source was placed after) — the user sees
 * the line of their own text. */
export function mapLog(log, offset, limit = Infinity) {
  const lines = [];
  for (const raw of String(log || "").split("\n")) {
    const m = raw.match(/^(?:ERROR|WARNING):\s*\d+:(\d+):\s*(.*)$/);
    if (!m) {
      if (raw.trim()) lines.push({ line: null, text: raw.trim() });
      continue;
    }
    const at = Number(m[1]) - offset;
    lines.push(at >= 1 && at <= limit ? { line: at, text: m[2] } : { line: null, text: m[2] });
  }
  return lines;
}

function compileShader(gl, type, src, offset, limit) {
  const s = gl.createShader(type);
  gl.shaderSource(s, src);
  gl.compileShader(s);
  if (!gl.getShaderParameter(s, gl.COMPILE_STATUS) && !gl.isContextLost()) {
    const log = gl.getShaderInfoLog(s);
    gl.deleteShader(s);
    const lines = mapLog(log, offset, limit);
    const text = lines.map((x) => (x.line ? `line ${x.line}: ${x.text}` : x.text)).join("\n");
    throw new ShaderError(`the shader does not compile:\n${text}`, lines);
  }
  return s;
}

/** A linked program from a vertex and a fragment source; `offset` lines of the fragment
 * source come before the user's `limit` lines (for the error's line numbers). */
export function program(gl, vs, fs, { offset = 0, limit = Infinity } = {}) {
  const p = gl.createProgram();
  const v = compileShader(gl, gl.VERTEX_SHADER, vs, 0, Infinity);
  const f = compileShader(gl, gl.FRAGMENT_SHADER, fs, offset, limit);
  gl.attachShader(p, v);
  gl.attachShader(p, f);
  gl.linkProgram(p);
  gl.deleteShader(v);
  gl.deleteShader(f);
  if (!gl.getProgramParameter(p, gl.LINK_STATUS) && !gl.isContextLost()) {
    const log = gl.getProgramInfoLog(p);
    gl.deleteProgram(p);
    throw new ShaderError(`the shader does not link: ${log}`, mapLog(log, offset, limit));
  }
  return p;
}

/** An RGBA32F texture of w×h (nearest filtering: texels are samples, not an image). */
export function floatTexture(gl, w, h, data = null) {
  const t = gl.createTexture();
  gl.bindTexture(gl.TEXTURE_2D, t);
  for (const [k, v] of [[gl.TEXTURE_MIN_FILTER, gl.NEAREST], [gl.TEXTURE_MAG_FILTER, gl.NEAREST],
                        [gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE], [gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE]]) gl.texParameteri(gl.TEXTURE_2D, k, v);
  gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA32F, w, h, 0, gl.RGBA, gl.FLOAT, data);
  return t;
}

/** A float32 render target: {tex, fb, w, h}. */
export function floatTarget(gl, w, h) {
  const tex = floatTexture(gl, w, h);
  const fb = gl.createFramebuffer();
  gl.bindFramebuffer(gl.FRAMEBUFFER, fb);
  gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, tex, 0);
  const ok = gl.checkFramebufferStatus(gl.FRAMEBUFFER) === gl.FRAMEBUFFER_COMPLETE;
  gl.bindFramebuffer(gl.FRAMEBUFFER, null);
  if (!ok) throw new Error("a float render target is incomplete on this GPU");
  return { tex, fb, w, h };
}

/** The target's texels as float32 RGBA, row 0 at the bottom (GL's order). */
export function readTarget(gl, target) {
  const out = new Float32Array(target.w * target.h * 4);
  gl.bindFramebuffer(gl.FRAMEBUFFER, target.fb);
  gl.readPixels(0, 0, target.w, target.h, gl.RGBA, gl.FLOAT, out);
  gl.bindFramebuffer(gl.FRAMEBUFFER, null);
  return out;
}

/** Sets each named float uniform whose location exists (one the compiler removed as
 * unused has none); numbers → float, arrays of 2–4 → vecN, a data texture ({width,
 * height, data}) → a sampler (bindData), a uniform block ({packing "std140", data}) → a
 * buffer (bindBlock). Locations are looked up once per program
 * (uniformLocation). */
const locations = new WeakMap();
export function uniformLocation(gl, prog, name) {
  let m = locations.get(prog);
  if (!m) locations.set(prog, (m = new Map()));
  if (!m.has(name)) m.set(name, gl.getUniformLocation(prog, name));
  return m.get(name);
}

/** Data textures (/code's JSON "textures": {width, height, format "R32F", data}), one
 * upload per context and value; bound from DATA_UNIT up (units the views' own textures
 * leave free), the active unit restored. */
const DATA_UNIT = 8;
const dataTextures = new WeakMap();
function bindData(gl, loc, v, unit) {
  let m = dataTextures.get(gl);
  if (!m) dataTextures.set(gl, (m = new WeakMap()));
  const active = gl.getParameter(gl.ACTIVE_TEXTURE);
  gl.activeTexture(gl.TEXTURE0 + unit);
  let t = m.get(v);
  if (!t) {
    m.set(v, (t = gl.createTexture()));
    gl.bindTexture(gl.TEXTURE_2D, t);
    for (const [k, x] of [[gl.TEXTURE_MIN_FILTER, gl.NEAREST], [gl.TEXTURE_MAG_FILTER, gl.NEAREST],
                          [gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE], [gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE]]) gl.texParameteri(gl.TEXTURE_2D, k, x);
    gl.pixelStorei(gl.UNPACK_ALIGNMENT, 4);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.R32F, v.width, v.height, 0, gl.RED, gl.FLOAT, new Float32Array(v.data));
  } else gl.bindTexture(gl.TEXTURE_2D, t);
  gl.uniform1i(loc, unit);
  gl.activeTexture(active);
}

/** Uniform blocks (/code's JSON "blocks": {packing "std140", data}: a parameterised
 * shader's tables, app/shader/block.py), one buffer per context and value, bound to
 * binding points from 0 up. */
const blockBuffers = new WeakMap();
function bindBlock(gl, prog, name, v, binding) {
  const index = gl.getUniformBlockIndex(prog, name);
  if (index === gl.INVALID_INDEX) return false;          // optimised away (unused)
  let m = blockBuffers.get(gl);
  if (!m) blockBuffers.set(gl, (m = new WeakMap()));
  let buffer = m.get(v);
  if (!buffer) {
    m.set(v, (buffer = gl.createBuffer()));
    gl.bindBuffer(gl.UNIFORM_BUFFER, buffer);
    gl.bufferData(gl.UNIFORM_BUFFER, new Float32Array(v.data), gl.STATIC_DRAW);
  }
  gl.uniformBlockBinding(prog, index, binding);
  gl.bindBufferBase(gl.UNIFORM_BUFFER, binding, buffer);
  return true;
}

export function setUniforms(gl, prog, values) {
  let unit = DATA_UNIT, binding = 0;
  for (const [name, v] of Object.entries(values)) {
    if (v && typeof v === "object" && v.packing === "std140") {
      if (bindBlock(gl, prog, name, v, binding)) binding++;
      continue;
    }
    const loc = uniformLocation(gl, prog, name);
    if (loc === null) continue;
    if (v && typeof v === "object" && Array.isArray(v.data)) bindData(gl, loc, v, unit++);
    else if (typeof v === "number") gl.uniform1f(loc, v);
    else if (typeof v === "boolean") gl.uniform1f(loc, v ? 1 : 0);
    else if (Array.isArray(v) && v.length >= 2 && v.length <= 4) gl[`uniform${v.length}fv`](loc, v);
  }
}
