"""The single-bounce microfacet BRDF plus a Lambertian term.

f(l, v) = f_d + D(h) F(v·h) G2(l, v) / (4 |n·l| |n·v|), h = (l+v)/‖l+v‖, F of the
angle between v and h, no cosine in f (Walter et al. 2007, eq. 20). The diffuse term f_d
is kd/π (Lambert) unless ``diffuse`` names another model of app/physics/diffuse/, which
then takes ρ = kd.

Reflection only: f = 0 unless both l and v are in the closed upper hemisphere.
Where l = −v the specular term is 0. Where both graze, the height-correlated specular
term diverges and is +inf (a limit, not an error); every other value is finite.

References
----------
Cook & Torrance 1982; Walter et al. 2007, eq. 20; Heitz 2014, eq. 4.
"""
from __future__ import annotations

from dataclasses import dataclass, fields, replace
from typing import Callable

import numpy as np

from .diffuse import Diffuse
from .fresnel import Fresnel
from .g2 import G2Form, azimuth_difference
from .masking import G1, Masking
from .ndf import NDF
from .numeric import on_mask, where_valid
from .vectors import dot, half_vector

QUANTITIES = ("f", "f_diffuse", "D", "G1_i", "G1_o", "G2", "F")


@dataclass(frozen=True)
class BRDF:
    ndf: NDF
    masking: Masking
    g2: G2Form
    fresnel: Fresnel
    kd: float = 0.0
    lambda_phi: Callable | None = None  # λ(φ) for the direction-correlated G2 forms
    lobe2: NDF | None = None            # second specular lobe (same NDF, its own α)
    lobe_mix: float = 0.0               # its weight w
    diffuse: Diffuse | None = None      # None: Lambert kd/π

    def evaluate(self, l, v, want=("f",)) -> dict[str, np.ndarray]:
        """The requested quantities (a subset of :data:`QUANTITIES`) at direction pairs.

        ``l`` is the light direction (index i in the API), ``v`` the view (o). D, F and
        the G terms are taken at the half vector h.
        """
        l = np.asarray(l, dtype=float)
        v = np.asarray(v, dtype=float)
        if self.lobe2 is not None and self.lobe_mix > 0:
            return self._evaluate_two_lobes(l, v, want)
        h, h_exists = half_vector(l, v)
        mu_l, mu_v = l[..., 2], v[..., 2]
        upper = (mu_l >= 0) & (mu_v >= 0)
        out: dict[str, np.ndarray] = {}

        need_D = "f" in want or "D" in want
        need_F = "f" in want or "F" in want
        need_G2 = "f" in want or "G2" in want
        if need_D:
            D = on_mask(h_exists, self.ndf.D, h)
        if need_F:
            F = self.fresnel.F(dot(v, h))
        if need_G2 or "G1_i" in want or "G1_o" in want:
            ml_l = self.masking.mu_Lambda(self.ndf, l)
            ml_v = self.masking.mu_Lambda(self.ndf, v)
        if need_G2:
            phi = azimuth_difference(l, v) if self.g2.needs_phi else None
            G2, V = self.g2.G2_and_V(np.maximum(mu_l, 0.0), np.maximum(mu_v, 0.0), ml_l, ml_v,
                                     phi=phi, ndf=self.ndf, lambda_phi=self.lambda_phi)
            G2 = np.where(upper & h_exists, G2, 0.0)
        if "f" in want or "f_diffuse" in want:
            f_diffuse = self._f_diffuse(l, v, upper)
        if "f_diffuse" in want:
            out["f_diffuse"] = f_diffuse
        if "f" in want:
            specular = where_valid(upper & h_exists & (D * F > 0), [D, F, V],
                                   lambda d, fr, vis: d * fr * vis, 0.0)
            out["f"] = specular + f_diffuse
        if "D" in want:
            out["D"] = D
        if "F" in want:
            out["F"] = F
        if "G2" in want:
            out["G2"] = G2
        # G1(ω, h) = χ⁺(ω·h) G1(ω): ω·h > 0 wherever h exists and ω is upper.
        if "G1_i" in want:
            out["G1_i"] = np.where(h_exists, G1(mu_l, ml_l), 0.0)
        if "G1_o" in want:
            out["G1_o"] = np.where(h_exists, G1(mu_v, ml_v), 0.0)
        return out

    def _f_diffuse(self, l, v, upper) -> np.ndarray:
        """The diffuse term kd/π or diffuse.f(kd, μ_l, μ_v, l·v), 0 unless both are upper."""
        if self.diffuse is None:
            return np.where(upper, self.kd / np.pi, 0.0)
        return where_valid(upper, [l[..., 2], v[..., 2], dot(l, v)],
                           lambda a, b, c: self.diffuse.f(self.kd, a, b, c), 0.0)

    def diffuse_albedo(self, mu) -> tuple[np.ndarray, float]:
        """(E_d(μ), its error): the diffuse term's directional albedo, kd for Lambert."""
        mu = np.atleast_1d(np.asarray(mu, dtype=float))
        if self.diffuse is None:
            return np.full(mu.shape, float(self.kd)), 0.0
        return self.diffuse.albedo(self.kd, mu)

    def diffuse_albedo_avg(self) -> tuple[float, float]:
        """(E_d,avg, its error), kd for Lambert."""
        if self.diffuse is None:
            return float(self.kd), 0.0
        return self.diffuse.albedo_avg(self.kd)

    def _evaluate_two_lobes(self, l, v, want) -> dict[str, np.ndarray]:
        """f = (1 − w) f(α) + w f(α₂), both lobes with the same NDF, masking, G2 and F
        (Kulla & Conty 2017, two-lobe blend); kd/π is in both and so in the blend once.
        D is the blend of the two NDFs (itself a normalised NDF); the G terms and F are
        the first lobe's."""
        first = replace(self, lobe2=None, lobe_mix=0.0).evaluate(l, v, want)
        blended = [q for q in ("f", "D") if q in want]
        if not blended:
            return first
        second = replace(self, ndf=self.lobe2, lobe2=None, lobe_mix=0.0).evaluate(l, v, tuple(blended))
        for q in blended:
            first[q] = blend_lobes(self.lobe_mix, first[q], second[q])
        return first

    def lobes(self):
        """[(weight, single-lobe BRDF without the diffuse term)]: what a linear functional
        (albedo) sums; the diffuse term's albedo is :meth:`diffuse_albedo`."""
        single = replace(self, kd=0.0, lobe2=None, lobe_mix=0.0, diffuse=None)
        if self.lobe2 is None or self.lobe_mix == 0:
            return [(1.0, single)]
        return [(1.0 - self.lobe_mix, single), (self.lobe_mix, replace(single, ndf=self.lobe2))]

    def f(self, l, v) -> np.ndarray:
        return self.evaluate(l, v, ("f",))["f"]


