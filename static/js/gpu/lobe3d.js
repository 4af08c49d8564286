/* The 3-D lobe on the GPU: the surface r(ω_o) = f(ω_i, ω_o)·cos θ_o over the hemisphere
 * of outgoing directions (the radiance leaving towards ω_o per unit irradiance from ω_i:
 * the lobe panel's f·cos θ_o, app/quantities.py lobe_curve, over every azimuth; the
 * server's 3-D lobe draws f), for the light ω_i, as a mesh whose vertices are displaced in the
 * vertex shader by evaluating the BRDF there (its GLSL compiled into the vertex stage:
 * a new light or value moves every vertex with no upload). The luminance of f (Rec. 709,
 * as the server's "f" of a coloured model). Seen from an orbit (azimuth, elevation).
 *
 * The directions are formed in float64 in JS and sent as float32 attributes (the GPU's
 * sin/cos are off by ~1e-4 on SwiftShader; slice.js does the same). The radius drawn is
 * read back from a float target — each vertex a point on its own texel — by radii().
 */
import { program, floatTarget, readTarget, setUniforms, uniformLocation } from "./gl.js";
import { HEAD } from "./sphere.js";

const DEG = Math.PI / 180;
/** Rows θ_o = 0..90° and columns φ_o = 0..360°, both ends included: 1.4° × 2.8° cells. */
export const MESH = { theta: 65, phi: 129 };
/** Texels per row of the read-back target. */
const PROBE_WIDTH = 256;
/** The lobe's largest radius is drawn at this share of the half-width. */
export const FILL = 0.9;

const LOBE_VS = `
in vec3 a_dir;             // ω_o, unit, formed in float64
uniform vec3 u_light;      // ω_i, unit
uniform mat3 u_view;       // world (z: the normal) → view (x right, y up, z away)
uniform float u_zoom;      // FILL / the largest radius
uniform bool u_probe;      // read-back: vertex k → texel k of a PROBE_WIDTH-wide target
uniform vec2 u_probe_size;
out float v_r;
out vec3 v_pos;
void main() {
  vec3 f = brdf(vec3(0.0, 0.0, 1.0), u_light, a_dir);
  float r = dot(f, vec3(0.2126, 0.7152, 0.0722)) * max(a_dir.z, 0.0);   // f·cos θ_o
  v_r = r;
  if (u_probe) {
    vec2 texel = vec2(float(gl_VertexID % ${PROBE_WIDTH}), float(gl_VertexID / ${PROBE_WIDTH})) + 0.5;
    gl_Position = vec4(2.0 * texel / u_probe_size - 1.0, 0.0, 1.0);
    gl_PointSize = 1.0;
    return;
  }
  vec3 p = u_view * (r * a_dir) * u_zoom;
  v_pos = p;
  gl_Position = vec4(p.xy, 0.5 * p.z, 1.0);
}`;

const LOBE_FS = `${HEAD}
in float v_r;
in vec3 v_pos;
uniform bool u_probe;
uniform float u_zoom;
out vec4 color;
vec3 ramp(float t) {       // slice.js's: dark blue → teal → yellow
  return t < 0.5 ? mix(vec3(0.267, 0.005, 0.329), vec3(0.128, 0.567, 0.551), 2.0 * t)
                 : mix(vec3(0.128, 0.567, 0.551), vec3(0.993, 0.906, 0.144), 2.0 * t - 1.0);
}
void main() {
  if (u_probe) { color = vec4(v_r, 0.0, 0.0, 1.0); return; }
  if (isnan(v_r) || isinf(v_r)) { color = vec4(1.0, 0.0, 1.0, 1.0); return; }
  vec3 n = normalize(cross(dFdx(v_pos), dFdy(v_pos)));    // the facet's normal, for shading
  float shade = 0.45 + 0.55 * abs(n.z);
  color = vec4(ramp(clamp(v_r * u_zoom / ${FILL.toFixed(2)}, 0.0, 1.0)) * shade, 1.0);
}`;

