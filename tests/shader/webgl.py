"""Evaluate generated GLSL in a WebGL2 context: direction pairs in, f (RGB) out, float32.

The fragment shader reads l and v of pixel (x, y) from two RGBA32F textures and writes
brdf(n, l, v) into an RGBA32F colour buffer (EXT_color_buffer_float), read back with
readPixels. Shared by the browser tests; runs in any page (no server code needed)."""
from __future__ import annotations

import base64

import numpy as np

from app.physics.vectors import direction_deg

VERTEX = """#version 300 es
void main() {
    vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}"""

FRAGMENT_HEAD = """#version 300 es
precision highp float;
precision highp int;
"""

FRAGMENT_MAIN = """
uniform highp sampler2D u_l;
uniform highp sampler2D u_v;
uniform vec3 u_n;
out vec4 color;
void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec3 l = texelFetch(u_l, p, 0).xyz;
    vec3 v = texelFetch(u_v, p, 0).xyz;
    color = vec4(brdf(u_n, l, v), 1.0);
}"""

#: (vertex, fragment, width, height, l as flat RGBA, v as flat RGBA, n[, textures]) → {f: flat
#: RGBA} or {error}; textures: /code's JSON "textures" (a Kulla-Conty shader's data), bound from unit 3
#: binds one of /code's JSON "textures" (R32F, unfiltered) to a sampler, or one of its "blocks"
#: (std140) to a uniform buffer: shared by both runners
DATA_TEXTURE_JS = """const dataTexture = (prog, name, v, unit) => {
    const t = gl.createTexture();
    gl.activeTexture(gl.TEXTURE0 + unit); gl.bindTexture(gl.TEXTURE_2D, t);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.NEAREST);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.NEAREST);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.R32F, v.width, v.height, 0, gl.RED, gl.FLOAT, new Float32Array(v.data));
    gl.uniform1i(gl.getUniformLocation(prog, name), unit);
    gl.activeTexture(gl.TEXTURE0);
  };
  const uniformBlock = (prog, name, v, binding) => {
    const index = gl.getUniformBlockIndex(prog, name);
    if (index === gl.INVALID_INDEX) return;
    const b = gl.createBuffer();
    gl.bindBuffer(gl.UNIFORM_BUFFER, b);
    gl.bufferData(gl.UNIFORM_BUFFER, new Float32Array(v.data), gl.STATIC_DRAW);
    gl.uniformBlockBinding(prog, index, binding);
    gl.bindBufferBase(gl.UNIFORM_BUFFER, binding, b);
  };
  const bindData = (prog, name, v, unit, binding) => (v.packing === 'std140'
    ? uniformBlock(prog, name, v, binding) : dataTexture(prog, name, v, unit));"""

RUN_JS = """async ([vs, fs, w, h, L, V, n, textures]) => {
  const canvas = document.createElement('canvas');
  canvas.width = w; canvas.height = h;
  const gl = canvas.getContext('webgl2');
  if (!gl) return {error: 'no WebGL2'};
  if (!gl.getExtension('EXT_color_buffer_float')) return {error: 'no EXT_color_buffer_float'};
  const compile = (type, src) => {
    const s = gl.createShader(type); gl.shaderSource(s, src); gl.compileShader(s);
    if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(s));
    return s;
  };
  let prog;
  const t0 = performance.now();
  try {
    prog = gl.createProgram();
    gl.attachShader(prog, compile(gl.VERTEX_SHADER, vs));
    gl.attachShader(prog, compile(gl.FRAGMENT_SHADER, fs));
    gl.linkProgram(prog);
    if (!gl.getProgramParameter(prog, gl.LINK_STATUS)) return {error: gl.getProgramInfoLog(prog)};
  } catch (e) { return {error: String(e)}; }
  const texture = (unit, data) => {
    const t = gl.createTexture();
    gl.activeTexture(gl.TEXTURE0 + unit); gl.bindTexture(gl.TEXTURE_2D, t);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.NEAREST);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.NEAREST);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA32F, w, h, 0, gl.RGBA, gl.FLOAT, new Float32Array(data));
    return t;
  };
  ${DATA_TEXTURE}
  gl.useProgram(prog);
  texture(0, L); texture(1, V);
  Object.entries(textures || {}).forEach(([name, v], k) => bindData(prog, name, v, 3 + k, k));
  gl.uniform1i(gl.getUniformLocation(prog, 'u_l'), 0);
  gl.uniform1i(gl.getUniformLocation(prog, 'u_v'), 1);
  gl.uniform3f(gl.getUniformLocation(prog, 'u_n'), n[0], n[1], n[2]);
  const target = gl.createTexture();
  gl.activeTexture(gl.TEXTURE2); gl.bindTexture(gl.TEXTURE_2D, target);
  gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA32F, w, h, 0, gl.RGBA, gl.FLOAT, null);
  const fb = gl.createFramebuffer();
  gl.bindFramebuffer(gl.FRAMEBUFFER, fb);
  gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, target, 0);
  if (gl.checkFramebufferStatus(gl.FRAMEBUFFER) !== gl.FRAMEBUFFER_COMPLETE) return {error: 'framebuffer incomplete'};
  gl.viewport(0, 0, w, h);
  gl.drawArrays(gl.TRIANGLES, 0, 3);
  const out = new Float32Array(w * h * 4);
  gl.readPixels(0, 0, w, h, gl.RGBA, gl.FLOAT, out);
  return {f: Array.from(out), ms: performance.now() - t0};
}""".replace("${DATA_TEXTURE}", DATA_TEXTURE_JS)

