/* A BRDF measured from GPU evaluations read back (float32 render targets): its albedo
 * E(μ_v) with a stated error, the white furnace, reciprocity, positivity, NaN/∞ and
 * where, and the largest difference from another BRDF (a registry model's code).
 *
 * Every number comes from f(l, v) evaluated on the GPU at direction pairs the page
 * chooses (one texel each, two RGBA32F inputs), summed in float64 in JS.
 */
import { FULLSCREEN_VS, program, floatTexture, floatTarget, readTarget, setUniforms } from "./gl.js";
import { HEAD } from "./sphere.js";

/** Texels per row of the pair textures. */
const WIDTH = 256;
/** θ ≤ 88° for the pairs that compare two BRDFs (as tests/e2e/test_shader_webgl.py). */
const THETA_MAX = (88 * Math.PI) / 180;
/** μ_v at which E is measured (μ = 0 is the grazing limit, left out). */
export const MU = [0.1, 0.25, 0.5, 0.75, 1.0];
/** The albedo's quadrature: Gauss-Legendre in μ_l × the midpoint rule in φ (spectrally
 * accurate for a periodic integrand); its error is stated as |E − E at half the nodes
 * each way|, a bound when the quadrature has converged, and a warning when it has not. */
export const ALBEDO_NODES = { mu: 128, phi: 256 };
/** The float32 evaluation's share of the albedo's stated error, relative: the generated
 * GLSL is held to 1e-5 of float64 (tests/e2e/test_shader_webgl.py); a user's shader is
 * assumed no worse (its difference from a registry twin, measured below, shows it). */
export const FLOAT32_REL = 1e-5;
/** Relative to the largest |f| seen: below FLOOR·peak a difference counts against it. */
export const FLOOR = 1e-6;

const PAIRS_MAIN = `
uniform highp sampler2D u_l;
uniform highp sampler2D u_v;
out vec4 color;
void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  vec3 l = texelFetch(u_l, p, 0).xyz;
  vec3 v = texelFetch(u_v, p, 0).xyz;
  color = vec4(brdf(vec3(0.0, 0.0, 1.0), l, v), 1.0);
}`;

/** Gauss-Legendre nodes and weights on [0, 1] (Newton on P_n; Golub-Welsch would do too). */
export function gaussLegendre(n) {
  const x = new Float64Array(n), w = new Float64Array(n);
  for (let i = 0; i < n; i++) {
    let z = Math.cos((Math.PI * (i + 0.75)) / (n + 0.5)), dp = 0;
    for (let it = 0; it < 100; it++) {
      let p0 = 1, p1 = z;
      for (let k = 2; k <= n; k++) [p0, p1] = [p1, ((2 * k - 1) * z * p1 - (k - 1) * p0) / k];
      dp = (n * (z * p1 - p0)) / (z * z - 1);
      const dz = p1 / dp;
      z -= dz;
      if (Math.abs(dz) < 1e-16) break;
    }
    x[i] = (1 - z) / 2;
    w[i] = 1 / ((1 - z * z) * dp * dp);            // 2/((1−z²)P'²) on [−1, 1], halved
  }
  return { x, w };
}

/** Evaluates compiled BRDFs at direction pairs on one WebGL2 context. */
export class PairEvaluator {
  constructor(gl) {
    this.gl = gl;
  }

  /** A program for GLSL defining brdf(n, l, v); throws ShaderError. */
  compile(glsl, opts = {}) {
    const head = HEAD.split("\n").length - 1;
    return program(this.gl, FULLSCREEN_VS, HEAD + glsl + PAIRS_MAIN, { ...opts, offset: (opts.offset || 0) + head });
  }

  /** f (RGB) at pairs: l, v as Float64Array/Array of 3·count; returns Float32Array 4·count. */
  run(prog, uniforms, l, v) {
    const gl = this.gl;
    const count = l.length / 3, h = Math.ceil(count / WIDTH);
    const pack = (d) => {
      const out = new Float32Array(WIDTH * h * 4);
      for (let i = 0; i < count; i++) out.set([d[3 * i], d[3 * i + 1], d[3 * i + 2], 0], 4 * i);
      return out;
    };
    gl.activeTexture(gl.TEXTURE0);
    const tl = floatTexture(gl, WIDTH, h, pack(l));
    gl.activeTexture(gl.TEXTURE1);
    const tv = floatTexture(gl, WIDTH, h, pack(v));
    gl.activeTexture(gl.TEXTURE2);                 // not a unit the inputs are bound to
    const target = floatTarget(gl, WIDTH, h);
    gl.bindFramebuffer(gl.FRAMEBUFFER, target.fb);
    gl.viewport(0, 0, WIDTH, h);
    gl.useProgram(prog);
    setUniforms(gl, prog, uniforms);
    gl.uniform1i(gl.getUniformLocation(prog, "u_l"), 0);
    gl.uniform1i(gl.getUniformLocation(prog, "u_v"), 1);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    const out = readTarget(gl, target).subarray(0, 4 * count);
    for (const t of [tl, tv, target.tex]) gl.deleteTexture(t);
    gl.deleteFramebuffer(target.fb);
    return out;
  }
}

