"""One neutral spelling of straight-line shading code, written out as GLSL, HLSL or numpy.

Every generated function is a list of typed single assignments and a return expression.
Expressions use C syntax plus a few macros, so that one source gives the three languages
and the Python that the tests run against the API is the same algorithm as the shaders:

    sel(c, a, b)   c ? a : b (scalar)      sel3(c, a, b)   the same for vec3 values
    and_, or_, not_                        X(v), Y(v), Z(v)  components
    vec3(a, b, c), splat(a)                dot, cross, normalize, length
    sqrt exp log abs floor pow min max clamp atan2          toint(x), tofloat(i)
    INF()          +∞ (a limit returned as its value)

There are no branches or loops: tables are indexed directly (their axes are uniform in
a known variable). numpy evaluates both sides of a ``sel``; the generated Python silences
floating-point warnings for that, and the value not selected is discarded."""
from __future__ import annotations

from dataclasses import dataclass, field

from ..physics.formula import MACROS, literal, translate  # noqa: F401  (the one language)

#: The languages /api/v1/code writes (the expression language also has a scalar-Python
#: target, for the compiled kernels: app/physics/formula.py).
LANGS = ("glsl", "hlsl", "python")

TYPES = {"float": ("float", "float"), "vec3": ("vec3", "float3"),
         "int": ("int", "int"), "bool": ("bool", "bool")}


@dataclass
class Const:
    """A named number; ``uniform``: a parameter of the material, set by the caller (the
    parameterised form), its value here the default."""
    name: str
    value: float
    comment: str
    uniform: bool = False


@dataclass
class Table:
    """A constant array; ``kind`` "float" or "int". Tables of one name (one per lobe)
    are written as one array, each part at its ``offset``."""
    name: str
    values: list
    comment: str
    kind: str = "float"
    offset: int = 0


@dataclass
class Fn:
    """A function: typed parameters, typed single assignments, one return expression."""
    name: str
    ret: str
    params: list[tuple[str, str]]
    body: list[tuple[str, str, str]]
    result: str
    doc: str = ""
    notes: dict = field(default_factory=dict)   # variable → comment


@dataclass
class Program:
    """``texture``: the shaders read the tables from one R32F data texture (DATA_TEXTURE,
    texture.py) instead of embedding them as arrays; ``block``: from one uniform block
    (block.py); the Python form embeds them always."""
    header: list[str]
    consts: list[Const]
    tables: list[Table]
    functions: list[Fn]
    texture: bool = False
    block: bool = False
