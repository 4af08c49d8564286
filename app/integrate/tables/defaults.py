"""The E(μ, α) tables a server queues at start-up for its background builder
(store.start)."""
from __future__ import annotations

from ...physics.brdf import BRDF
from ...physics.fresnel import FRESNELS
from ...physics.ndf import NDFS
from . import table as tables


def default_keys(brdfs) -> list[tuple]:
    """The tables of ``brdfs`` (the server passes its default models: GGX and Beckmann):
    each lobe at F = 1 (Kulla-Conty, method=table with fresnel=none), then the Schlick
    bases (a first Kulla-Conty request for Beckmann then waits for two builds, not four),
    then every other NDF's F = 1 table with its default shape and the first model's
    options, its exact Smith masking (Blinn-Phong's Walter Λ is an approximation: its
    compensation is the Smith integral's), so that its first Kulla-Conty request waits
    for one build at most (issue 13)."""
    keys = []
    for brdf in brdfs:
        for _, lobe in brdf.lobes():
            keys.append(tables.table_key(lobe, None))
            # its Fresnel's Schlick basis, if it has one (F = 1 is the None term)
            keys += [tables.table_key(lobe, p) for _, p in brdf.fresnel.schlick_basis() or ()]
    keys = sorted(dict.fromkeys(keys), key=lambda k: k[-1] is not None)
    lobe = next((lobe for b in brdfs for _, lobe in b.lobes()), None)
    for cls in NDFS.values() if lobe is not None else ():
        ndf = cls(0.5)     # any α: the key holds none
        keys.append(tables.table_key(BRDF(ndf, lobe.masking.exact(ndf), lobe.g2, FRESNELS["none"](),
                                          lambda_phi=lobe.lambda_phi)))
    return list(dict.fromkeys(keys))