def blend_lobes(w: float, first, second) -> np.ndarray:
    """(1 − w) a + w b, +inf where either lobe is (both graze: a limit, not a number)."""
    return where_valid(np.isfinite(first) & np.isfinite(second), [first, second],
                       lambda a, b: (1.0 - w) * a + w * b, np.inf)


@dataclass(frozen=True)
class CompensatedBRDF(BRDF):
    """f = f_single + f_ms: the single-scattering BRDF plus a multiple-scattering lobe
    ``multiscatter(μ_l, μ_v)`` (Kulla & Conty 2017, Fresnel factor included), built in
    app/integrate/compensation.py: physics does not import integrate. A subclass, so
    that :meth:`single` gives the plain single-scattering BRDF back."""
    multiscatter: Callable | None = None   # (mu_l, mu_v) -> f_ms, reciprocal

    def single(self) -> BRDF:
        """The single-scattering BRDF (plain :class:`BRDF`, same terms)."""
        return BRDF(**{f.name: getattr(self, f.name) for f in fields(BRDF)})

    def evaluate(self, l, v, want=("f",)) -> dict[str, np.ndarray]:
        out = self.single().evaluate(l, v, want)
        if "f" in want:
            out["f"] = out["f"] + self.multiscatter_f(l, v)
        return out

    def multiscatter_f(self, l, v) -> np.ndarray:
        """f_ms(μ_l, μ_v) where both directions are upper, else 0."""
        l = np.asarray(l, dtype=float)
        v = np.asarray(v, dtype=float)
        mu_l, mu_v = np.broadcast_arrays(l[..., 2], v[..., 2])
        if self.multiscatter is None:
            return np.zeros(mu_l.shape)
        upper = (mu_l >= 0) & (mu_v >= 0)
        return where_valid(upper, [mu_l, mu_v], self.multiscatter, 0.0)
