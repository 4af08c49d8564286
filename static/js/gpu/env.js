/* The sphere under a procedural environment on the GPU, progressive: each frame adds K
 * sample pairs per pixel to a float32 accumulation (ping-pong targets), the display shows
 * their mean. The environments are app/environment/maps.py's, written again in GLSL
 * (uniform, studio, overcast, sunset; key = the light direction, colour).
 *
 * Estimator: per pair, one direction drawn ∝ cos θ about n and one from the environment's
 * bright part (uniformly in the cone of studio's key box or sunset's sun; the user map's
 * pdf) or, where there is none (uniform, overcast), from a glossy lobe about the mirror
 * direction; the balance heuristic over the two (Veach 1997, ch. 9): Σ_s f L μ_l / Σ p_s.
 * Alpha accumulates the luminance's square, for the stated standard error.
 */
import { FULLSCREEN_VS, program, floatTarget, floatTexture, readTarget, setUniforms, uniformLocation } from "./gl.js";
import { LUMINANCE } from "../panels/average.js";
import { HEAD } from "./sphere.js";

export const ENVIRONMENTS = ["uniform", "studio", "overcast", "sunset"];
/** The environment name of a user's map (setMap): u_env 4. */
export const MAP = "map";
/** The share of the map's sampling pdf spread uniformly over the sphere (render.py's
 * PDF_UNIFORM_SHARE): no direction where L > 0 has p = 0, a black cell's neighbour too. */
const MAP_UNIFORM_SHARE = 0.05;
/** Sample pairs per pixel per frame at rest (full resolution) and while the input
 * changes (the preview: PREVIEW_SIZE², one pair — an eighth of the work, measured
 * 7–9 frames/s → bench/gpu_sphere.py --env). */
export const PAIRS_PER_FRAME = 2;
export const PREVIEW_PAIRS = 1;
/** Pixels across the preview accumulation (shown scaled up, nearest, on the same canvas). */
export const PREVIEW_SIZE = 128;
/** Stops the environment sphere is shown below the panel's exposure: an environment of
 * radiance 1 gives a Lambertian surface L_o = ρ, a point light of irradiance 1 gives
 * ρ/π·cos θ — log2 π stops brighter, so one exposure suits both spheres. */
const ENV_EXPOSURE_OFFSET = Math.log2(Math.PI);
const DEG = Math.PI / 180;
/** The soft discs of maps.py, [radius, edge] in degrees: the key box or the sun, and
 * studio's fill box. Their edges' cosines are formed here in float64 and passed as
 * uniforms: SwiftShader's float32 cos() is off by ~1e-4 near 3° (measured), a sixth of
 * the sun's edge ramp (cos 2° − cos 3° = 7.6e-4), which brightened the GPU's sunset by 2 %
 * and its studio by 0.5 % against the server's (docs/gpu.md). */
const DISCS = { studio: [[12, 5], [20, 8]], sunset: [[2.5, 1], [2.5, 1]] };
const edges = ([r, e]) => [Math.cos((r - e / 2) * DEG), Math.cos((r + e / 2) * DEG)];
/** The bright disc each environment's cone samples: [radius + edge/2 in degrees] (maps.py). */
const CONE_DEG = { studio: 12 + 5 / 2, sunset: 2.5 + 1 / 2 };

