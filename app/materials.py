"""Measured materials (physicallybased.info, CC0): RGB complex indices n + ik of metals, real
indices of dielectrics, and per channel (linear sRGB) the Fresnel forms used in their place:

* exact       Born & Wolf (the registry's ``conductor``), F₀ = ((n − 1)² + k²)/((n + 1)² + k²)
* schlick     F₀ + (1 − F₀)(1 − μ)^5 from that F₀ (Schlick 1994)
* f82_tint    Schlick − a μ(1 − μ)^6 with a such that F(μ̄ = 1/7) = t · Schlick(μ̄), t the
              measured F82 tint (Kutz et al. 2021, "Novel aspects of the Adobe Standard
              Material"; Hoffman 2019)
* gulbrandsen n, k rebuilt from r = F₀ and the measured edge tint g (Gulbrandsen 2014,
              "Artist Friendly Metallic Fresnel", JCGT 3(4)), then the exact form

A channel with F₀ = 1 (gold's and silver's red: n = 0) reflects everything at every angle;
every form gives F = 1 there (Gulbrandsen's n, k diverge: the limit is used).
(derivation: docs/fresnel.md §2)
"""
from __future__ import annotations

import difflib
import json
from dataclasses import replace
from functools import lru_cache
from pathlib import Path

import numpy as np

from .errors import ParameterError
from .physics.fresnel import FRESNELS, Fresnel
from .physics.fresnel.base import _cos

DATA = Path(__file__).resolve().parent / "data" / "materials.json"
#: Rec. 709 luminance weights of linear sRGB: the scalar F and f of a coloured model
LUMINANCE = np.array([0.2126, 0.7152, 0.0722])
CHANNELS = ("r", "g", "b")
#: F82's reference angle: μ̄ = cos θ = 1/7, θ ≈ 81.8° (Kutz et al. 2021)
MU_BAR = 1.0 / 7.0
#: 1 − F₀ below which a channel is a perfect mirror (F = 1 at every angle, to rounding)
MIRROR_GAP = 1e-12


@lru_cache(maxsize=1)
def _data() -> dict:
    return json.loads(DATA.read_text(encoding="utf-8"))


def materials() -> dict[str, dict]:
    """slug → material record (name, category, kind, n/k or ior, tints, references)."""
    return {m["slug"]: m for m in _data()["materials"]}


def unknown_material(slug) -> str:
    """The message for a slug that names no material: the nearest slugs first ("did you
    mean gold?" for Gold), then where the full list is."""
    table = materials()
    near = difflib.get_close_matches(str(slug).strip().lower().replace(" ", "_").replace("-", "_"),
                                     list(table), n=3, cutoff=0.6)
    hint = f"did you mean {' or '.join(near)}? " if near else ""
    return (f"unknown material {slug!r}; {hint}(the {len(table)} slugs: GET /api/v1/materials; "
            f"lower case, e.g. {next(iter(table))})")


def material(slug: str) -> dict:
    table = materials()
    if slug not in table:
        raise ParameterError("material", unknown_material(slug))
    return table[slug]


def f0(record: dict) -> np.ndarray:
    """Per-channel reflectance at normal incidence."""
    if record["kind"] == "conductor":
        n, k = np.asarray(record["n"]), np.asarray(record["k"])
        return ((n - 1) ** 2 + k ** 2) / ((n + 1) ** 2 + k ** 2)
    eta = record["ior"]
    return np.full(3, ((eta - 1) / (eta + 1)) ** 2)


def channel_fresnels(record: dict) -> list[Fresnel]:
    """The exact Fresnel of each channel (the registry's conductor or dielectric)."""
    if record["kind"] == "conductor":
        return [FRESNELS["conductor"](ior=n, k=k) for n, k in zip(record["n"], record["k"])]
    return [FRESNELS["dielectric"](ior=record["ior"])] * 3


class MaterialFresnel(Fresnel):
    """The luminance of a material's per-channel exact Fresnel; ``channels`` holds the
    three. Not in the registry: a model gets it through ``material=<slug>``."""
    name = "material"
    label = "Material (measured RGB index)"
    description = "Exact Fresnel per RGB channel from a measured complex or real index."

    def __init__(self, slug: str):
        super().__init__()
        self.slug = slug
        self.record = material(slug)
        self.channels = channel_fresnels(self.record)

    def F(self, cos_theta_d) -> np.ndarray:
        return sum(w * ch.F(cos_theta_d) for w, ch in zip(LUMINANCE, self.channels))

    def F_rgb(self, cos_theta_d) -> np.ndarray:
        return np.stack([ch.F(cos_theta_d) for ch in self.channels], axis=-1)


