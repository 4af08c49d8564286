/* The running average of independent renders of the environment sphere, pixel by pixel,
 * and the noise it states. Each render is the data route's answer (GET
 * /api/v1/sphere_env: `radiance` n×n×3 linear, nulls off the sphere; `std_error` n×n, each
 * pixel's standard error of its luminance; `background` n×n×3), one seed each. k renders'
 * errors σ_j combine to √(Σσ_j²)/k per pixel, the variance of a mean of independent
 * estimates (Bienaymé); the image's relative noise is their RMS over the pixels over the
 * mean luminance — app/environment/render.py's `averaged` and `stated_noise`, the same
 * statement as one render's `noise.relative`.
 */

/** Rec. 709 luminance of linear RGB (render.py's LUMINANCE): the noise is stated on it. */
export const LUMINANCE = [0.2126, 0.7152, 0.0722];

/** The sRGB transfer function (IEC 61966-2-1) of a value clipped to [0, 1], as 0–255:
 * app/figures/sphere_image.py's srgb8, which drew the sphere's first image. */
export function srgb8(linear) {
  const c = Math.min(Math.max(linear, 0), 1);
  return Math.round((c <= 0.0031308 ? 12.92 * c : 1.055 * c ** (1 / 2.4) - 0.055) * 255);
}

export class RenderAverage {
  constructor() {
    this.k = 0;            // renders averaged
    this.samples = 0;      // their samples per pixel, all together
  }

  /** One more render (the data route's answer) into the average. */
  add(body) {
    const rows = body.radiance, n = rows.length;
    if (!this.k) {
      this.n = n;
      this.on = new Uint8Array(n * n);             // the pixels on the sphere
      this.sum = new Float64Array(n * n * 3);      // Σ L_o per pixel and channel
      this.variance = new Float64Array(n * n);     // Σ σ_j² per pixel
      this.background = body.background;
    }
    for (let i = 0; i < n; i++) {
      for (let j = 0; j < n; j++) {
        const rgb = rows[i][j];
        if (rgb[0] === null) continue;             // off the sphere (NaN, sent as null): the background
        const p = i * n + j, sigma = body.std_error[i][j];
        this.on[p] = 1;
        for (let c = 0; c < 3; c++) this.sum[3 * p + c] += rgb[c];
        this.variance[p] += sigma * sigma;
      }
    }
    this.k += 1;
    this.samples += body.samples.per_pixel;
  }

  /** The averaged image's relative noise: √(mean over the pixels of (√Σσ_j²/k)²) over
   * the mean luminance of the average. */
  noise() {
    let lum = 0, variance = 0, pixels = 0;
    for (let p = 0; p < this.on.length; p++) {
      if (!this.on[p]) continue;
      for (let c = 0; c < 3; c++) lum += LUMINANCE[c] * this.sum[3 * p + c];
      variance += this.variance[p];
      pixels += 1;
    }
    const mean = lum / this.k / pixels;
    return mean > 0 ? Math.sqrt(variance / (this.k * this.k) / pixels) / mean : 0;
  }

  /** The average over its background as 8-bit sRGB RGBA (row 0 at the top, as the data's
   * rows), ×2^exposure first: what sphere_image.py's figure shows of one render. */
  rgba(exposureEv) {
    const n = this.n, scale = 2 ** exposureEv / this.k, out = new Uint8ClampedArray(n * n * 4);
    for (let i = 0; i < n; i++) {
      for (let j = 0; j < n; j++) {
        const p = i * n + j;
        for (let c = 0; c < 3; c++) {
          const linear = this.on[p] ? this.sum[3 * p + c] * scale : 2 ** exposureEv * this.background[i][j][c];
          out[4 * p + c] = srgb8(linear);
        }
        out[4 * p + 3] = 255;
      }
    }
    return out;
  }
}