const ENV_GLSL = `
uniform vec3 u_key;
uniform vec3 u_colour;
uniform int u_env;          // 0 uniform, 1 studio, 2 overcast, 3 sunset, 4 the user's map
const vec3 ENV_ZENITH = vec3(0.08, 0.16, 0.45);
const vec3 ENV_HORIZON = vec3(1.0, 0.45, 0.15);
const vec3 ENV_GROUND = vec3(0.04, 0.03, 0.025);
const vec3 ENV_SUN_COLOUR = vec3(1.0, 0.75, 0.45);
uniform vec2 u_disc_key;     // cos of the key box's / the sun's inner and outer edge
uniform vec2 u_disc_fill;    // the same for studio's fill box
// The user's equirectangular map (MapTextures): cells w × h, row 0 at θ = 0 (+y), the
// column's φ = atan(x, −z) from −π (the map's centre is seen behind the sphere, −z).
uniform highp sampler2D u_map;       // each cell's radiance (rgb)
uniform highp sampler2D u_map_rows;  // h × 1: marginal CDF at the row's end, cos θ_top, cos θ_bottom
uniform highp sampler2D u_map_cols;  // w × h: the row's CDF at the column's end, the cell's pdf per steradian
ivec2 env_map_cell(vec3 w) {
  ivec2 size = textureSize(u_map, 0);
  int lo = 0, hi = size.y - 1;       // the row: the first whose cos θ_bottom ≤ w.y
  while (lo < hi) { int mid = (lo + hi) / 2; if (w.y >= texelFetch(u_map_rows, ivec2(mid, 0), 0).b) hi = mid; else lo = mid + 1; }
  float u = (atan(w.x, -w.z) + 3.14159265) / 6.2831853;
  return ivec2(clamp(int(u * float(size.x)), 0, size.x - 1), lo);
}
float env_smooth_disc(vec3 w, vec3 c, vec2 cos_in_out) {
  float t = clamp((dot(w, c) - cos_in_out.y) / (cos_in_out.x - cos_in_out.y), 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}
vec3 env_radiance(vec3 w) {
  if (u_env == 0) return u_colour;
  if (u_env == 4) return texelFetch(u_map, env_map_cell(w), 0).rgb * u_colour;
  if (u_env == 1) {
    vec3 fill = normalize(vec3(-u_key.x, 0.5 * abs(u_key.y) + 0.3, max(u_key.z, 0.3)));
    return (0.02 + 16.0 * env_smooth_disc(w, u_key, u_disc_key) + 1.2 * env_smooth_disc(w, fill, u_disc_fill)) * u_colour;
  }
  if (u_env == 2) {
    float c = dot(w, u_key);
    return (c >= 0.0 ? (1.0 + 2.0 * clamp(c, 0.0, 1.0)) / 3.0 : 0.15) * u_colour;
  }
  float up = clamp(w.y, -1.0, 1.0);
  vec3 sky = up >= 0.0 ? ENV_HORIZON + pow(max(up, 0.0), 0.4) * (ENV_ZENITH - ENV_HORIZON) : ENV_GROUND;
  return (sky + 60.0 * env_smooth_disc(w, u_key, u_disc_key) * ENV_SUN_COLOUR) * u_colour;
}`;