#: The batch runner's body: ${READBACK} is what each uniform set's draw leaves (a
#: readback into ``outs``), ${RESULT} what the call returns; ${SETUP} runs once first.
_BATCH_TEMPLATE = """async ([vs, programs, w, h, L, V, n]) => {
  const canvas = document.createElement('canvas');
  canvas.width = w; canvas.height = h;
  const gl = canvas.getContext('webgl2');
  if (!gl) return {error: 'no WebGL2'};
  if (!gl.getExtension('EXT_color_buffer_float')) return {error: 'no EXT_color_buffer_float'};
  const t0 = performance.now();
  const texture = (unit, data) => {
    const t = gl.createTexture();
    gl.activeTexture(gl.TEXTURE0 + unit); gl.bindTexture(gl.TEXTURE_2D, t);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.NEAREST);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.NEAREST);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA32F, w, h, 0, gl.RGBA, gl.FLOAT, data ? new Float32Array(data) : null);
    return t;
  };
  texture(0, L); texture(1, V);
  const target = texture(2, null);
  const fb = gl.createFramebuffer();
  gl.bindFramebuffer(gl.FRAMEBUFFER, fb);
  gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, target, 0);
  if (gl.checkFramebufferStatus(gl.FRAMEBUFFER) !== gl.FRAMEBUFFER_COMPLETE) return {error: 'framebuffer incomplete'};
  gl.viewport(0, 0, w, h);
  const compile = (type, src) => {
    const s = gl.createShader(type); gl.shaderSource(s, src); gl.compileShader(s);
    if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(s));
    return s;
  };
  ${DATA_TEXTURE}
  ${SETUP}
  const vsh = compile(gl.VERTEX_SHADER, vs);
  const results = [];
  for (const p of programs) {
    let prog;
    try {
      prog = gl.createProgram();
      gl.attachShader(prog, vsh);
      gl.attachShader(prog, compile(gl.FRAGMENT_SHADER, p.fs));
      gl.linkProgram(prog);
      if (!gl.getProgramParameter(prog, gl.LINK_STATUS)) { results.push({error: gl.getProgramInfoLog(prog)}); continue; }
    } catch (e) { results.push({error: String(e)}); continue; }
    gl.useProgram(prog);
    gl.uniform1i(gl.getUniformLocation(prog, 'u_l'), 0);
    gl.uniform1i(gl.getUniformLocation(prog, 'u_v'), 1);
    gl.uniform3f(gl.getUniformLocation(prog, 'u_n'), n[0], n[1], n[2]);
    const outs = [];
    for (const set of p.uniforms) {
      let unit = 3, binding = 0;
      for (const [name, value] of Object.entries(set)) {
        if (typeof value === 'object' && value.packing === 'std140') {      // a uniform block
          uniformBlock(prog, name, value, binding++);
          continue;
        }
        const loc = gl.getUniformLocation(prog, name);
        if (loc === null) continue;                    // optimised away (unused)
        if (typeof value === 'object') dataTexture(prog, name, value, unit++);   // a data texture
        else gl.uniform1f(loc, value);
      }
      gl.drawArrays(gl.TRIANGLES, 0, 3);
      ${READBACK}
    }
    results.push(outs);
    gl.deleteProgram(prog);
  }
  ${RESULT}
}"""


def _batch_js(setup: str, readback: str, result: str) -> str:
    return (_BATCH_TEMPLATE.replace("${DATA_TEXTURE}", DATA_TEXTURE_JS).replace("${SETUP}", setup)
            .replace("${READBACK}", readback).replace("${RESULT}", result))


