/* What the page adds to GET /api/v1/views: presentation only (order, which panels open
 * by default, one sentence of what each shows). Titles, field roles, whether a view is
 * heavy (an image fetched coarser while a slider is held), overlayable and the room it
 * takes are the API's ("title", field "role", "heavy", "overlayable", "layout").
 *   shown: open by default; slice: its phi_deg follows the plane of incidence when
 *   anisotropic; keys: URL names of its toggles that predate generic panels; pin: made of
 *   curves, so POST /figures/{name} can overlay pinned models; tails: "compare tails";
 *   lightDrag: a sphere whose light is dragged on it (spheredrag.js); refine: a sampled image
 *   refined at rest by averaging independent renders (refine.js).
 */
export const HINTS = {
  lobe: { shown: true, pin: true, keys: { log: "log", cosine: "cosine" },
          caption: "f(l, v) in the plane of incidence: the light from θ_i sent towards each θ_o." },
  ndf: { shown: true, slice: true, pin: true, tails: true,
         caption: "D(θ_m): how the microfacet normals are spread around the surface normal." },
  g1: { shown: true, slice: true, pin: true,
        caption: "The fraction of microfacets seen from a direction, G₁ = 1/(1 + Λ), against its angle." },
  albedo: { shown: true, slice: true, pin: true, fields: ["tol"],
            caption: "The share of light the surface reflects for each incidence μ = cos θ, with its error." },
  lobe3d: {
            caption: "f over the whole hemisphere of outgoing directions, for the light at (θ_i, φ_i)." },
  g2: {
        caption: "G₂(θ_l, θ_v): the microfacets seen from both the light and the viewer." },
  fresnel: { pin: true,
             caption: "F(θ_d): the share reflected by one microfacet against the angle to its normal." },
  sphere: { lightDrag: true,
            caption: "A sphere of this material under one directional light at (θ_i, φ_i); drag on it to move the light." },
  sphere_env: { lightDrag: true, refine: true,
                caption: "A sphere of this material in an environment or under a point light; drag on it to move the light." },
  slice: {
           caption: "f over half-vector and difference angles, the image slice of Disney's BRDF explorer." },
  samples: {
             caption: "Directions drawn by the sampler for one view, against the density they should follow." },
  checks: {
            caption: "Identities the model must satisfy, each computed next to the value it must have." },
  tradeoff: {
              caption: "The albedo's error against its cost, for each integration method." },
  advise: { fields: ["tol"],
            caption: "Cheaper choices of the model, their largest error over the scene and their cost." },
};
export const PANEL_ORDER = ["lobe", "ndf", "g1", "albedo"];   // first; then the API's order

/* The page's own panels (not views of the API), each after the view it is placed beside
 * in the PANELS bar and the grid; shown and linked like the others (show=). */
export const PAGE_PANELS = [
  { name: "gpu", title: "Live sphere (GPU)", after: "sphere",
    caption: "The lit sphere drawn per pixel in your browser (WebGL2) from the generated shader; drag on it to move the light." },
];

/** Every panel of the PANELS bar, in order: the API's views (sorted already) with the
 * page's own inserted after the view each names. */
export function panelList(views) {
  const list = views.map((v) => ({ name: v.name, title: viewTitle(v), caption: hintOf(v.name).caption || v.summary }));
  for (const p of PAGE_PANELS) {
    const at = list.findIndex((x) => x.name === p.after);
    list.splice(at < 0 ? list.length : at + 1, 0, p);
  }
  return list;
}

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

export const hintOf = (name) => HINTS[name] || {};
export const viewTitle = (view) => view.title || view.name;
export const fieldRole = (f) => f.role || (f.type === "boolean" ? "display" : "shape");
/** A heavy image (fetched coarser while a slider is held): the view's `heavy`. */
export const isHeavy = (view) => !!view.heavy;
/** The room a view takes: the view's `layout` (half | wide | strip). */
export const layoutOf = (view) => view.layout;
/** Whether a view overlays models or values (pins, vary): the view's `overlayable`. */
export const overlayable = (view) => !!view.overlayable;

/** A panel field's state key and element id ("view.field" cannot collide with a model
 * parameter: those have no dots). */
export const localKey = (view, field) => hintOf(view).keys?.[field] || `${view}.${field}`;
export const localId = (view, field) => hintOf(view).keys?.[field] || `${view}-${field.replace(/_/g, "-")}`;

/** A panel field's label: the page's table, else the API name made readable. */
export function fieldLabel(view, f) {
  return VIEW_FIELD_LABELS[view.name]?.[f.name] || f.label || FIELD_LABELS[f.name]
    || f.name.replace(/_deg$/, " (°)").replace(/^phi/, "φ").replace(/^theta/, "θ").replace(/^alpha/, "α");
}