const ACCUMULATE_MAIN = `
uniform highp sampler2D u_prev;
uniform float u_n;
uniform uint u_frame;
uniform uint u_seed;         // another seed, another independent image
uniform float u_cone_cos;    // cos of the cone's half-angle; 1: no cone
uniform int u_pairs;         // sample pairs this frame
out vec4 color;
const float ENV_PI = 3.14159265;
const float RIM_TEXELS = 1.5;    // a texel whose centre is this many texels past the rim can cover the disk
const float RIM_INSIDE = 0.9999; // and is drawn at this radius (n·v > 0 there: 1.4e-2)
uint env_hash(uint x) {          // a 32-bit integer mix (Wellons' lowbias32)
  x ^= x >> 16; x *= 0x7feb352du; x ^= x >> 15; x *= 0x846ca68bu; x ^= x >> 16; return x;
}
float env_rnd(inout uint s) { s = env_hash(s); return float(s >> 8) / 16777216.0; }
// a direction drawn ∝ the map's pdf: a row by its marginal CDF, a column by the row's
// CDF, then uniformly in the cell's solid angle (cos θ and φ uniform)
vec3 env_map_sample(float u1, float u2, float u3, float u4) {
  ivec2 size = textureSize(u_map, 0);
  int lo = 0, hi = size.y - 1;
  while (lo < hi) { int mid = (lo + hi) / 2; if (texelFetch(u_map_rows, ivec2(mid, 0), 0).r > u1) hi = mid; else lo = mid + 1; }
  int row = lo;
  lo = 0; hi = size.x - 1;
  while (lo < hi) { int mid = (lo + hi) / 2; if (texelFetch(u_map_cols, ivec2(mid, row), 0).r > u2) hi = mid; else lo = mid + 1; }
  vec4 r = texelFetch(u_map_rows, ivec2(row, 0), 0);
  float c = mix(r.g, r.b, u3), sn = sqrt(max(0.0, 1.0 - c * c));
  float phi = -ENV_PI + 2.0 * ENV_PI * (float(lo) + u4) / float(size.x);
  return vec3(sn * sin(phi), c, -sn * cos(phi));
}
// Without a bright disc to sample, the second strategy is a glossy lobe about the mirror
// direction: half vectors from an equal mixture of two GGX distributions (Walter et al.
// 2007, eq. 33 and 35), α = LOBE_ALPHA.x and .y, whatever the BRDF (the balance
// heuristic keeps any such pdf unbiased; it pays where f has a lobe of about that width).
const vec2 LOBE_ALPHA = vec2(0.1, 0.5);
float env_ggx_d(float a, float c) {  // D(h)·cos θ_h's D, c = cos θ_h
  float a2 = a * a, t = c * c * (a2 - 1.0) + 1.0;
  return a2 / (ENV_PI * t * t);
}
vec3 env_lobe_sample(mat3 fn, vec3 v, float u1, float u2) {
  float a = u1 < 0.5 ? LOBE_ALPHA.x : LOBE_ALPHA.y, u = fract(2.0 * u1);
  float c2 = (1.0 - u) / (1.0 + (a * a - 1.0) * u), sn = sqrt(max(0.0, 1.0 - c2));
  vec3 h = fn * vec3(sn * cos(2.0 * ENV_PI * u2), sn * sin(2.0 * ENV_PI * u2), sqrt(c2));
  return reflect(-v, h);
}
float env_lobe_pdf(vec3 n, vec3 v, vec3 l) {   // per steradian of l: p(h)/(4 v·h)
  vec3 h = normalize(l + v);
  float c = dot(n, h), vh = dot(v, h);
  if (c <= 0.0 || vh <= 0.0) return 0.0;
  return 0.5 * (env_ggx_d(LOBE_ALPHA.x, c) + env_ggx_d(LOBE_ALPHA.y, c)) * c / (4.0 * vh);
}
mat3 env_basis(vec3 z) {         // any orthonormal frame with z as its third axis
  vec3 a = abs(z.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0);
  vec3 x = normalize(cross(a, z));
  return mat3(x, cross(z, x), z);
}
void main() {
  ivec2 px = ivec2(gl_FragCoord.xy);
  vec4 prev = texelFetch(u_prev, px, 0);
  vec2 p = 2.0 * gl_FragCoord.xy / u_n - 1.0;
  float r2 = dot(p, p);
  // texels just off the rim are drawn at the rim: a coarse (preview) texel there covers
  // canvas pixels on the disk; at full size they are never shown nor counted
  float rim = 1.0 + RIM_TEXELS * 2.0 / u_n;
  if (r2 >= rim * rim) { color = vec4(0.0); return; }
  if (r2 >= 1.0) { p *= RIM_INSIDE / sqrt(r2); r2 = dot(p, p); }
  vec3 n = vec3(p, sqrt(1.0 - r2)), v = vec3(0.0, 0.0, 1.0);
  uint s = env_hash(env_hash(u_seed) ^ (uint(px.x) + 4096u * uint(px.y) + 16777216u * u_frame));
  mat3 fn = env_basis(n), fc = env_basis(u_key);
  float cone_pdf = u_cone_cos < 1.0 ? 1.0 / (2.0 * ENV_PI * (1.0 - u_cone_cos)) : 0.0;
  vec3 sum_rgb = vec3(0.0);
  float sum_l2 = 0.0;
  for (int k = 0; k < u_pairs; k++) {
    vec3 est = vec3(0.0);
    for (int strategy = 0; strategy < 2; strategy++) {
      float u1 = env_rnd(s), u2 = env_rnd(s);
      vec3 l;
      if (strategy == 0) {
        float sr = sqrt(u1);
        l = fn * vec3(sr * cos(2.0 * ENV_PI * u2), sr * sin(2.0 * ENV_PI * u2), sqrt(1.0 - u1));
      } else if (u_env == 4) {
        l = env_map_sample(u1, u2, env_rnd(s), env_rnd(s));
      } else if (cone_pdf > 0.0) {
        float c = 1.0 - u1 * (1.0 - u_cone_cos), sn = sqrt(max(0.0, 1.0 - c * c));
        l = fc * vec3(sn * cos(2.0 * ENV_PI * u2), sn * sin(2.0 * ENV_PI * u2), c);
      } else {
        l = env_lobe_sample(fn, v, u1, u2);
      }
      float mu = dot(n, l);
      if (mu <= 0.0) continue;
      float pdf = mu / ENV_PI + (u_env == 4 ? texelFetch(u_map_cols, env_map_cell(l), 0).g
                                : cone_pdf > 0.0 ? (dot(l, u_key) >= u_cone_cos ? cone_pdf : 0.0)
                                : env_lobe_pdf(n, v, l));
      est += brdf(n, l, v) * env_radiance(l) * mu / pdf;
    }
    sum_rgb += est;
    float lum = dot(est, vec3(${LUMINANCE.join(", ")}));
    sum_l2 += lum * lum;
  }
  color = prev + vec4(sum_rgb, sum_l2);
}`;

