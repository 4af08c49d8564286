/* What the page adds to GET /api/v1/views: presentation only (order, size, which
 * panels open by default, one sentence of what each shows). Titles and field roles
 * come from the API when it declares them ("title", field "role"); the table here is
 * the fallback for a server that does not.
 *   shown: open by default; slice: its phi_deg follows the plane of incidence when
 *   anisotropic; keys: URL names of its toggles that predate generic panels; wide /
 *   short: layout; pin: made of curves, so POST /figures/{name} can overlay pinned
 *   models; tails: "compare tails"; heavy: an image fetched coarser while a slider is held;
 *   lightDrag: a sphere whose light is dragged on it (spheredrag.js).
 */
export const HINTS = {
  lobe: { title: "BRDF lobe", shown: true, pin: true, keys: { log: "log", cosine: "cosine" },
          caption: "f(l, v) in the plane of incidence: the light from θ_i sent towards each θ_o." },
  ndf: { title: "Normal distribution D", shown: true, slice: true, pin: true, tails: true,
         caption: "D(θ_m): how the microfacet normals are spread around the surface normal." },
  g1: { title: "Smith masking Λ and G_1", shown: true, slice: true, pin: true,
        caption: "The fraction of microfacets seen from a direction, G₁ = 1/(1 + Λ), against its angle." },
  albedo: { title: "Directional albedo E(μ)", shown: true, slice: true, pin: true, fields: ["tol"],
            caption: "The share of light the surface reflects for each incidence μ = cos θ, with its error." },
  lobe3d: { title: "3-D lobe", wide: true, heavy: true,
            caption: "f over the whole hemisphere of outgoing directions, for the light at (θ_i, φ_i)." },
  g2: { title: "Masking-shadowing G_2",
        caption: "G₂(θ_l, θ_v): the microfacets seen from both the light and the viewer." },
  fresnel: { title: "Fresnel F", pin: true,
             caption: "F(θ_d): the share reflected by one microfacet against the angle to its normal." },
  sphere: { title: "Lit sphere", heavy: true, lightDrag: true,
            caption: "A sphere of this material under one directional light at (θ_i, φ_i); drag on it to move the light." },
  sphere_env: { heavy: true, lightDrag: true,
                caption: "A sphere of this material in an environment or under a point light; drag on it to move the light." },
  slice: { title: "θ_h / θ_d slice", heavy: true,
           caption: "f over half-vector and difference angles, the image slice of Disney's BRDF explorer." },
  samples: { title: "Importance sampling", heavy: true,
             caption: "Directions drawn by the sampler for one view, against the density they should follow." },
  checks: { title: "Identity checks", wide: true,
            caption: "Identities the model must satisfy, each computed next to the value it must have." },
  tradeoff: { title: "Speed against accuracy", wide: true,
              caption: "The albedo's error against its cost, for each integration method." },
  advise: { title: "Model only what the scene needs", wide: true, short: true, fields: ["tol"],
            caption: "Cheaper choices of the model, their largest error over the scene and their cost." },
};
export const PANEL_ORDER = ["lobe", "ndf", "g1", "albedo"];   // first; then the API's order

/* Where the page starts a panel's field elsewhere than the API's default. The albedo:
 * auto, the cheapest method whose bound meets the panel's tol (the E(μ, α) table of the
 * default models, 9.8e-6 ≤ 1e-5, in 0.5–1 ms against the quadrature's 9 ms; the legend
 * names the method taken): a slider then redraws it within a frame. */
export const PAGE_DEFAULTS = { albedo: { method: "auto" } };

// Labels of panel fields (the API's names otherwise); roles where the API gives none.
export const FIELD_LABELS = { log: "log scale", display: "display", exposure: "exposure (stops)", y_range: "y axis" };
export const OPTION_LABELS = { y_range: { fit: "fitted to the data", unit: "0–1" } };
export const VIEW_FIELD_LABELS = {
  lobe: { cosine: "f·cos θ_o" },
  ndf: { cosine: "× cos θ_m" },
  slice: { cosine: "× cos θ_l" },
};
const FALLBACK_ROLES = { n: "resolution", n_theta: "resolution", n_phi: "resolution", mu: "resolution",
                         tol: "resolution", order: "resolution" };

export const hintOf = (name) => HINTS[name] || {};
export const viewTitle = (view) => view.title || hintOf(view.name).title || view.name;
export const fieldRole = (f) => f.role || FALLBACK_ROLES[f.name] || (f.type === "boolean" ? "display" : "shape");

/** A panel field's state key and element id ("view.field" cannot collide with a model
 * parameter: those have no dots). */
export const localKey = (view, field) => hintOf(view).keys?.[field] || `${view}.${field}`;
export const localId = (view, field) => hintOf(view).keys?.[field] || `${view}-${field.replace(/_/g, "-")}`;

/** A panel field's label: the page's table, else the API name made readable. */
export function fieldLabel(view, f) {
  return VIEW_FIELD_LABELS[view.name]?.[f.name] || f.label || FIELD_LABELS[f.name]
    || f.name.replace(/_deg$/, " (°)").replace(/^phi/, "φ").replace(/^theta/, "θ").replace(/^alpha/, "α");
}
