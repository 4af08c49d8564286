"""The principled BRDF (Burley 2012): lobes built from the registry's parts, per RGB
channel, each lobe and its albedo visible on its own (docs/principled.md)."""
from .colour import channel
from .material import Principled, PrincipledBRDF, principled_brdf
from .params import LOBES, OPTIONS, PARAMS

__all__ = ["LOBES", "OPTIONS", "PARAMS", "Principled", "PrincipledBRDF", "channel", "principled_brdf"]