const DISPLAY_FS = `${HEAD}
uniform highp sampler2D u_sum;   // the accumulation, m² (m ≤ the canvas's n)
uniform float u_n;               // the canvas's pixels across
uniform float u_count;
uniform float u_scale;
out vec4 color;
vec3 srgb(vec3 c) {
  c = clamp(c, 0.0, 1.0);
  return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(0.0031308, c));
}
void main() {
  vec2 p = 2.0 * gl_FragCoord.xy / u_n - 1.0;
  if (dot(p, p) >= 1.0) { color = vec4(1.0); return; }
  float m = float(textureSize(u_sum, 0).x);
  vec4 sum = texelFetch(u_sum, ivec2(gl_FragCoord.xy * m / u_n), 0);
  color = vec4(srgb(sum.rgb / u_count * u_scale), 1.0);
}`;

/** A user's equirectangular map ({width, height, rgb: Float32Array, rows from θ = 0}) as
 * the three textures the shader reads: the cells' radiance, the rows' marginal CDF with
 * their cos θ bounds, and each row's CDF over its columns with each cell's pdf per
 * steradian. The pdf: ∝ luminance × solid angle, MAP_UNIFORM_SHARE of it uniform over the
 * sphere (Pharr, Jakob & Humphreys, PBR 3rd ed., §14.2.4, with render.py's uniform share).
 * Bounds and CDFs are formed here in float64 (SwiftShader's float32 cos is off by ~1e-4). */
export function mapTextures(gl, { width: w, height: h, rgb }) {
  const radiance = new Float32Array(w * h * 4), rows = new Float32Array(h * 4), cols = new Float32Array(w * h * 4);
  const cosAt = (i) => Math.cos(Math.PI * i / h);
  const cellOmega = (i) => 2 * Math.PI * (cosAt(i) - cosAt(i + 1)) / w;
  const weight = new Float64Array(w * h);
  let total = 0;
  for (let i = 0; i < h; i++) {
    for (let j = 0; j < w; j++) {
      const q = i * w + j;
      radiance.set([rgb[3 * q], rgb[3 * q + 1], rgb[3 * q + 2], 1], 4 * q);
      const lum = LUMINANCE[0] * rgb[3 * q] + LUMINANCE[1] * rgb[3 * q + 1] + LUMINANCE[2] * rgb[3 * q + 2];
      weight[q] = Math.max(lum, 0) * cellOmega(i);
      total += weight[q];
    }
  }
  const share = total > 0 ? MAP_UNIFORM_SHARE : 1;
  let rowCdf = 0;
  for (let i = 0; i < h; i++) {
    const omega = cellOmega(i);
    const p = new Float64Array(w);                   // each cell's probability
    let rowSum = 0;
    for (let j = 0; j < w; j++) {
      p[j] = (1 - share) * (total > 0 ? weight[i * w + j] / total : 0) + share * omega / (4 * Math.PI);
      rowSum += p[j];
    }
    let c = 0;
    for (let j = 0; j < w; j++) {
      c += p[j];
      cols.set([j === w - 1 ? 1 : c / rowSum, p[j] / omega, 0, 0], 4 * (i * w + j));
    }
    rowCdf += rowSum;
    rows.set([i === h - 1 ? 1 : rowCdf, cosAt(i), cosAt(i + 1), 0], 4 * i);
  }
  return { map: floatTexture(gl, w, h, radiance), rows: floatTexture(gl, h, 1, rows), cols: floatTexture(gl, w, h, cols) };
}