/** Guides: the normal, the light and the horizon, in world space. */
const LINE_VS = `#version 300 es
in vec3 a_pos;
uniform mat3 u_view;
void main() { vec3 p = u_view * a_pos * ${FILL.toFixed(2)}; gl_Position = vec4(p.xy, 0.5 * p.z, 1.0); }`;
const LINE_FS = `${HEAD}
uniform vec3 u_color;
out vec4 color;
void main() { color = vec4(u_color, 1.0); }`;

/** Unit vector at (θ, φ) in degrees. */
const dir = (t, p) => [Math.sin(t * DEG) * Math.cos(p * DEG), Math.sin(t * DEG) * Math.sin(p * DEG), Math.cos(t * DEG)];

/** The orbit's matrix (column-major mat3): turned by `azimuth` about the normal, seen from
 * `elevation` above the horizon. */
export function orbit(azimuthDeg, elevationDeg) {
  const ca = Math.cos(azimuthDeg * DEG), sa = Math.sin(azimuthDeg * DEG);
  const ce = Math.cos(elevationDeg * DEG), se = Math.sin(elevationDeg * DEG);
  // rows: screen x = x₁, screen y = z cos e + y₁ sin e, depth = y₁ cos e − z sin e,
  // with (x₁, y₁) = the azimuth's rotation of (x, y)
  const rows = [[ca, -sa, 0], [se * sa, se * ca, ce], [ce * sa, ce * ca, -se]];
  return [0, 1, 2].flatMap((c) => rows.map((r) => r[c]));
}

