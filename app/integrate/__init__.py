"""Integrals of the physics: albedo by deterministic quadrature (more to come).

Imports the physics, never FastAPI or Plotly.
"""