export class EnvSphere {
  constructor(gl, n) {
    Object.assign(this, { gl, n, prog: null, source: null, uniforms: {}, env: "studio", key: [0, 0, 1],
                          colour: [1, 1, 1], exposure: 0, frames: 0, samples: 0, preview: false, seed: 0 });
    this.full = [floatTarget(gl, n, n), floatTarget(gl, n, n)];
    const m = Math.min(n, PREVIEW_SIZE);
    this.coarse = [floatTarget(gl, m, m), floatTarget(gl, m, m)];
    this.display = program(gl, FULLSCREEN_VS, DISPLAY_FS);
  }

  /** The user's map (mapTextures' input): the environment MAP. */
  setMap(cells) {
    const gl = this.gl;
    for (const t of Object.values(this.mapTex || {})) gl.deleteTexture(t);
    this.mapTex = mapTextures(gl, cells);
  }

  /** The BRDF's GLSL (brdf(n, l, v)); compiles when it differs. Throws ShaderError. */
  setSource(glsl) {
    if (glsl === this.source && this.prog) return false;
    const prog = program(this.gl, FULLSCREEN_VS, HEAD + glsl + ENV_GLSL + ACCUMULATE_MAIN);
    if (this.prog) this.gl.deleteProgram(this.prog);
    Object.assign(this, { prog, source: glsl });
    this.reset();
    return true;
  }

  /** Start the accumulation again (the model, light or environment changed); `preview`:
   * accumulate coarse and one pair a frame (the input is still changing). */
  reset(preview = false) {
    const gl = this.gl;
    this.preview = preview;
    this.targets = preview ? this.coarse : this.full;
    for (const t of this.targets) {
      gl.bindFramebuffer(gl.FRAMEBUFFER, t.fb);
      gl.clearBufferfv(gl.COLOR, 0, [0, 0, 0, 0]);
    }
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    this.frames = 0;
    this.samples = 0;
    this.current = null;
  }

  /** One frame's samples added; the mean shown. */
  step() {
    const { gl } = this;
    if (!this.prog) return;
    const [from, to] = this.frames % 2 ? [this.targets[1], this.targets[0]] : this.targets;
    const pairs = this.preview ? PREVIEW_PAIRS : PAIRS_PER_FRAME;
    gl.bindFramebuffer(gl.FRAMEBUFFER, to.fb);
    gl.viewport(0, 0, to.w, to.h);
    gl.useProgram(this.prog);
    setUniforms(gl, this.prog, this.uniforms);
    const u = (name) => uniformLocation(gl, this.prog, name);
    gl.activeTexture(gl.TEXTURE0);
    gl.bindTexture(gl.TEXTURE_2D, from.tex);
    gl.uniform1i(u("u_prev"), 0);
    gl.uniform1f(u("u_n"), to.w);
    gl.uniform1ui(u("u_frame"), this.frames);
    gl.uniform1ui(u("u_seed"), this.seed);
    gl.uniform1i(u("u_pairs"), pairs);
    gl.uniform3fv(u("u_key"), this.key);
    gl.uniform3fv(u("u_colour"), this.colour);
    gl.uniform1i(u("u_env"), this.env === MAP ? 4 : ENVIRONMENTS.indexOf(this.env));
    if (this.env === MAP) {
      [this.mapTex.map, this.mapTex.rows, this.mapTex.cols].forEach((t, k) => {
        gl.activeTexture(gl.TEXTURE1 + k);
        gl.bindTexture(gl.TEXTURE_2D, t);
        gl.uniform1i(u(["u_map", "u_map_rows", "u_map_cols"][k]), 1 + k);
      });
      gl.activeTexture(gl.TEXTURE0);
    }
    gl.uniform1f(u("u_cone_cos"), CONE_DEG[this.env] ? Math.cos(CONE_DEG[this.env] * DEG) : 1);
    const [key, fill] = DISCS[this.env] || [[1, 1], [1, 1]];
    gl.uniform2fv(u("u_disc_key"), edges(key));
    gl.uniform2fv(u("u_disc_fill"), edges(fill));
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    this.frames++;
    this.samples += pairs;
    this.current = to;
    this.show();
  }

