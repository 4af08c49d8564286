/* The truth toggle: the GPU's float32 frame against the server's float64 render of the
 * same frame (GET /api/v1/reference/sphere: the same pixel centres and the very float32
 * light vector the GPU drew with), per pixel and per channel.
 *
 * Relative difference |gpu − ref| / max(|ref|, FLOOR·peak), stated two ways:
 * - over the pixels where both directions are at most GRAZING_DEG from the normal (the
 *   band in which the generated GLSL is held to 1e-5 by tests/e2e/test_shader_webgl.py):
 *   the float32 error of the BRDF itself;
 * - over the whole disk, as an absolute difference in units of the frame's peak. Near the
 *   terminator and the rim, n·l and n·v are sums that cancel: float32 rounds each term by
 *   ~6e-8, so μ ≈ 1e-4 carries a relative error of ~1e-3 whatever the shader does — a
 *   property of float32 input, not of the model. Both numbers are shown.
 */
import { API, apiMessage, query } from "../base/dom.js";

/** Relative to the frame's brightest channel value: below FLOOR·peak a pixel's
 * difference counts as absolute, in units of the peak. */
export const FLOOR = 1e-6;
/** The well-conditioned band: θ_l, θ_v ≤ 88° (μ ≥ cos 88° ≈ 0.035). */
export const GRAZING_DEG = 88;
const DEG = Math.PI / 180;
/** cos GRAZING_DEG: a direction with n·ω below it is outside the band. */
export const MU_MIN = Math.cos((GRAZING_DEG * Math.PI) / 180);

/** The server's float64 frame: Float64Array n·n·3, rows from the top, NaN off the disk. */
export async function referenceFrame(model, light, n) {
  const [lx, ly, lz] = light;
  const res = await fetch(`${API}/reference/sphere?${query({ ...model, lx, ly, lz, n })}`);
  if (!res.ok) throw new Error(apiMessage(await res.json().catch(() => null), res));
  return new Float64Array(await res.arrayBuffer());
}

/** The server's float64 slice (GET /api/v1/reference/slice): Float64Array n·n·3, rows
 * θ_d from 0, NaN below the horizon. */
export async function referenceSlice(model, phiH, phiD, n) {
  const res = await fetch(`${API}/reference/slice?${query({ ...model, phi_h_deg: phiH, phi_d_deg: phiD, n })}`);
  if (!res.ok) throw new Error(apiMessage(await res.json().catch(() => null), res));
  return new Float64Array(await res.arrayBuffer());
}

/** Per-pixel relative difference (Float32Array n·n, NaN off the disk) with its largest
 * and mean value in the well-conditioned band, where the largest is, the largest absolute
 * difference over the whole disk in units of the peak, and the pixels that are NaN/∞. */
export function compare(gpu, ref, n, light) {
  return compareFrame(gpu, ref, n, (p) => {
    const x = -1 + (2 * (p % n) + 1) / n, y = 1 - (2 * Math.floor(p / n) + 1) / n;
    const muV = Math.sqrt(Math.max(0, 1 - x * x - y * y));
    return x * light[0] + y * light[1] + muV * light[2] >= MU_MIN && muV >= MU_MIN;
  });
}

/** The same for the slice: the band is θ_l, θ_v ≤ GRAZING_DEG of the directions drawn
 * (l, v: the slice's float32 direction arrays, 4 per pixel). */
export function compareSlice(gpu, ref, n, l, v) {
  return compareFrame(gpu, ref, n, (p) => l[4 * p + 2] >= MU_MIN && v[4 * p + 2] >= MU_MIN);
}

/** gpu: float32 RGBA per pixel; ref: float64 RGB, NaN where the frame has no value;
 * inBand(p): the pixel counts towards the relative statistics. */
export function compareFrame(gpu, ref, n, inBand) {
  const r = compareSamples(gpu, ref, n * n, { inBand });
  return { ...r, at: r.at === null ? null : [r.at % n, Math.floor(r.at / n)] };
}

/** The statistics of compareFrame over `count` samples of `channels` values each, at
 * strides gpuStride (float32) and refStride (float64); `at` is the sample's index. */
