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

import math
import re
from dataclasses import dataclass, field

LANGS = ("glsl", "hlsl", "python")

TYPES = {"float": ("float", "float"), "vec3": ("vec3", "float3"),
         "int": ("int", "int"), "bool": ("bool", "bool")}

# name → (GLSL, HLSL, Python) templates over the translated arguments {0}, {1}, ...
MACROS = {
    "sel": ("(({0}) ? ({1}) : ({2}))", "(({0}) ? ({1}) : ({2}))", "np.where({0}, {1}, {2})"),
    "sel3": ("(({0}) ? ({1}) : ({2}))", "(({0}) ? ({1}) : ({2}))",
             "np.where(np.asarray({0})[..., None], {1}, {2})"),
    "and_": ("(({0}) && ({1}))", "(({0}) && ({1}))", "(({0}) & ({1}))"),
    "or_": ("(({0}) || ({1}))", "(({0}) || ({1}))", "(({0}) | ({1}))"),
    "not_": ("(!({0}))", "(!({0}))", "(~({0}))"),
    "X": ("({0}).x", "({0}).x", "({0})[..., 0]"),
    "Y": ("({0}).y", "({0}).y", "({0})[..., 1]"),
    "Z": ("({0}).z", "({0}).z", "({0})[..., 2]"),
    "vec3": ("vec3({0}, {1}, {2})", "float3({0}, {1}, {2})", "_vec3({0}, {1}, {2})"),
    "splat": ("vec3({0})", "(({0}).xxx)", "_splat({0})"),
    "dot": ("dot({0}, {1})", "dot({0}, {1})", "_dot({0}, {1})"),
    "cross": ("cross({0}, {1})", "cross({0}, {1})", "np.cross({0}, {1})"),
    "normalize": ("normalize({0})", "normalize({0})", "_normalize({0})"),
    "length": ("length({0})", "length({0})", "np.sqrt(_dot({0}, {0}))"),
    "sqrt": ("sqrt({0})", "sqrt({0})", "np.sqrt({0})"),
    "exp": ("exp({0})", "exp({0})", "np.exp({0})"),
    "log": ("log({0})", "log({0})", "np.log({0})"),
    "abs": ("abs({0})", "abs({0})", "np.abs({0})"),
    "floor": ("floor({0})", "floor({0})", "np.floor({0})"),
    "pow": ("pow({0}, {1})", "pow({0}, {1})", "np.power({0}, {1})"),
    "min": ("min({0}, {1})", "min({0}, {1})", "np.minimum({0}, {1})"),
    "max": ("max({0}, {1})", "max({0}, {1})", "np.maximum({0}, {1})"),
    "clamp": ("clamp({0}, {1}, {2})", "clamp({0}, {1}, {2})", "np.clip({0}, {1}, {2})"),
    "atan2": ("atan({0}, {1})", "atan2({0}, {1})", "np.arctan2({0}, {1})"),
    "toint": ("int({0})", "int({0})", "np.asarray({0}).astype(np.int64)"),
    "tofloat": ("float({0})", "float({0})", "np.asarray({0}, dtype=float)"),
    "INF": ("uintBitsToFloat(0x7F800000u)", "asfloat(0x7F800000u)", "np.inf"),
}

_TOKEN = re.compile(r"\s*(?:(\d+\.\d*(?:[eE][+-]?\d+)?|\d*\.\d+(?:[eE][+-]?\d+)?|\d+[eE][+-]?\d+"
                    r"|\d+)|([A-Za-z_]\w*)|(&&|\|\||==|!=|<=|>=|[-+*/()<>,\[\]!?:%]))")


def _tokens(text: str) -> list[str]:
    out, pos = [], 0
    text = text.strip()
    while pos < len(text):
        m = _TOKEN.match(text, pos)
        if not m or m.end() == pos:
            raise ValueError(f"cannot read {text[pos:pos + 20]!r} in {text!r}")
        out.append(m.group(1) or m.group(2) or m.group(3))
        pos = m.end()
    return out


def translate(expr: str, lang: str) -> str:
    """``expr`` (the neutral syntax) in ``lang``."""
    if lang not in LANGS:
        raise ValueError(f"lang must be one of {', '.join(LANGS)}")
    text, _ = _emit(_tokens(expr), 0, LANGS.index(lang), stop=())
    # the templates bracket every argument; a bracketed single name or number needs none
    while True:
        shorter = _REDUNDANT.sub(r"\1", text)
        if shorter == text:
            return text
        text = shorter


_REDUNDANT = re.compile(r"(?<![\w\]])\(([\w.]+)\)")


def _emit(tok: list[str], i: int, k: int, stop: tuple) -> tuple[str, int]:
    parts: list[str] = []
    depth = 0
    while i < len(tok):
        t = tok[i]
        if depth == 0 and t in stop:
            break
        if t in MACROS and i + 1 < len(tok) and tok[i + 1] == "(":
            args, i = _args(tok, i + 2, k)
            parts.append(MACROS[t][k].format(*args))
            continue
        if t in "([":
            depth += 1
        elif t in ")]":
            depth -= 1
        parts.append(t)
        i += 1
    return _join(parts), i


def _args(tok: list[str], i: int, k: int) -> tuple[list[str], int]:
    args = []
    if tok[i] == ")":
        return args, i + 1
    while True:
        text, i = _emit(tok, i, k, stop=(",", ")"))
        args.append(text)
        if tok[i] == ")":
            return args, i + 1
        i += 1


_BINARY = {"+", "-", "*", "/", "<", ">", "<=", ">=", "==", "!=", "&&", "||", "?", ":", "%"}


def _join(parts: list[str]) -> str:
    """Tokens (and translated macro calls) as readable text: spaces around binary
    operators, none inside brackets; a minus after an operator or bracket is unary."""
    out = ""
    prev = None
    for p in parts:
        if p == ",":
            out += ", "
        elif p in ")]":
            out = out.rstrip() + p
        elif p in _BINARY and prev is not None and prev not in _BINARY and prev not in "([,":
            out += f" {p} "
        else:
            out += p
        prev = p
    return out


def literal(x: float) -> str:
    """A float literal that GLSL, HLSL and Python read alike (round trip in float64)."""
    x = float(x)
    if not math.isfinite(x):
        raise ValueError(f"constant {x!r} is not finite")
    text = repr(x)
    return text if ("." in text or "e" in text) else text + ".0"


@dataclass
class Const:
    name: str
    value: float
    comment: str


@dataclass
class Table:
    """A constant array; ``kind`` "float" or "int"."""
    name: str
    values: list
    comment: str
    kind: str = "float"


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
    header: list[str]
    consts: list[Const]
    tables: list[Table]
    functions: list[Fn]