  /** The mean so far drawn on the canvas (×2^exposure, sRGB): after a step, or when only
   * the exposure changed. */
  show() {
    const { gl } = this;
    if (!this.current || !this.samples) return;
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    gl.viewport(0, 0, this.n, this.n);
    gl.useProgram(this.display);
    gl.activeTexture(gl.TEXTURE0);
    gl.bindTexture(gl.TEXTURE_2D, this.current.tex);
    gl.uniform1i(uniformLocation(gl, this.display, "u_sum"), 0);
    gl.uniform1f(uniformLocation(gl, this.display, "u_n"), this.n);
    gl.uniform1f(uniformLocation(gl, this.display, "u_count"), this.samples);
    gl.uniform1f(uniformLocation(gl, this.display, "u_scale"), 2 ** (this.exposure - ENV_EXPOSURE_OFFSET));
    gl.drawArrays(gl.TRIANGLES, 0, 3);
  }

  /** Sample pairs per pixel so far, the image's mean luminance over the disk and its
   * standard error (√Σσ²/P), and the image's relative noise: the RMS over the pixels of
   * each pixel's standard error (from its own samples), over the mean — render.py's
   * definitions (noise.mean_radiance_error, noise.relative), so the two compare. */
  stats() {
    const N = this.samples;
    if (!this.current || N < 2) return null;
    const raw = readTarget(this.gl, this.current);
    const n = this.current.w;
    let sum = 0, varSum = 0, P = 0;
    for (let j = 0; j < n; j++) {
      for (let i = 0; i < n; i++) {
        const x = -1 + (2 * i + 1) / n, y = -1 + (2 * j + 1) / n;
        if (x * x + y * y >= 1) continue;
        const q = 4 * (j * n + i);
        const s1 = LUMINANCE[0] * raw[q] + LUMINANCE[1] * raw[q + 1] + LUMINANCE[2] * raw[q + 2], s2 = raw[q + 3];
        sum += s1 / N;
        varSum += Math.max(s2 - (s1 * s1) / N, 0) / (N - 1) / N;
        P++;
      }
    }
    const mean = sum / P;
    return { samples: N, pixels: P, mean, error: Math.sqrt(varSum) / P,
             relative: mean > 0 ? Math.sqrt(varSum / P) / mean : 0 };
  }

  /** Each disk pixel's mean radiance so far, r, g, b in turn (rows from the bottom, the
   * disk's pixels in order): for checking the image against closed forms and the stated
   * noise against independent images. */
  pixelMeans() {
    const raw = readTarget(this.gl, this.current), n = this.current.w, N = this.samples, out = [];
    for (let j = 0; j < n; j++) {
      for (let i = 0; i < n; i++) {
        const x = -1 + (2 * i + 1) / n, y = -1 + (2 * j + 1) / n;
        const q = 4 * (j * n + i);
        if (x * x + y * y < 1) out.push(raw[q] / N, raw[q + 1] / N, raw[q + 2] / N);
      }
    }
    return out;
  }
}
