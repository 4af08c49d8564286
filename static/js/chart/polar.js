/* A polar plot (Plotly's layout.polar): θ in degrees turned by `rotation` and run
 * `direction` ("clockwise" or not), over the `sector` of the circle it shows (degrees,
 * counter-clockwise from the right); r linear or log (its range in decades), its
 * labels along the ray at `radialaxis.angle`. The lobe's: θ = 0 up, clockwise, the
 * upper half.
 */
import { Scale } from "./scale.js";
import { axisRange } from "./cartesian.js";

const RAD = Math.PI / 180;
const LABEL_ROOM = { x: 40, y: 26 };     // px beside and above the circle for the angle labels
const OUTER_ROOM = 10;
const RADIAL_SPACING = 26;               // px between radial labels, about (one line of 12 px text and a gap)                   // px: a radial label this close to the circle would meet an angle's

/** The sector's extent on the unit circle (centre included): [xmin, xmax, ymin, ymax], y up. */
function sectorBox([a0, a1]) {
  const xs = [0], ys = [0];
  const add = (a) => { xs.push(Math.cos(a * RAD)); ys.push(Math.sin(a * RAD)); };
  add(a0);
  add(a1);
  for (let a = Math.ceil(a0 / 90) * 90; a < a1; a += 90) add(a);
  return [Math.min(...xs), Math.max(...xs), Math.min(...ys), Math.max(...ys)];
}

const inSector = (phi, [a0, a1]) => {
  const d = (((phi - a0) % 360) + 360) % 360;
  return d <= a1 - a0 + 1e-9;
};

export function drawPolar(ctx, layout, traces, w, h, font) {
  const polar = layout.polar || {};
  const ang = polar.angularaxis || {}, rad = polar.radialaxis || {};
  const sector = Array.isArray(polar.sector) ? polar.sector : [0, 360];
  const rotation = Number.isFinite(ang.rotation) ? ang.rotation : 0;
  const sign = ang.direction === "clockwise" ? -1 : 1;
  const phiOf = (theta) => rotation + sign * theta;            // degrees, counter-clockwise from the right
  const [bx0, bx1, by0, by1] = sectorBox(sector);
  const R = Math.max(10, Math.min((w - 2 * LABEL_ROOM.x) / (bx1 - bx0), (h - 2 * LABEL_ROOM.y) / (by1 - by0)));
  const cx = w / 2 - ((bx0 + bx1) / 2) * R, cy = h / 2 + ((by0 + by1) / 2) * R + 4;
  const range = axisRange({ ...rad, rangemode: rad.type === "log" ? undefined : "tozero" }, traces, (tr) => tr.y, "r");
  const r = new Scale({ ...rad, range }, [0, R]);
  const area = { x: cx + bx0 * R, y: cy - by1 * R, w: (bx1 - bx0) * R, h: (by1 - by0) * R };
  const a0 = -sector[1] * RAD, a1 = -sector[0] * RAD;           // canvas angles run clockwise

  // background and grid
  ctx.fillStyle = polar.bgcolor || "#fff";
  ctx.beginPath(); ctx.moveTo(cx, cy); ctx.arc(cx, cy, R, a0, a1); ctx.closePath(); ctx.fill();
  const rTicks = r.ticks(R, RADIAL_SPACING).filter((t) => r.px(t.v) > 0.5);
  ctx.lineWidth = 1;
  ctx.strokeStyle = rad.gridcolor || "#e5e5e5";
  ctx.beginPath();
  for (const t of rTicks) { const p = r.px(t.v); ctx.moveTo(cx + p * Math.cos(a0), cy + p * Math.sin(a0)); ctx.arc(cx, cy, p, a0, a1); }
  const step = Number.isFinite(ang.dtick) && ang.dtick > 0 ? ang.dtick : 30;
  const thetas = [];
  for (let th = -180; th < 180 + 1e-9; th += step) if (inSector(phiOf(th), sector) && !thetas.some((o) => Math.abs(((phiOf(o) - phiOf(th)) % 360)) < 1e-6)) thetas.push(th);
  ctx.strokeStyle = ang.gridcolor || "#e5e5e5";
  for (const th of thetas) { const p = phiOf(th) * RAD; ctx.moveTo(cx, cy); ctx.lineTo(cx + R * Math.cos(p), cy - R * Math.sin(p)); }
  ctx.stroke();
  // the outline and the labels
  ctx.strokeStyle = "#444";
  ctx.beginPath(); ctx.arc(cx, cy, R, a0, a1);
  if (sector[1] - sector[0] < 360) { ctx.lineTo(cx, cy); ctx.closePath(); }
  ctx.stroke();
  ctx.fillStyle = font.color;
  ctx.font = font.tick;
  ctx.textBaseline = "middle";
  const suffix = ang.ticksuffix ?? "";
  for (const th of thetas) {
    const p = phiOf(th) * RAD, c = Math.cos(p), s = Math.sin(p);
    ctx.textAlign = Math.abs(c) < 0.2 ? "center" : c > 0 ? "left" : "right";
    const label = `${String(Math.round(th * 1e6) / 1e6).replace("-", "−")}${suffix}`;
    ctx.fillText(label, cx + (R + 6) * c, cy - (R + 6) * s - (Math.abs(c) < 0.2 ? 4 : 0));
  }
  const ra = (Number.isFinite(rad.angle) ? rad.angle : sector[0]) * RAD;
  ctx.textAlign = "left";
  for (const t of rTicks) {
    const p = r.px(t.v);
    if (p > R - OUTER_ROOM) continue;       // the outer circle's angle label is there
    ctx.fillText(t.label, cx + p * Math.cos(ra) + 4, cy - p * Math.sin(ra));
  }
  ctx.strokeStyle = "#444";
  ctx.beginPath();
  ctx.moveTo(cx, cy); ctx.lineTo(cx + R * Math.cos(ra), cy - R * Math.sin(ra));
  for (const t of rTicks) {
    const p = r.px(t.v), x0 = cx + p * Math.cos(ra), y0 = cy - p * Math.sin(ra);
    ctx.moveTo(x0, y0); ctx.lineTo(x0 + 4 * Math.sin(ra), y0 + 4 * Math.cos(ra));
  }
  ctx.stroke();

  // points: r below the axis's start at the centre, the rest clipped by the sector
  const at = (tr) => (i) => {
    const rho = Math.max(0, r.px(tr.y[i])), p = phiOf(tr.x[i]) * RAD;
    return Number.isFinite(rho) && Number.isFinite(p) ? [cx + rho * Math.cos(p), cy - rho * Math.sin(p)] : null;
  };
  const clip = () => { ctx.beginPath(); ctx.moveTo(cx, cy); ctx.arc(cx, cy, R + 1, a0, a1); ctx.closePath(); ctx.clip(); };
  return { area, at, clip, titles: {}, ranges: { r: range }, r, zeroY: () => cy, atY: null };
}