/** How long one pixel of a shader may take before it is refused as one that would stall
 * the GPU (a 256² sphere of it would take 65 536 times as long on a software GPU). */
export const PROBE_LIMIT_MS = 300;

/** Draws one pixel of `prog` (n = l = v = +z) and waits for it without blocking the page
 * (a fence polled from timers): resolves to the milliseconds it took, or null when it
 * is still running after PROBE_LIMIT_MS. */
export function probe(gl, prog, uniforms) {
  const target = (gl.activeTexture(gl.TEXTURE2), floatTarget(gl, 1, 1));
  gl.activeTexture(gl.TEXTURE0);
  const tl = floatTexture(gl, 1, 1, new Float32Array([0, 0, 1, 0]));
  gl.activeTexture(gl.TEXTURE1);
  const tv = floatTexture(gl, 1, 1, new Float32Array([0, 0, 1, 0]));
  gl.bindFramebuffer(gl.FRAMEBUFFER, target.fb);
  gl.viewport(0, 0, 1, 1);
  gl.useProgram(prog);
  setUniforms(gl, prog, uniforms);
  gl.uniform1i(gl.getUniformLocation(prog, "u_l"), 0);
  gl.uniform1i(gl.getUniformLocation(prog, "u_v"), 1);
  const t0 = performance.now();
  gl.drawArrays(gl.TRIANGLES, 0, 3);
  const sync = gl.fenceSync(gl.SYNC_GPU_COMMANDS_COMPLETE, 0);
  gl.flush();
  gl.bindFramebuffer(gl.FRAMEBUFFER, null);
  return new Promise((resolve) => {
    const poll = () => {
      if (gl.isContextLost()) return resolve(null);
      if (gl.getSyncParameter(sync, gl.SYNC_STATUS) === gl.SIGNALED) {
        gl.deleteSync(sync);
        for (const t of [tl, tv, target.tex]) gl.deleteTexture(t);
        gl.deleteFramebuffer(target.fb);
        return resolve(performance.now() - t0);
      }
      if (performance.now() - t0 > PROBE_LIMIT_MS) return resolve(null);
      setTimeout(poll, 5);
    };
    setTimeout(poll, 0);
  });
}

const dir = (theta, phi) => [Math.sin(theta) * Math.cos(phi), Math.sin(theta) * Math.sin(phi), Math.cos(theta)];

/** The albedo's pairs: for each μ_v of `mus` (v at azimuth `phiV`, radians), l over
 * Gauss-Legendre μ_l × the midpoint rule in φ; weights dω cos θ_l = dμ dφ μ. */
export function albedoPairs(nMu, nPhi, mus = MU, phiV = 0) {
  const { x, w } = gaussLegendre(nMu);
  const l = [], v = [], weights = [];
  for (const muV of mus) {
    const sv = Math.sqrt(1 - muV * muV);
    const vv = [sv * Math.cos(phiV), sv * Math.sin(phiV), muV];
    for (let i = 0; i < nMu; i++) {
      const s = Math.sqrt(1 - x[i] * x[i]);
      for (let j = 0; j < nPhi; j++) {
        const phi = (2 * Math.PI * (j + 0.5)) / nPhi;
        l.push(s * Math.cos(phi), s * Math.sin(phi), x[i]);
        v.push(...vv);
        weights.push((w[i] * x[i] * 2 * Math.PI) / nPhi);
      }
    }
  }
  return { l, v, weights, per: nMu * nPhi, count: mus.length };
}

/** Seeded pairs in the closed-off upper hemisphere, θ ≤ 88° (mulberry32: reproducible). */
export function randomPairs(count, seed = 7) {
  let a = seed >>> 0;
  const rnd = () => {
    a = (a + 0x6d2b79f5) >>> 0;
    let t = a;
    t = Math.imul(t ^ (t >>> 15), t | 1);
    t ^= t + Math.imul(t ^ (t >>> 7), t | 61);
    return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
  };
  const l = [], v = [];
  for (let i = 0; i < count; i++) {
    l.push(...dir(Math.acos(1 - rnd() * (1 - Math.cos(THETA_MAX))), 2 * Math.PI * rnd()));
    v.push(...dir(Math.acos(1 - rnd() * (1 - Math.cos(THETA_MAX))), 2 * Math.PI * rnd()));
  }
  return { l, v };
}

