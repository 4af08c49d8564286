"""Gauss-Legendre rules live in app.physics.gauss (the Smith integral needs them too)."""
from ..physics.gauss import gauss_legendre_01  # noqa: F401
