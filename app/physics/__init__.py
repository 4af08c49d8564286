"""Pure numpy/scipy physics. Imports neither FastAPI nor Plotly.

Conventions are those of ``shared/MATH.md``: n = +z, directions point away from the
surface, ``alpha`` is the microfacet roughness of the formulas, angles are radians or
cosines inside this package.
"""
