"""Functions the shading languages lack, written in the neutral syntax (dsl.py) and
emitted into a program when one of its formulas calls them."""
from __future__ import annotations

from .dsl import Fn

#: Numerical Recipes (Press et al. 2007, sec. 6.2.2, "erfc"): erfc(z) = t exp(−z² + P(t)),
#: t = 1/(1 + z/2), relative error < 1.2e-7 for z ≥ 0; P without −z² is erfcx.
ERFCX_MAX_RELATIVE_ERROR = 1.2e-7
ERFCX = Fn("erfcx", "float", [("float", "x")], [("float", "t", "1.0 / (1.0 + 0.5 * x)")],
           "t * exp(-1.26551223 + t * (1.00002368 + t * (0.37409196 + t * (0.09678418 + t * (-0.18628806"
           " + t * (0.27886807 + t * (-1.13520398 + t * (1.48851587 + t * (-0.82215223 + t * 0.17087277)))))))))",
           "erfcx(x) = exp(x²) erfc(x) for x ≥ 0 (Numerical Recipes 3rd ed., sec. 6.2.2; relative error < 1.2e-7).")

LIBRARY = {"erfcx": ERFCX}
