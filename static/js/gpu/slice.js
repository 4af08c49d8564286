/* The half/difference slice on the GPU: f over θ_h (columns) × θ_d (rows, 0 at the
 * bottom) at fixed φ_h, φ_d, the Disney explorer's image slice (Burley 2012, fig. 3), at
 * pixel centres θ = 90°·(k + ½)/n. The directions l, v are formed in float64 here by
 * Rusinkiewicz's rotation (1998, sec. 3; app/quantities.rusinkiewicz_directions) and
 * read by the shader from two RGBA32F textures: the GPU's float32 sin/cos would move
 * them by ~1e-4 (SwiftShader, measured), and GET /api/v1/reference/slice evaluates the
 * very same float32 directions in float64 — the truth is the BRDF's arithmetic alone.
 * Shown as log10 f over the image's finite range, viridis-like.
 */
import { FULLSCREEN_VS, program, floatTarget, floatTexture, readTarget, setUniforms, uniformLocation } from "./gl.js";
import { HEAD } from "./sphere.js";

const DEG = Math.PI / 180;
/** The colour range comes from the pixels with θ_l, θ_v ≤ this (truth.js's band). */
const COLOUR_BAND_DEG = 88;
const MU_BAND = Math.cos(COLOUR_BAND_DEG * DEG);
/** Decades of f the colours span at most. */
const COLOUR_DECADES = 4;

/** l and v (Float32Array n·n·4 each, rows θ_d from 0) at the slice's pixel centres. */
export function sliceDirections(n, phiHDeg, phiDDeg) {
  const l = new Float32Array(n * n * 4), v = new Float32Array(n * n * 4);
  const cp = Math.cos(phiHDeg * DEG), sp = Math.sin(phiHDeg * DEG);
  const cd = Math.cos(phiDDeg * DEG), sd = Math.sin(phiDDeg * DEG);
  for (let j = 0; j < n; j++) {
    const td = 90 * (j + 0.5) / n * DEG;
    const d = [Math.sin(td) * cd, Math.sin(td) * sd, Math.cos(td)];
    for (let i = 0; i < n; i++) {
      const th = 90 * (i + 0.5) / n * DEG, ct = Math.cos(th), st = Math.sin(th);
      const rotate = ([wx, wy, wz]) => {        // R_z(φ_h) R_y(θ_h)
        const x = wx * ct + wz * st, z = -wx * st + wz * ct;
        return [x * cp - wy * sp, x * sp + wy * cp, z, 1];
      };
      l.set(rotate(d), 4 * (j * n + i));
      v.set(rotate([-d[0], -d[1], d[2]]), 4 * (j * n + i));
    }
  }
  return { l, v };
}

const SLICE_MAIN = `
uniform highp sampler2D u_l;
uniform highp sampler2D u_v;
uniform bool u_display;       // true: log10 f coloured; false: f (rgb), alpha 1 where defined
uniform vec2 u_log_range;     // log10 of the image's smallest and largest positive f
out vec4 color;
vec3 ramp(float t) {          // dark blue → teal → yellow (viridis's ends and middle)
  return t < 0.5 ? mix(vec3(0.267, 0.005, 0.329), vec3(0.128, 0.567, 0.551), 2.0 * t)
                 : mix(vec3(0.128, 0.567, 0.551), vec3(0.993, 0.906, 0.144), 2.0 * t - 1.0);
}
void main() {
  ivec2 px = ivec2(gl_FragCoord.xy);
  vec3 l = texelFetch(u_l, px, 0).xyz, v = texelFetch(u_v, px, 0).xyz;
  if (l.z <= 0.0 || v.z <= 0.0) { color = u_display ? vec4(1.0) : vec4(0.0); return; }
  vec3 f = brdf(vec3(0.0, 0.0, 1.0), l, v);
  if (!u_display) { color = vec4(f, 1.0); return; }
  float y = dot(f, vec3(0.2126, 0.7152, 0.0722));
  if (isnan(y) || isinf(y)) { color = vec4(1.0, 0.0, 1.0, 1.0); return; }
  float t = y > 0.0 ? clamp((log(y) / log(10.0) - u_log_range.x) / max(u_log_range.y - u_log_range.x, 1e-6), 0.0, 1.0) : 0.0;
  color = vec4(ramp(t), 1.0);
}`;