def evaluate_rgb(brdf, l, v, want=("f",)) -> dict:
    """``brdf.evaluate`` once per channel (each with its scalar exact Fresnel, so that a
    Kulla-Conty F_ms is per channel too): F_rgb, f_rgb (…, 3) and their luminance F, f."""
    fresnel = brdf.fresnel
    if not isinstance(fresnel, MaterialFresnel):
        return brdf.evaluate(l, v, want)
    base = brdf.single() if hasattr(brdf, "single") else brdf
    per = []
    for ch in fresnel.channels:
        model = replace(base, fresnel=ch)
        if base is not brdf:
            from .integrate.compensation import compensated
            model = compensated(model)
        per.append(model.evaluate(l, v, want))
    out = dict(per[0])
    for q in ("f", "F"):
        if q in want:
            rgb = np.stack([p[q] for p in per], axis=-1)
            out[f"{q}_rgb"] = rgb
            out[q] = rgb @ LUMINANCE
    return out


# ----------------------------------------------------------------- the artists' forms

class F82Tint(Fresnel):
    """Schlick − a μ(1 − μ)^6, a = Schlick(μ̄)(1 − t)/(μ̄ (1 − μ̄)^6) (Kutz et al. 2021)."""
    name = "f82_tint"
    label = "F82-tint"
    description = "Schlick with the measured F82 tint (Kutz et al. 2021)."

    def __init__(self, f0: float, tint: float):
        super().__init__()
        self.f0, self.tint = float(f0), float(tint)
        schlick_bar = self.f0 + (1 - self.f0) * (1 - MU_BAR) ** 5
        self.a = schlick_bar * (1 - self.tint) / (MU_BAR * (1 - MU_BAR) ** 6)

    def F(self, cos_theta_d):
        mu = _cos(cos_theta_d)
        return np.clip(self.f0 + (1 - self.f0) * (1 - mu) ** 5 - self.a * mu * (1 - mu) ** 6, 0.0, 1.0)


def gulbrandsen_nk(r: float, g: float) -> tuple[float, float] | None:
    """n, k from reflectivity r and edge tint g (Gulbrandsen 2014, eq. 8-9); None for r ≥ 1
    (a perfect mirror: the limit F = 1)."""
    r = min(max(r, 0.0), 1.0)
    if 1.0 - r < MIRROR_GAP:
        return None
    sr = np.sqrt(r)
    n = g * (1 - r) / (1 + r) + (1 - g) * (1 + sr) / (1 - sr)
    k2 = (r * (n + 1) ** 2 - (n - 1) ** 2) / (1 - r)
    return float(n), float(np.sqrt(max(k2, 0.0)))


def approximations(record: dict) -> dict[str, list[Fresnel]]:
    """Per channel: exact, schlick, f82_tint, gulbrandsen (conductors; a dielectric has
    exact and schlick only)."""
    exact = channel_fresnels(record)
    F0 = f0(record)
    out = {"exact": exact,
           "schlick": [FRESNELS["schlick"](f0=float(x), f90=1.0, fresnel_p=5.0) for x in F0]}
    if record["kind"] == "conductor":
        tint = record.get("f82_tint", [1.0] * 3)
        out["f82_tint"] = [F82Tint(x, t) for x, t in zip(F0, tint)]
        edge = record.get("edge_tint")
        if edge is not None:
            gul = []
            for x, g in zip(F0, edge):
                nk = gulbrandsen_nk(float(x), float(g))
                gul.append(FRESNELS["none"]() if nk is None else FRESNELS["conductor"](ior=nk[0], k=nk[1]))
            out["gulbrandsen"] = gul
    return out


def comparison(slug: str, lobe, n: int, albedo_average) -> dict:
    """F(θ) per channel of every form, its error against the exact one, and each form's
    E_avg per channel for ``lobe`` (an isotropic single-scattering BRDF) with its error."""
    record = material(slug)
    theta = np.linspace(0.0, 90.0, n)
    mu = np.cos(np.deg2rad(theta))
    mu[-1] = 0.0
    forms = approximations(record)
    curves, errors, e_avg, e_avg_err = {}, {}, {}, {}
    for name, chans in forms.items():
        curves[name] = np.stack([c.F(mu) for c in chans], axis=-1)
        e, err = zip(*(albedo_average(replace(lobe, fresnel=c))[:2] for c in chans))
        e_avg[name], e_avg_err[name] = np.array(e), np.array(err)
    for name in forms:
        if name != "exact":
            errors[name] = {"F": curves[name] - curves["exact"],
                            "F_max": np.max(np.abs(curves[name] - curves["exact"]), axis=0),
                            "E_avg": e_avg[name] - e_avg["exact"],
                            "E_avg_bound": e_avg_err[name] + e_avg_err["exact"]}
    return {"material": summary(record), "theta_deg": theta, "channels": list(CHANNELS), "F": curves,
            "E_avg": e_avg, "E_avg_error": e_avg_err, "errors": errors}


def summary(record: dict) -> dict:
    out = {k: record[k] for k in ("name", "slug", "category", "kind") if k in record}
    out.update({k: record[k] for k in ("n", "k", "ior", "color", "f82_tint", "edge_tint") if k in record})
    out["f0"] = f0(record).tolist()
    return out


def listing() -> dict:
    data = _data()
    return {"source": data["source"], "license": data["license"], "note": data["note"],
            "materials": [summary(m) for m in data["materials"]]}