export class LobeRenderer {
  constructor(gl) {
    Object.assign(this, { gl, prog: null, source: null, uniforms: {}, light: [0, 0, 1], view: orbit(-30, 25), zoom: 1 });
    const dirs = [], index = [];
    for (let i = 0; i < MESH.theta; i++) {
      for (let j = 0; j < MESH.phi; j++) dirs.push(...dir(90 * i / (MESH.theta - 1), 360 * j / (MESH.phi - 1)));
    }
    for (let i = 0; i + 1 < MESH.theta; i++) {
      for (let j = 0; j + 1 < MESH.phi; j++) {
        const a = i * MESH.phi + j, b = a + 1, c = a + MESH.phi, d = c + 1;
        index.push(a, c, b, b, c, d);
      }
    }
    this.meshDirs = Float32Array.from(dirs);
    this.vertices = this.buffer(this.meshDirs);
    this.indices = gl.createBuffer();
    gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, this.indices);
    gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, new Uint32Array(index), gl.STATIC_DRAW);
    this.count = index.length;
    this.lineProg = program(gl, LINE_VS, LINE_FS);
    const circle = [];
    for (let k = 0; k < 96; k++) circle.push(...dir(90, 360 * k / 96), ...dir(90, 360 * (k + 1) / 96));
    this.horizon = { buf: this.buffer(Float32Array.from(circle)), n: 192 };
  }

  buffer(data) {
    const gl = this.gl, b = gl.createBuffer();
    gl.bindBuffer(gl.ARRAY_BUFFER, b);
    gl.bufferData(gl.ARRAY_BUFFER, data, gl.STATIC_DRAW);
    return b;
  }

  /** The BRDF's GLSL (brdf(n, l, v)), compiled into the vertex stage when it differs.
   * Throws ShaderError. */
  setSource(glsl) {
    if (glsl === this.source && this.prog) return false;
    const prog = program(this.gl, HEAD + glsl + LOBE_VS, LOBE_FS);
    if (this.prog) this.gl.deleteProgram(this.prog);
    Object.assign(this, { prog, source: glsl });
    return true;
  }

  bind(prog, buf) {
    const gl = this.gl, at = gl.getAttribLocation(prog, prog === this.lineProg ? "a_pos" : "a_dir");
    gl.bindBuffer(gl.ARRAY_BUFFER, buf);
    gl.enableVertexAttribArray(at);
    gl.vertexAttribPointer(at, 3, gl.FLOAT, false, 0, 0);
  }

  lobeUniforms(probe, size = [1, 1]) {
    const gl = this.gl, u = (n) => uniformLocation(gl, this.prog, n);
    gl.useProgram(this.prog);
    setUniforms(gl, this.prog, this.uniforms);
    gl.uniform3fv(u("u_light"), this.light);
    gl.uniformMatrix3fv(u("u_view"), false, this.view);
    gl.uniform1f(u("u_zoom"), this.zoom);
    gl.uniform1i(u("u_probe"), probe ? 1 : 0);
    gl.uniform2fv(u("u_probe_size"), size);
  }

  /** r = f·cos θ_o (float32, as the vertex shader computes it) at unit directions `dirs`
   * (a flat array of 3·count). */
  radii(dirs) {
    const gl = this.gl, count = dirs.length / 3, h = Math.ceil(count / PROBE_WIDTH);
    const target = floatTarget(gl, PROBE_WIDTH, h), buf = this.buffer(Float32Array.from(dirs));
    gl.bindFramebuffer(gl.FRAMEBUFFER, target.fb);
    gl.viewport(0, 0, PROBE_WIDTH, h);
    gl.disable(gl.DEPTH_TEST);
    gl.clearColor(0, 0, 0, 0);
    gl.clear(gl.COLOR_BUFFER_BIT);
    this.lobeUniforms(true, [PROBE_WIDTH, h]);
    this.bind(this.prog, buf);
    gl.drawArrays(gl.POINTS, 0, count);
    const px = readTarget(gl, target);
    gl.deleteBuffer(buf);
    gl.deleteTexture(target.tex);
    gl.deleteFramebuffer(target.fb);
    return Float32Array.from({ length: count }, (_, k) => px[4 * k]);
  }

  /** The largest radius over the mesh's vertices (finite ones), read back. */
  peak() {
    let top = 0;
    for (const r of this.radii(this.meshDirs)) if (Number.isFinite(r) && r > top) top = r;
    return top;
  }

  /** The lobe onto the canvas at `zoom` (FILL / the largest radius of what is compared). */
  draw(zoom) {
    const gl = this.gl;
    if (!this.prog) return;
    this.zoom = zoom;
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    gl.viewport(0, 0, gl.drawingBufferWidth, gl.drawingBufferHeight);
    gl.clearColor(1, 1, 1, 1);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    gl.enable(gl.DEPTH_TEST);
    this.lobeUniforms(false);
    this.bind(this.prog, this.vertices);
    gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, this.indices);
    gl.drawElements(gl.TRIANGLES, this.count, gl.UNSIGNED_INT, 0);
    // guides: the horizon (grey), the normal (black) and the light (orange), unit length
    gl.useProgram(this.lineProg);
    gl.uniformMatrix3fv(uniformLocation(gl, this.lineProg, "u_view"), false, this.view);
    const line = (buf, n, rgb) => {
      gl.uniform3fv(uniformLocation(gl, this.lineProg, "u_color"), rgb);
      this.bind(this.lineProg, buf);
      gl.drawArrays(gl.LINES, 0, n);
    };
    line(this.horizon.buf, this.horizon.n, [0.6, 0.6, 0.6]);
    const axes = this.buffer(Float32Array.from([0, 0, 0, 0, 0, 1, 0, 0, 0, ...this.light]));
    line(axes, 2, [0.1, 0.1, 0.1]);
    gl.uniform3fv(uniformLocation(gl, this.lineProg, "u_color"), [0.9, 0.6, 0.0]);
    gl.drawArrays(gl.LINES, 2, 2);
    gl.deleteBuffer(axes);
    gl.disable(gl.DEPTH_TEST);
  }
}
