"""Pure numpy/scipy physics. Imports neither FastAPI nor Plotly, and knows no accelerator.

Conventions: n = +z, directions point away from the surface, ``alpha`` is the microfacet
roughness of the formulas, angles are radians or cosines inside this package. Each
model (NDF, masking, G2 form, Fresnel) is an entry of its registry (``registry.py``)
and writes its formulas twice: vectorised for numpy, and for one point
(``scalar.py``), which app/kernels compiles.
"""