const degOf = (d) => [Math.acos(Math.min(1, d[2])) * 180 / Math.PI, Math.atan2(d[1], d[0]) * 180 / Math.PI];
const at = (arr, i) => [arr[3 * i], arr[3 * i + 1], arr[3 * i + 2]];
const where = (l, v, i) => {
  const [tl, pl] = degOf(at(l, i)), [tv, pv] = degOf(at(v, i));
  return { theta_l: tl, phi_l: pl, theta_v: tv, phi_v: pv };
};

/** NaN/∞ and negative values among f's channels at the pairs: counts and the first place. */
function scan(f, l, v, found) {
  for (let i = 0; i < f.length / 4; i++) {
    for (let c = 0; c < 3; c++) {
      const x = f[4 * i + c];
      if (!Number.isFinite(x)) { found.nonFinite++; found.firstNonFinite ??= { ...where(l, v, i), value: String(x) }; }
      else if (x < 0) { found.negative++; if (x < found.min) { found.min = x; found.minAt = where(l, v, i); } }
    }
  }
}

/** E(μ_v) per channel from one quadrature's evaluations (count μ_v of `per` pairs each). */
export function albedoOf(f, weights, per, count = MU.length) {
  return Array.from({ length: count }, (_, k) => {
    const e = [0, 0, 0];
    for (let i = k * per; i < (k + 1) * per; i++) for (let c = 0; c < 3; c++) e[c] += weights[i] * f[4 * i + c];
    return e;
  });
}

/** Everything measured about one compiled BRDF; `other`: {prog, uniforms} of the model to
 * compare with, or null. */
export function measure(ev, prog, uniforms, other = null) {
  const found = { nonFinite: 0, firstNonFinite: null, negative: 0, min: 0, minAt: null };
  const fine = albedoPairs(ALBEDO_NODES.mu, ALBEDO_NODES.phi);
  const coarse = albedoPairs(ALBEDO_NODES.mu / 2, ALBEDO_NODES.phi / 2);
  const fFine = ev.run(prog, uniforms, fine.l, fine.v);
  const fCoarse = ev.run(prog, uniforms, coarse.l, coarse.v);
  scan(fFine, fine.l, fine.v, found);
  const E = albedoOf(fFine, fine.weights, fine.per), E2 = albedoOf(fCoarse, coarse.weights, coarse.per);
  const albedo = MU.map((mu, k) => ({ mu, E: E[k],
    error: Math.max(...[0, 1, 2].map((c) => Math.abs(E[k][c] - E2[k][c]) + FLOAT32_REL * Math.abs(E[k][c]))) }));
  const furnace = albedo.reduce((m, a) => (Math.max(...a.E) > m.E ? { mu: a.mu, E: Math.max(...a.E), error: a.error } : m), { mu: null, E: -Infinity, error: 0 });
  // reciprocity: f(l, v) against f(v, l) on random pairs
  const r = randomPairs(4096);
  const fLV = ev.run(prog, uniforms, r.l, r.v), fVL = ev.run(prog, uniforms, r.v, r.l);
  scan(fLV, r.l, r.v, found);
  const rel = (a, b, floor) => (a === b ? 0 : Math.abs(a - b) / Math.max(Math.abs(b), floor));
  let peak = 0;
  for (let i = 0; i < fLV.length; i++) if (i % 4 !== 3 && Number.isFinite(fLV[i])) peak = Math.max(peak, Math.abs(fLV[i]));
  let recip = { max: 0, at: null };
  for (let i = 0; i < fLV.length / 4; i++) {
    for (let c = 0; c < 3; c++) {
      const d = rel(fLV[4 * i + c], fVL[4 * i + c], FLOOR * peak);
      if (d > recip.max) recip = { max: d, at: where(r.l, r.v, i) };
    }
  }
  const out = { albedo, furnace, reciprocity: recip, positivity: found, peak, pairs: fine.l.length / 3 + 2 * r.l.length / 3 };
  if (other) {
    const g = ev.run(other.prog, other.uniforms, r.l, r.v);
    const gFine = ev.run(other.prog, other.uniforms, fine.l, fine.v);
    let otherPeak = 0;
    for (let i = 0; i < g.length; i++) if (i % 4 !== 3 && Number.isFinite(g[i])) otherPeak = Math.max(otherPeak, Math.abs(g[i]));
    let diff = { max: 0, at: null };
    for (const [a, b, L, V] of [[fLV, g, r.l, r.v]]) {
      for (let i = 0; i < a.length / 4; i++) {
        for (let c = 0; c < 3; c++) {
          const d = rel(a[4 * i + c], b[4 * i + c], FLOOR * otherPeak);
          if (d > diff.max || (Number.isNaN(d) && Number.isFinite(diff.max))) diff = { max: d, at: where(L, V, i) };
        }
      }
    }
    const Eo = albedoOf(gFine, fine.weights, fine.per);
    out.difference = { ...diff, pairs: r.l.length / 3, albedo: MU.map((mu, k) => ({ mu, E: Eo[k] })) };
  }
  return out;
}
