"""The gallery: canonical figures of the microfacet literature, each a state of one view,
and a card for each capability that is not one view's figure (an example data set on a
view, a fit, shader code, a LUT, the roughness conventions: ``kind`` names it, and
gallery/cards.py builds its links).

Each entry lists candidate states, best first; the gallery shows the first that the API
accepts today (so "GGX vs Beckmann vs Blinn-Phong" becomes "GGX vs Beckmann" where no
Blinn-Phong is registered, and an entry none of whose states validates is left out).
Captions are two sentences: what the figure shows, and why it matters.
"""
from __future__ import annotations

from dataclasses import dataclass

from pydantic import ValidationError

from ..errors import ParameterError
from . import cards
from ..views import VIEWS, lookup, vary
from ..views.schemas import spec_of


@dataclass(frozen=True)
class Entry:
    id: str
    title: str
    caption: str
    kind: str
    states: tuple[dict, ...]          # candidate query parameters, best first
    source: str


ENTRIES: tuple[Entry, ...] = (
    Entry("ndf-tails", "NDF tails at matched α",
          "At the same α the distributions agree near the normal, but on a log scale their "
          "tails differ by orders of magnitude toward grazing θ_m. GGX's long power-law tail "
          "is the glow around its highlights that Beckmann's Gaussian-like tail lacks.",
          "ndf", ({"alpha": 0.3, "vary": "ndf", "values": "ggx,beckmann,blinn_phong"},
                  {"alpha": 0.3, "vary": "ndf", "values": "ggx,beckmann"}),
          "Walter et al. 2007, fig. 6; Burley 2012, fig. 8"),
    Entry("anisotropic-lobe", "The anisotropic GGX lobe",
          "With α_x = 0.1 along the tangent and α_y = 0.4 across it, the microfacet slopes "
          "spread four times more along y, and so does the reflected lobe. Brushed metal "
          "streaks its highlights the same way.",
          "lobe3d", ({"alpha": 0.1, "alpha_y": 0.4, "theta_i_deg": 45, "fresnel": "none"},),
          "Heitz 2014, sec. 5.4"),
    Entry("g2-energy-loss", "Separable vs height-correlated G2: energy lost",
          "With F = 1 every bit of E(μ) below 1 is energy the single-scattering model loses; "
          "the separable G2 treats masking and shadowing as independent, so it shadows more "
          "and loses more. The height-correlated form is the one Heitz recommends, and both "
          "miss the light that bounces between microfacets.",
          "albedo", ({"alpha": 0.8, "fresnel": "none", "vary": "g2",
                      "values": "separable,height_correlated"},),
          "Heitz 2014, sec. 6 and fig. 10"),
    Entry("g1-walter", "Walter's rational fit against exact Smith (Beckmann)",
          "Walter's rational approximation of Beckmann's Λ needs no error function, and the "
          "G1 it gives is within 0.004 of the exact Smith G1 at every angle. At this scale "
          "the two curves lie on top of each other.",
          "g1", ({"ndf": "beckmann", "alpha": 0.5, "masking": "walter"},
                 {"ndf": "beckmann", "alpha": 0.5, "vary": "masking", "values": "smith,walter"}),
          "Walter et al. 2007, eq. 27"),
    Entry("g1-karis", "Karis's approximation against exact Smith (GGX)",
          "Karis's G1 ≈ 2μ/(μ(2 − α) + α) replaces the square root of the exact Smith G1 "
          "of GGX by a rational function. It is exact at the normal and at grazing incidence "
          "and falls below the exact curve in between, by up to 0.05 at α = 0.6.",
          "g1", ({"ndf": "ggx", "alpha": 0.6, "masking": "karis"},
                 {"ndf": "ggx", "alpha": 0.6, "vary": "masking", "values": "smith,karis"}),
          "Karis 2013, Real Shading in Unreal Engine 4, eq. 4"),
    Entry("fresnel-schlick-dielectric", "Schlick against exact Fresnel for glass",
          "Schlick's polynomial with F₀ = 0.04 equals the exact reflectance of glass "
          "(η = 1.5) at 0° and 90° and stays within 0.04 of it in between. The error (right "
          "axis) changes sign near 75°: too low at mid angles, too high close to grazing.",
          "fresnel", ({"fresnel": "schlick", "f0": 0.04},),
          "Schlick 1994, eq. 15; Born & Wolf sec. 1.5.2"),
    Entry("fresnel-conductor", "Exact Fresnel of gold",
          "A conductor reflects most light at every angle: gold at 549 nm (η = 0.43, "
          "κ = 2.46) has F₀ ≈ 0.79. F stays nearly flat, with a shallow minimum near 50°, "
          "up to about 60° and then rises to 1 at grazing incidence.",
          "fresnel", ({"fresnel": "conductor"},),
          "Johnson & Christy 1972; pbrt-v4 sec. 9.3.6"),
    Entry("albedo-roughness", "Directional albedo of GGX across roughness",
          "With F = 1 a lossless surface would have E(μ) = 1, but single-scattering GGX "
          "returns less and less as α grows: at α = 1 only 31% at normal incidence. The "
          "missing energy is what multiple-scattering compensation (Kulla & Conty) adds back.",
          "albedo", ({"fresnel": "none", "vary": "alpha", "values": "0.1,0.3,0.5,0.7,1"},),
          "Kulla & Conty 2017, slide 18"),
    Entry("lobe-roughness", "The GGX lobe across roughness, log scale",
          "At θ_i = 60° the lobe of a smooth surface is a narrow spike around the mirror "
          "direction; as α grows from 0.05 to 0.5 it widens and its peak drops twentyfold. "
          "The log radial axis shows all three at once.",
          "lobe", ({"theta_i_deg": 60, "log": True, "vary": "alpha", "values": "0.05,0.2,0.5"},),
          "Walter et al. 2007, fig. 4"),
    Entry("lit-sphere", "A rough GGX sphere under one light",
          "The BRDF times the cosine, evaluated on every pixel of a sphere lit from 40° to the "
          "right of the viewer, shown as a display would show it. The highlight sits where "
          "the surface normal is the half vector of light and view (the × marker).",
          "sphere", ({"alpha": 0.25, "theta_i_deg": 40, "kd": 0.2, "display": "render",
                      "exposure": -1},),
          "Burley 2012, the Disney BRDF Explorer's lit sphere"),
    Entry("disney-slice", "The θ_h, θ_d image slice",
          "In half/difference angles the specular peak is a band along small θ_h, and the "
          "Fresnel and masking terms vary along θ_d. Measured BRDFs look the same way in "
          "these coordinates, which is why Burley studied them there.",
          "slice", ({"alpha": 0.2, "f0": 0.04, "log": True},),
          "Burley 2012, sec. 4, fig. 3; Rusinkiewicz 1998"),
    Entry("g2-map", "Masking-shadowing G2 over both angles",
          "G2 is near 1 while both directions are near the normal and falls to 0 as either "
          "grazes. The height-correlated form 1/(1 + Λ(l) + Λ(v)) is never below the "
          "separable product G1(l)·G1(v): a facet hidden from one direction is likely low, "
          "and so likely hidden from the other too.",
          "g2", ({"alpha": 0.5, "phi_deg": 180},),
          "Heitz 2014, sec. 6"),
    # the newer capabilities, one card each (the principled model, environments,
    # measured materials, the tables shaders ship)
    Entry("principled-metallic", "The principled BRDF: dielectric and metal",
          "One base colour at metallic = 0 and at metallic = 1, lit at 60°. As a dielectric "
          "the colour goes into the diffuse lobe under a weak white specular one; as a metal "
          "it tints a much stronger specular lobe and the diffuse lobe is gone.",
          "lobe", ({"model": "principled", "base_color": "0.9,0.6,0.2", "roughness": 0.3,
                    "theta_i_deg": 60, "log": True, "vary": "metallic", "values": "0,1"},),
          "Burley 2012, sec. 5.1; docs/principled.md"),
    Entry("environment-sphere", "A gold-coloured metal in a studio",
          "The principled model on a sphere in colour, lit by a procedural studio environment "
          "and rendered with importance sampling of the light and the BRDF. The caption of "
          "the figure states the noise that is left.",
          "sphere_env", ({"model": "principled", "base_color": "0.9,0.6,0.2", "metallic": 1,
                          "roughness": 0.3, "environment": "studio"},),
          "Veach 1997, ch. 9 (multiple importance sampling); Burley 2012"),
    Entry("material-copper", "Measured copper's Fresnel",
          "The reflectance of copper from its measured complex index of refraction per "
          "linear-sRGB channel, drawn as their luminance. Like every conductor's it stays "
          "high at every angle and rises to 1 at grazing incidence.",
          "fresnel", ({"material": "copper"},),
          "physicallybased.info (CC0); Born & Wolf sec. 13.2"),
    Entry("table-albedo", "A tabulated albedo against the quadrature",
          "The E(μ, α) table that energy compensation and shaders look up, drawn over the "
          "adaptive quadrature it was built from. The two curves agree within the bound the "
          "table reports, which /api/v1/lut states for the tables a shader ships.",
          "albedo", ({"alpha": 0.5, "fresnel": "none", "vary": "method",
                      "values": "quadrature,table"},),
          "Kulla & Conty 2017; Karis 2013 (split sum); docs/tables.md"),
    # the capabilities beyond the views: data, fits, code, tables, conventions (cards.py)
    Entry("data-overlay", "Data on the model: GGX samples against Beckmann",
          "Synthetic samples the server ships, written from a metal-like GGX surface (α = 0.3, "
          "F₀ = 0.9) by its own model.csv export, drawn as points over a Beckmann lobe of the "
          "same α and F₀ at θ_i = 40°. Loading measured or exported data this way shows where "
          "a model misses: here GGX's long tails lie far above Beckmann's away from the peak.",
          "dataset", ({"data": "ggx-samples", "view": "lobe", "ndf": "beckmann", "alpha": 0.3,
                       "f0": 0.9, "kd": 0, "theta_i_deg": 40, "log": True},),
          "docs/datasets.md; Walter et al. 2007, fig. 6"),
    Entry("fit-beckmann", "A least-squares fit, and what it cannot fix",
          "Beckmann's α, F₀ and k_d fitted to the same GGX samples (log measure), drawn over "
          "them with the fitted values and their standard errors. To reach GGX's tails the fit "
          "invents a diffuse term the surface does not have and still misses by more than 5 %, "
          "so the answer warns that the model family, not its parameters, is wrong.",
          "fit", ({"data": "ggx-samples", "view": "lobe", "free": "alpha,f0,kd", "measure": "log",
                   "ndf": "beckmann", "alpha": 0.3, "f0": 0.5, "kd": 0, "theta_i_deg": 40,
                   "log": True},),
          "docs/datasets.md (fits); Ngan et al. 2005"),
    Entry("shader-code", "The model as shader code",
          "The GGX model at α = 0.3 as self-contained GLSL, generated from the same formulas the "
          "server's kernels evaluate, with HLSL and numpy versions beside it. What the explorer "
          "draws is what a renderer runs, term for term.",
          "code", ({"lang": "glsl", "ndf": "ggx", "alpha": 0.3, "f0": 0.04},),
          "docs/shaders.md; Walter et al. 2007, eq. 20"),
    Entry("lut-split-sum", "The split-sum lookup table and its error",
          "Karis's split-sum table of GGX, scale (red) and bias (green) of F₀ over roughness and "
          "μ = cos θ_v, as the 32 × 32 16-bit PNG a shader samples. Each table states its "
          "error against the converged integral: of its values, after quantisation and "
          "after bilinear lookup.",
          "lut", ({"kind": "split_sum", "size": 32},),
          "Karis 2013, Real Shading in Unreal Engine 4; docs/luts.md"),
    Entry("roughness-conventions", "One roughness, many α",
          "The α that Disney, glTF, Filament, UE4, pbrt, Blender and OpenPBR compute from the "
          "same roughness 0.5, and the lobes they give. Mixing two conventions, say D at α = r² "
          "and G at α = r, changes the albedo, which the check link quantifies.",
          "conventions", ({"roughness": 0.5},),
          "Burley 2012, sec. 5.4; docs/conventions.md"),
)


