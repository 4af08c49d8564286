"""BRDF Lobe Explorer: microfacet BRDFs as numbers and Plotly figures."""

__version__ = "0.1.0"