#: Many programs in one page load, each compiled once and drawn once per uniform set (a
#: set may hold a data texture by name, /code's JSON "textures"):
#: ([vs, [{fs, uniforms: [{name: value}, ...]}, ...], w, h, L, V, n]) →
#: {results: [[flat RGBA per uniform set] or {error}], ms}
RUN_BATCH_JS = _batch_js(
    "",
    """const out = new Float32Array(w * h * 4);
      gl.readPixels(0, 0, w, h, gl.RGBA, gl.FLOAT, out);
      outs.push(Array.from(out));""",
    "return {results, ms: performance.now() - t0};")

#: RUN_BATCH_JS with a compact answer, for thousands of programs: every draw's RGB read
#: back into one Float32Array, returned as one base64 string (a JSON array of numbers per
#: draw through Playwright cost as much as SwiftShader's compiles) — same arguments →
#: {rgb: base64 of float32 RGB, draw after draw in order, sets: [draws per program, 0 for a
#: program that failed], errors: {program index: message}, ms}. run_packed decodes it.
RUN_PACKED_JS = _batch_js(
    """const draws = programs.reduce((s, p) => s + p.uniforms.length, 0);
  const rgb = new Float32Array(draws * w * h * 3);
  const rgba = new Float32Array(w * h * 4);
  let at = 0;""",
    """gl.readPixels(0, 0, w, h, gl.RGBA, gl.FLOAT, rgba);
      for (let i = 0; i < w * h; i++) {
        rgb[at++] = rgba[4 * i]; rgb[at++] = rgba[4 * i + 1]; rgb[at++] = rgba[4 * i + 2];
      }
      outs.push(1);""",
    """const ms = performance.now() - t0;
  const bytes = new Uint8Array(rgb.buffer, 0, at * 4);
  let bin = '';
  for (let i = 0; i < bytes.length; i += 0x8000) bin += String.fromCharCode.apply(null, bytes.subarray(i, i + 0x8000));
  const errors = {};
  results.forEach((r, k) => { if (!Array.isArray(r)) errors[k] = r.error; });
  return {rgb: btoa(bin), sets: results.map(r => Array.isArray(r) ? r.length : 0), errors, ms};""")


def run_packed(page, programs: list[dict], side: int, l_rgba, v_rgba, n=(0.0, 0.0, 1.0)) -> tuple[list, float]:
    """RUN_PACKED_JS on a page: each program's result as an array (uniform sets, side²,
    3) of float32 f, or its compile or link error (a string); and the page's milliseconds."""
    out = page.evaluate(RUN_PACKED_JS, [VERTEX, programs, side, side, l_rgba, v_rgba, list(n)])
    assert "error" not in out, out.get("error")
    flat = np.frombuffer(base64.b64decode(out["rgb"]), dtype="<f4")
    results, at = [], 0
    for k, sets in enumerate(out["sets"]):
        if not sets:
            results.append(str(out["errors"].get(str(k), "no result")))
            continue
        size = sets * side * side * 3
        results.append(flat[at:at + size].reshape(sets, side * side, 3))
        at += size
    assert at == flat.size, (at, flat.size)
    return results, out["ms"]


def random_pairs(side: int, seed: int) -> tuple[dict, list]:
    """side² random direction pairs with θ ≤ 88° (off the horizon, where a float32 rounding
    below it gives 0): the float64 angles in degrees (theta_i_deg, phi_i_deg, theta_o_deg,
    phi_o_deg: what /eval takes) and [l, v] as the flat float32 RGBA texels a shader reads."""
    rng = np.random.default_rng(seed)
    n = side * side
    angles = {"theta_i_deg": rng.uniform(0, 88, n), "phi_i_deg": rng.uniform(-180, 180, n),
              "theta_o_deg": rng.uniform(0, 88, n), "phi_o_deg": rng.uniform(-180, 180, n)}
    l = direction_deg(angles["theta_i_deg"], angles["phi_i_deg"])
    v = direction_deg(angles["theta_o_deg"], angles["phi_o_deg"])
    rgba = [np.concatenate([d, np.zeros((n, 1))], axis=1).astype(np.float32).ravel().tolist() for d in (l, v)]
    return angles, rgba


def batch_entry(body: dict, sets=({},)) -> dict:
    """RUN_BATCH_JS's entry for a /code JSON body (app.shader.generate.describe): its GLSL
    in the fragment shader, and each uniform set with the body's data textures and uniform
    blocks."""
    return {"fs": FRAGMENT_HEAD + body["code"] + FRAGMENT_MAIN,
            "uniforms": [{**s, **body.get("textures", {}), **body.get("blocks", {})} for s in sets]}
