/* The lit sphere on the GPU: L_o/E = f(l, v)·⟨n·l⟩ per pixel, in the server's frame
 * (app/quantities.lit_sphere): orthographic viewer along +z, pixel centres
 * x, y = −1 + (2k + 1)/n, n = (x, y, √(1−x²−y²)), the BRDF's tangent +x projected
 * (the generated brdf(n, l, v) builds that frame itself). Drawn into a float32 target
 * (read back for the truth toggle and the measurements), then shown with an exposure.
 *
 * A BRDF is GLSL defining `vec3 brdf(vec3 n, vec3 l, vec3 v)` and its uniforms: a new
 * source compiles once; new uniform values, the light or the exposure only draw.
 */
import { FULLSCREEN_VS, program, floatTarget, readTarget, setUniforms, uniformLocation } from "./gl.js";

export const HEAD = "#version 300 es\nprecision highp float;\nprecision highp int;\n";

const SPHERE_MAIN = `
uniform vec3 u_light;      // unit, camera frame
uniform float u_n;         // pixels across
uniform bool u_display;    // true: display values (×2^exposure, sRGB); false: radiance, alpha 1 on the disk
uniform float u_scale;     // 2^exposure
uniform vec3 u_background;
out vec4 color;
vec3 srgb(vec3 c) {        // IEC 61966-2-1's transfer, clipped to [0, 1]
  c = clamp(c, 0.0, 1.0);
  return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(0.0031308, c));
}
void main() {
  vec2 p = 2.0 * gl_FragCoord.xy / u_n - 1.0;     // pixel centre (gl_FragCoord at k + 1/2)
  float r2 = dot(p, p);
  if (r2 >= 1.0) { color = u_display ? vec4(u_background, 1.0) : vec4(0.0); return; }
  vec3 n = vec3(p, sqrt(1.0 - r2));
  float mu_l = dot(n, u_light);
  vec3 radiance = mu_l > 0.0 ? brdf(n, u_light, vec3(0.0, 0.0, 1.0)) * mu_l : vec3(0.0);
  if (!u_display) { color = vec4(radiance, 1.0); return; }
  bool bad = any(isnan(radiance)) || any(isinf(radiance));
  color = bad ? vec4(1.0, 0.0, 1.0, 1.0) : vec4(srgb(radiance * u_scale), 1.0);
}`;

export class SphereRenderer {
  /** gl: a context from gl.js's makeContext; n: pixels across. */
  constructor(gl, n) {
    this.gl = gl;
    this.n = n;
    this.target = floatTarget(gl, n, n);
    this.prog = null;
    this.source = null;
    this.uniforms = {};
    this.light = [0, 0, 1];
    this.exposure = 0;
    this.background = [1, 1, 1];
  }

  /** The BRDF's GLSL (defining brdf(n, l, v)); compiles only when it differs from the
   * current one. Returns true when it compiled. `offset`/`limit`: where the user's own
   * lines sit in `glsl`, for error line numbers. Throws ShaderError. */
  setSource(glsl, { offset = 0, limit = Infinity } = {}) {
    if (glsl === this.source && this.prog) return false;
    const head = HEAD.split("\n").length - 1;
    const prog = program(this.gl, FULLSCREEN_VS, HEAD + glsl + SPHERE_MAIN, { offset: offset + head, limit });
    if (this.prog) this.gl.deleteProgram(this.prog);
    this.prog = prog;
    this.source = glsl;
    return true;
  }

  /** The light as the float32 vector the GPU draws with (what the truth is asked for). */
  setLight(l) {
    this.light = l.map(Math.fround);
  }

  /** One pass of the sphere program: into the float target (radiance) or onto the
   * canvas (display values: one pass per frame, no copy). */
  pass(display) {
    const { gl, n } = this;
    if (!this.prog) return;
    gl.bindFramebuffer(gl.FRAMEBUFFER, display ? null : this.target.fb);
    gl.viewport(0, 0, n, n);
    gl.useProgram(this.prog);
    setUniforms(gl, this.prog, this.uniforms);
    const u = (name) => uniformLocation(gl, this.prog, name);
    gl.uniform3fv(u("u_light"), this.light);
    gl.uniform1f(u("u_n"), n);
    gl.uniform1i(u("u_display"), display ? 1 : 0);
    gl.uniform1f(u("u_scale"), 2 ** this.exposure);
    gl.uniform3fv(u("u_background"), this.background);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    if (!display) gl.bindFramebuffer(gl.FRAMEBUFFER, null);
  }

  /** Radiance into the float target (for read()). */
  render() { this.pass(false); }

  /** The frame onto the canvas. */
  draw() { this.pass(true); }

  /** The last render's radiance, float32 RGBA, rows from the top (the server's order);
   * alpha 1 on the disk, 0 off it. */
  read() {
    const raw = readTarget(this.gl, this.target);
    const n = this.n;
    const out = new Float32Array(raw.length);
    for (let row = 0; row < n; row++) out.set(raw.subarray((n - 1 - row) * n * 4, (n - row) * n * 4), row * n * 4);
    return out;
  }
}
