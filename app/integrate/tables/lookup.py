"""Which E(μ, α) table answers a lobe: the store's whole tables (store.py) for
``method=table`` and the Schlick basis, looked up by :func:`table_key`; for Kulla-Conty's
compensation the whole table if ready and within alpha_slice.GOAL, else the slice at the
lobe's α (alpha_slice.py).

This module sits above the store (it imports store and table; neither imports it).
"""
from __future__ import annotations

import numpy as np

from ...errors import Busy
from ...physics.brdf import BRDF
from . import alpha_slice, store
from .alpha_slice import ESlice
from .table import ETable, lobe_at, compiled, table_key


def table_for_key(key: tuple) -> ETable:
    """The table for ``key`` from the store (store.py: memory, disk, built in the
    background or here; one the request's time budget cut short is answered, not kept)."""
    return store.table(key)


table_for_key.cache_info = store.cache_info
table_for_key.cache_clear = store.cache_clear


def table_for(lobe: BRDF, basis_p: float | None = None, ready_only: bool = False) -> ETable:
    """The (cached) default-size table for a single isotropic lobe (``BRDF.lobes()``);
    ``ready_only``: one already built, else Busy (nothing is built or queued)."""
    if not lobe.ndf.isotropic:
        raise ValueError("E(μ, α) tables are for isotropic roughness only (alpha_y = alpha)")
    if not ready_only:
        return table_for_key(table_key(lobe, basis_p))
    key = table_key(lobe, basis_p)
    if (t := store.table_if_ready(key)) is None:
        name = store.table_name(key)
        raise Busy(f"the {name} is not built yet", what=name)
    return t


def tabulated_albedo(brdf: BRDF, mu, ready_only: bool = False) -> tuple[np.ndarray, float, list[ETable]]:
    """E(μ) of a BRDF from tables: Σ_lobes w (F₀ E₁ + (F₉₀ − F₀) E_S) + E_d (the diffuse
    term's albedo, kd for Lambert), for F = 1 or generalised Schlick (E is linear in f and in F). Returns (E, error bound, tables).
    Raises ValueError for other Fresnel forms and anisotropic roughness; ``ready_only``: table_for."""
    parts = brdf.fresnel.schlick_basis()
    if parts is None:
        raise ValueError(f"method=table needs a Fresnel on the Schlick basis (none or schlick: E "
                         f"is tabulated per basis function); got fresnel={brdf.fresnel.name}")
    mu = np.atleast_1d(np.asarray(mu, dtype=float))
    E, error = brdf.diffuse_albedo(mu)
    tables = []
    for w, lobe in brdf.lobes():
        for c, basis in parts:
            if c == 0:
                continue
            table = table_for(lobe, basis, ready_only)
            E = E + w * c * table.E(mu, lobe.ndf.alpha_x)
            error += abs(w * c) * table.error
            tables.append(table)
    return E, error, tables


def compensation_table(lobe: BRDF) -> ETable | ESlice:
    """E(μ) at F = 1 for Kulla-Conty's lobe at ``lobe``'s α: the whole table when the
    store has it ready and its bound meets alpha_slice.GOAL (GGX and Beckmann: ~1e-5),
    else the slice at that α (alpha_slice.py: built in the request, a few tenths of a
    second to ~2 s, refined to GOAL for every shape). Either way its ``error`` bounds
    |Ê − E| at that α."""
    if not lobe.ndf.isotropic:
        raise ValueError("E(μ, α) tables are for isotropic roughness only (alpha_y = alpha)")
    key = table_key(lobe)
    whole = store.table_if_ready(key)
    if whole is not None and whole.error <= alpha_slice.GOAL:
        return whole
    compiled(lobe_at(key, lobe.ndf.alpha_x))      # waits a moment for the compiled loops
    return alpha_slice.slice_for_key(key, float(lobe.ndf.alpha_x))
