"""The lit sphere: one renderer (sphere.py) for a point light, procedural environments
(maps.py) and both together, its multiple-importance estimator (render.py), f at its
samples (evaluate.py); HDR files (hdr.py)."""