export class SliceRenderer {
  constructor(gl, n) {
    Object.assign(this, { gl, n, prog: null, source: null, uniforms: {}, phi: null, logRange: [-3, 1] });
    this.target = floatTarget(gl, n, n);
  }

  /** The BRDF's GLSL (brdf(n, l, v)); compiles when it differs. Throws ShaderError.
   * offset, limit: a user's file's line numbering (gl.js program). */
  setSource(glsl, { offset = 0, limit = Infinity } = {}) {
    if (glsl === this.source && this.prog) return false;
    const head = HEAD.split("\n").length - 1;
    const prog = program(this.gl, FULLSCREEN_VS, HEAD + glsl + SLICE_MAIN, { offset: offset + head, limit });
    if (this.prog) this.gl.deleteProgram(this.prog);
    Object.assign(this, { prog, source: glsl });
    return true;
  }

  /** The slice's azimuths (degrees): the direction textures made again when they change. */
  setAzimuths(phiH, phiD) {
    if (this.phi && this.phi[0] === phiH && this.phi[1] === phiD) return;
    const { l, v } = sliceDirections(this.n, phiH, phiD);
    for (const t of [this.lTex, this.vTex]) if (t) this.gl.deleteTexture(t);
    this.lTex = floatTexture(this.gl, this.n, this.n, l);
    this.vTex = floatTexture(this.gl, this.n, this.n, v);
    this.phi = [phiH, phiD];
    this.dirs = { l, v };
  }

  pass(display) {
    const { gl, n } = this;
    if (!this.prog || !this.lTex) return;
    gl.bindFramebuffer(gl.FRAMEBUFFER, display ? null : this.target.fb);
    gl.viewport(0, 0, n, n);
    gl.useProgram(this.prog);
    setUniforms(gl, this.prog, this.uniforms);
    const u = (name) => uniformLocation(gl, this.prog, name);
    [this.lTex, this.vTex].forEach((t, k) => {
      gl.activeTexture(gl.TEXTURE0 + k);
      gl.bindTexture(gl.TEXTURE_2D, t);
      gl.uniform1i(u(k ? "u_v" : "u_l"), k);
    });
    gl.activeTexture(gl.TEXTURE0);
    gl.uniform1i(u("u_display"), display ? 1 : 0);
    gl.uniform2fv(u("u_log_range"), this.logRange);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
  }

  /** f into the float target, the colour range taken from its finite positive values
   * where θ_l, θ_v ≤ COLOUR_BAND_DEG (at θ_h = 0, θ_d → 90° f grows as 1/cos² θ_d, a
   * divergence that would set the top and leave the rest one colour; brighter pixels
   * clip), at most COLOUR_DECADES below the top; then drawn. `logRange` given: drawn on
   * that scale instead (another slice's, to be compared with it by eye). */
  draw(logRange = null) {
    this.render();
    if (logRange) {
      this.logRange = logRange;
      return this.pass(true);
    }
    const f = this.read(), { l, v } = this.dirs;
    let lo = Infinity, hi = -Infinity;
    for (let p = 0; p < f.length; p += 4) {
      if (l[p + 2] < MU_BAND || v[p + 2] < MU_BAND) continue;
      const y = 0.2126 * f[p] + 0.7152 * f[p + 1] + 0.0722 * f[p + 2];
      if (y > 0 && Number.isFinite(y)) { lo = Math.min(lo, y); hi = Math.max(hi, y); }
    }
    if (hi > 0) this.logRange = [Math.max(Math.log10(lo), Math.log10(hi) - COLOUR_DECADES), Math.log10(hi)];
    this.pass(true);
  }

  render() { this.pass(false); }

  /** The last render's f, float32 RGBA, rows θ_d from 0 (the reference's order). */
  read() { return readTarget(this.gl, this.target); }
}