def _validate(kind: str, state: dict) -> bool:
    """Does the API accept this state for this view (the same checks a request gets)?"""
    try:
        view = lookup(kind)
        q = vary.figure_query(view).model_validate(state)
        expanded = vary.expand(view, q)
        for qk in (expanded[0] if expanded else [q]):
            spec_of(qk)
    except (ValidationError, ParameterError):
        return False
    return True


def explorer_link(kind: str, state: dict) -> str:
    """The explorer with this state and the view's panel shown."""
    return "/?" + cards.query({**state, "show": kind})


def figure_path(kind: str, state: dict, ext: str = "") -> str:
    return f"/api/v1/figures/{kind}{ext}?" + cards.query(state)


def _valid(e: Entry, state: dict) -> bool:
    """A view's state as the view checks it; a data set's or fit's view part likewise."""
    if e.kind in VIEWS:
        return _validate(e.kind, state)
    if "view" in state:
        drop = ("data", "view", "free", "measure")
        return _validate(state["view"], {k: v for k, v in state.items() if k not in drop})
    return True


def available() -> list[dict]:
    """The entries the API supports now, each with its first valid state and links."""
    out = []
    for e in ENTRIES:
        if e.kind not in VIEWS and e.kind not in cards.BUILDERS:
            continue
        state = next((s for s in e.states if _valid(e, s)), None)
        if state is None:
            continue
        if e.kind in cards.BUILDERS:
            out.append({"id": e.id, "title": e.title, "caption": e.caption, "kind": e.kind,
                        "state": state, "source": e.source, **cards.BUILDERS[e.kind](state)})
            continue
        out.append({"id": e.id, "title": e.title, "caption": e.caption, "kind": e.kind,
                    "state": state, "source": e.source,
                    "explorer": explorer_link(e.kind, state),
                    "figure": figure_path(e.kind, state, ".json"),
                    "svg": figure_path(e.kind, state, ".svg"),
                    "png": figure_path(e.kind, state, ".png"),
                    "csv": figure_path(e.kind, state, ".csv"),
                    "embed": f"/embed/{e.kind}?" + cards.query(state)})
    return out
