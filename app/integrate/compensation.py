"""Kulla-Conty energy compensation: the multiple-scattering lobe f_ms.

For one specular lobe with albedo E(μ) at F = 1 and Ē = 2 ∫₀¹ E(μ) μ dμ,
f_ms(μ_l, μ_v) = (1 − E(μ_l))(1 − E(μ_v)) / (π (1 − Ē)) has albedo 1 − E(μ_v), so with
F = 1 every μ reflects everything; with a Fresnel term it is scaled by
F_ms = F̄² Ē / (1 − F̄ (1 − Ē)). Derivation: docs/kulla_conty.md §1, §2.

E and Ē come from the E(μ, α) table (tables/); Ē is the average of the interpolant
itself, so the albedo of the f_ms actually used is exactly F_ms (1 − Ê(μ_v)), and the
furnace holds to within the table's error |Ê − E| (§3). A two-lobe model gets one f_ms
per lobe, weighted like the lobes. Anisotropic roughness is refused (app/model.py).

Reference: Kulla & Conty 2017, "Revisiting Physically Based Shading at Imageworks",
SIGGRAPH course notes, pp. 14-17.
"""
from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from ..physics.brdf import BRDF, CompensatedBRDF
from ..physics.numeric import where_valid
from .tables import ETable, compensation_table

#: 1 − Ē below which a lobe loses no energy worth compensating: Ē is then 1 to within
#: a few ulps of double rounding and (1 − E)(1 − E)/(1 − Ē) is rounding noise over
#: rounding noise. Such a lobe gets f_ms = 0 (its furnace error is ≤ this).
MIN_ENERGY_LOSS = 1e-12


@dataclass(frozen=True)
class MultiScatter:
    name: str
    label: str
    description: str
    reference: str = ""


MULTISCATTERS = {m.name: m for m in [
    MultiScatter("none", "None (single scattering)",
                 "f = the single-scattering microfacet BRDF: energy is lost at high roughness."),
    MultiScatter("kulla_conty", "Kulla-Conty compensation",
                 "Adds f_ms = F_ms (1 − E(μ_l))(1 − E(μ_v)) / (π (1 − Ē)) from an E(μ, α) "
                 "table: with F = 1 the albedo is 1 at every angle. Isotropic roughness only.",
                 "Kulla & Conty 2017"),
]}


def fresnel_factor(F_avg: float, E_avg: float) -> float:
    """F_ms = F̄² Ē / (1 − F̄ (1 − Ē)) (docs/kulla_conty.md §2); 1 when F̄ = 1. The
    denominator as (1 − F̄) + F̄ Ē, two terms ≥ 0: written as 1 − F̄ (1 − Ē) it cancels when
    Ē is tiny (Student-t γ → 1.5: Ē = 2e-15 gave F_ms = 0.92 at F̄ = 1)."""
    return F_avg * F_avg * E_avg / ((1.0 - F_avg) + F_avg * E_avg)


@dataclass(frozen=True, eq=False)   # hashed by identity (a BRDF field)
class LobeTerm:
    weight: float
    alpha: float
    table: ETable
    E_avg: float            # Ē of this lobe (F = 1), from the table's interpolant
    scale: float            # weight × F_ms / (π (1 − Ē)); 0 if the lobe loses nothing

    def one_minus_E(self, mu) -> np.ndarray:
        return 1.0 - self.table.E(mu, self.alpha)


@dataclass(frozen=True, eq=False)
class KullaConty:
    """f_ms(μ_l, μ_v) = Σ_lobes scale (1 − Ê(μ_l))(1 − Ê(μ_v)): symmetric in μ_l, μ_v,
    so the compensated BRDF stays reciprocal (docs/identities.md §5)."""
    lobes: tuple[LobeTerm, ...]
    F_avg: float
    F_ms: float             # factor of the first lobe (as reported); each lobe has its own

    def __call__(self, mu_l, mu_v) -> np.ndarray:
        out = 0.0
        for term in self.lobes:
            if term.scale:
                out = out + term.scale * term.one_minus_E(mu_l) * term.one_minus_E(mu_v)
        return np.broadcast_to(np.asarray(out, dtype=float), np.broadcast_shapes(
            np.shape(mu_l), np.shape(mu_v))).copy()

    def albedo(self, mu) -> np.ndarray:
        """∫ f_ms(μ_l, μ_v) μ_l dω_l = Σ weight F_ms (1 − Ê(μ_v)) (docs/kulla_conty.md §1), exact for Ê's Ē."""
        mu = np.asarray(mu, dtype=float)
        out = np.zeros(mu.shape)
        for term in self.lobes:
            if term.scale:
                out = out + term.scale * np.pi * (1.0 - term.E_avg) * term.one_minus_E(mu)
        return out

    def albedo_average(self) -> float:
        """2 ∫ E_ms μ dμ = Σ weight F_ms (1 − Ē)."""
        return float(sum(t.scale * np.pi * (1.0 - t.E_avg) ** 2 for t in self.lobes if t.scale))

    @property
    def error(self) -> float:
        """|E + E_ms − 1| bound of the furnace (F = 1): Σ weight × table error."""
        return float(sum(abs(t.weight) * t.table.error for t in self.lobes))

    @property
    def E_avg(self) -> float:
        """Ē (F = 1, single scattering) of the specular lobes, weighted."""
        return float(sum(t.weight * t.E_avg for t in self.lobes))


def kulla_conty(brdf: BRDF) -> KullaConty:
    """The f_ms of a BRDF's specular lobes (its kd is not compensated: it loses nothing)."""
    F_avg = float(brdf.fresnel.F_avg())
    terms, first_factor = [], None
    for weight, lobe in brdf.lobes():
        table = compensation_table(lobe)
        alpha = lobe.ndf.alpha_x
        E_avg = table.E_avg(alpha)
        loss = 1.0 - E_avg
        factor = fresnel_factor(F_avg, E_avg)
        first_factor = factor if first_factor is None else first_factor
        scale = float(where_valid(loss > MIN_ENERGY_LOSS, [loss],
                                  lambda x: weight * factor / (np.pi * x), 0.0))
        terms.append(LobeTerm(weight, alpha, table, E_avg, scale))
    return KullaConty(tuple(terms), F_avg, float(first_factor))


def compensated(brdf: BRDF) -> CompensatedBRDF:
    """The BRDF with its Kulla-Conty lobe."""
    base = brdf.single() if isinstance(brdf, CompensatedBRDF) else brdf
    values = {f.name: getattr(base, f.name) for f in fields(BRDF)}
    return CompensatedBRDF(**values, multiscatter=kulla_conty(base))