export function compareSamples(gpu, ref, count, { gpuStride = 4, refStride = 3, channels = 3, inBand = () => true } = {}) {
  let peak = 0;
  for (let p = 0; p < count; p++) {
    for (let c = 0; c < channels; c++) {
      const r = ref[p * refStride + c];
      if (Number.isFinite(r) && Math.abs(r) > peak) peak = Math.abs(r);
    }
  }
  const floor = FLOOR * peak;
  const diff = new Float32Array(count).fill(NaN);
  let max = 0, sum = 0, inside = 0, at = null, nonFinite = 0, absMax = 0, disk = 0;
  for (let p = 0; p < count; p++) {
    if (Number.isNaN(ref[p * refStride])) continue;    // no value here (off the disk, below the horizon)
    disk++;
    let worst = 0, abs = 0;
    for (let c = 0; c < channels; c++) {
      const r = ref[p * refStride + c], g = gpu[p * gpuStride + c];
      if (!Number.isFinite(g) || !Number.isFinite(r)) { worst = abs = Infinity; continue; }
      worst = Math.max(worst, Math.abs(g - r) / Math.max(Math.abs(r), floor));
      abs = Math.max(abs, Math.abs(g - r));
    }
    if (!Number.isFinite(worst)) { nonFinite++; continue; }
    absMax = Math.max(absMax, abs);
    diff[p] = worst;
    if (!inBand(p)) continue;
    sum += worst;
    inside++;
    if (worst > max) { max = worst; at = p; }
  }
  return { diff, max, mean: inside ? sum / inside : 0, at, pixels: inside, disk, nonFinite, floor, peak,
           absPeak: peak > 0 ? absMax / peak : absMax };
}

/** (θ, φ) in degrees of the direction (x, y, z), in float64 (φ in [0, 360)): what the
 * server's direction_deg turns back into the unit vector along it. */
export function anglesDeg(x, y, z) {
  const theta = Math.atan2(Math.hypot(x, y), z) / DEG;
  const phi = Math.atan2(y, x) / DEG;
  return [theta, phi < 0 ? phi + 360 : phi];
}

/** The server's float64 f (POST /api/v1/eval, Rec. 709 luminance for a coloured model)
 * of `model` for the light `light` and the views `dirs` (flat x, y, z; float32 values),
 * each sent as its exact angles: Float64Array, NaN where the server has no value. */
export async function referenceF(model, light, dirs) {
  const count = dirs.length / 3, to = [], po = [];
  for (let k = 0; k < count; k++) {
    const [t, p] = anglesDeg(dirs[3 * k], dirs[3 * k + 1], dirs[3 * k + 2]);
    to.push(t);
    po.push(p);
  }
  const [ti, pi] = anglesDeg(...light);
  const res = await fetch(`${API}/eval`, { method: "POST", headers: { "Content-Type": "application/json" },
    body: JSON.stringify({ ...model, theta_i_deg: [ti], phi_i_deg: [pi], theta_o_deg: to, phi_o_deg: po, quantities: ["f"] }) });
  const body = await res.json().catch(() => null);
  if (!res.ok || !body) throw new Error(apiMessage(body, res));
  return Float64Array.from(body.f, (f) => (f === null ? NaN : f));
}

/** A relative difference as stated on the page: two significant digits. */
export const fmt = (x) => (x === 0 ? "0" : x.toExponential(1));

/** The sphere's truth line for compare()'s answer. */
export function sphereTruthText(r) {
  const where = r.at ? ` at pixel (${r.at[0]}, ${r.at[1]})` : "";
  return `GPU (float32) against the server (float64), same frame: largest relative difference `
    + `${fmt(r.max)}${where}, mean ${fmt(r.mean)} over the ${r.pixels} pixels with θ_l, θ_v ≤ ${GRAZING_DEG}°; `
    + `over all ${r.disk} pixels the largest difference is ${fmt(r.absPeak)} of the peak `
    + `(near the terminator and the rim float32's rounding of n·l alone is ~1e-7)`
    + (r.nonFinite ? `; ${r.nonFinite} pixels NaN/∞` : "")
    + `. Right: the relative difference, log scale 1e-8 (dark) to 1e-3 (bright); below ${FLOOR}× the peak it counts against that floor.`;
}

/** The difference as an image: log10 from 1e-8 (black) to 1e-3 (white), magenta where
 * not finite, the background off the disk. ImageData-ready RGBA bytes. */
export function diffImage(diff, n) {
  const out = new Uint8ClampedArray(n * n * 4);
  for (let p = 0; p < n * n; p++) {
    const d = diff[p];
    let rgb;
    if (Number.isNaN(d)) rgb = [255, 255, 255];
    else {
      const t = Math.min(1, Math.max(0, (Math.log10(Math.max(d, 1e-12)) + 8) / 5));
      rgb = [255 * t, 255 * t * t, 255 * (1 - t) * t * 2];
    }
    out.set([...rgb, 255], p * 4);
  }
  return out;
}
