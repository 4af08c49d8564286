"""One spelling of a formula for every target: the neutral expression language.

A :class:`Formula` is a straight-line function of float arguments: single assignments
and a return expression, in C syntax plus a few macros (``sel(c, a, b)`` = c ? a : b,
``and_``, ``or_``, ``not_``, ``sqrt exp expm1 log abs floor pow min max clamp atan2
acos erfcx``, ``INF()`` = +∞). Named parameters ``p`` are read from the entry's
``kernel_params()`` array, in order. From the one spelling come:

* ``scalar``: plain Python over ``math`` for one point, the ``*_scalar`` functions that
  app/kernels compiles with numba (``@scalar``; conditional expressions evaluate one side);
* ``python``: numpy over arrays (``np.where`` evaluates both sides, warnings silenced),
  the Python that /api/v1/code writes, the same algorithm as its shaders;
* ``glsl`` / ``hlsl``: the shader functions app/shader writes (erfcx as a fitted helper).

An entry declares a formula as a class attribute (``D_formula``, ``F_formula``, …);
``scalar_function`` turns it into the ``*_scalar`` attribute the kernels resolve by
module and qualified name, with its source registered so that the kernels' cache key
(``inspect.getsource``) changes when the formula does. The numpy methods of each entry
stay the independent, readable reference both are tested against.
"""
from __future__ import annotations

import linecache
import math
import re
from dataclasses import dataclass

import scipy.special

from .scalar import scalar

LANGS = ("glsl", "hlsl", "python", "scalar")

# name → (GLSL, HLSL, numpy, scalar Python) templates over the translated arguments
MACROS = {
    "sel": ("(({0}) ? ({1}) : ({2}))", "(({0}) ? ({1}) : ({2}))", "np.where({0}, {1}, {2})",
            "(({1}) if ({0}) else ({2}))"),
    "sel3": ("(({0}) ? ({1}) : ({2}))", "(({0}) ? ({1}) : ({2}))",
             "np.where(np.asarray({0})[..., None], {1}, {2})", None),
    "and_": ("(({0}) && ({1}))", "(({0}) && ({1}))", "(({0}) & ({1}))", "(({0}) and ({1}))"),
    "or_": ("(({0}) || ({1}))", "(({0}) || ({1}))", "(({0}) | ({1}))", "(({0}) or ({1}))"),
    "not_": ("(!({0}))", "(!({0}))", "(~({0}))", "(not ({0}))"),
    "X": ("({0}).x", "({0}).x", "({0})[..., 0]", None),
    "Y": ("({0}).y", "({0}).y", "({0})[..., 1]", None),
    "Z": ("({0}).z", "({0}).z", "({0})[..., 2]", None),
    "vec3": ("vec3({0}, {1}, {2})", "float3({0}, {1}, {2})", "_vec3({0}, {1}, {2})", None),
    "splat": ("vec3({0})", "(({0}).xxx)", "_splat({0})", None),
    "dot": ("dot({0}, {1})", "dot({0}, {1})", "_dot({0}, {1})", None),
    "cross": ("cross({0}, {1})", "cross({0}, {1})", "np.cross({0}, {1})", None),
    "normalize": ("normalize({0})", "normalize({0})", "_normalize({0})", None),
    "length": ("length({0})", "length({0})", "np.sqrt(_dot({0}, {0}))", None),
    "sqrt": ("sqrt({0})", "sqrt({0})", "np.sqrt({0})", "math.sqrt({0})"),
    "exp": ("exp({0})", "exp({0})", "np.exp({0})", "math.exp({0})"),
    "log": ("log({0})", "log({0})", "np.log({0})", "math.log({0})"),
    "abs": ("abs({0})", "abs({0})", "np.abs({0})", "abs({0})"),
    "floor": ("floor({0})", "floor({0})", "np.floor({0})", "math.floor({0})"),
    "pow": ("pow({0}, {1})", "pow({0}, {1})", "np.power({0}, {1})", "(({0}) ** ({1}))"),
    "min": ("min({0}, {1})", "min({0}, {1})", "np.minimum({0}, {1})", "min({0}, {1})"),
    "max": ("max({0}, {1})", "max({0}, {1})", "np.maximum({0}, {1})", "max({0}, {1})"),
    "clamp": ("clamp({0}, {1}, {2})", "clamp({0}, {1}, {2})", "np.clip({0}, {1}, {2})",
              "min(max({0}, {1}), {2})"),
    "atan2": ("atan({0}, {1})", "atan2({0}, {1})", "np.arctan2({0}, {1})", "math.atan2({0}, {1})"),
    # e^x − 1: exact near 0 in numpy and the kernels; the shading languages have no
    # expm1, and exp(x) − 1 loses only absolute 1 ulp of 1 there (enough for float32 code)
    "expm1": ("(exp({0}) - 1.0)", "(exp({0}) - 1.0)", "np.expm1({0})", "math.expm1({0})"),
    "acos": ("acos({0})", "acos({0})", "np.arccos({0})", "math.acos({0})"),
    # erfcx(x) = e^{x²} erfc(x): scipy's in the kernels (app/kernels/special.py links the
    # same routine as numpy's); in generated code a fitted helper (app/shader/library.py)
    "erfcx": ("erfcx({0})", "erfcx({0})", "erfcx({0})", "erfcx({0})"),
    "toint": ("int({0})", "int({0})", "np.asarray({0}).astype(np.int64)", None),
    "tofloat": ("float({0})", "float({0})", "np.asarray({0}, dtype=float)", None),
    "INF": ("uintBitsToFloat(0x7F800000u)", "asfloat(0x7F800000u)", "np.inf", "math.inf"),
}

_TOKEN = re.compile(r"\s*(?:(\d+\.\d*(?:[eE][+-]?\d+)?|\d*\.\d+(?:[eE][+-]?\d+)?|\d+[eE][+-]?\d+"
                    r"|\d+)|([A-Za-z_]\w*)|(&&|\|\||==|!=|<=|>=|[-+*/()<>,\[\]!?:%]))")


def tokens(text: str) -> list[str]:
    out, pos = [], 0
    text = text.strip()
    while pos < len(text):
        m = _TOKEN.match(text, pos)
        if not m or m.end() == pos:
            raise ValueError(f"cannot read {text[pos:pos + 20]!r} in {text!r}")
        out.append(m.group(1) or m.group(2) or m.group(3))
        pos = m.end()
    return out


def translate(expr: str, lang: str, overrides: dict | None = None) -> str:
    """``expr`` (the neutral syntax) in ``lang``; ``overrides``: macro name → template
    taking the place of MACROS' for this translation (the float32 scalar form)."""
    if lang not in LANGS:
        raise ValueError(f"lang must be one of {', '.join(LANGS)}")
    text, _ = _emit(tokens(expr), 0, LANGS.index(lang), stop=(), overrides=overrides or {})
    # the templates bracket every argument; a bracketed single name or number needs none
    while True:
        shorter = _REDUNDANT.sub(r"\1", text)
        if shorter == text:
            return text
        text = shorter


_REDUNDANT = re.compile(r"(?<![\w\]])\(([\w.]+)\)")


def _emit(tok: list[str], i: int, k: int, stop: tuple, overrides: dict | None = None) -> tuple[str, int]:
    parts: list[str] = []
    depth = 0
    overrides = overrides or {}
    while i < len(tok):
        t = tok[i]
        if depth == 0 and t in stop:
            break
        if t in MACROS and i + 1 < len(tok) and tok[i + 1] == "(":
            template = overrides.get(t, MACROS[t][k])
            if template is None:
                raise ValueError(f"{t}() has no {LANGS[k]} form")
            args, i = _args(tok, i + 2, k, overrides)
            parts.append(template.format(*args))
            continue
        if t in "([":
            depth += 1
        elif t in ")]":
            depth -= 1
        parts.append(t)
        i += 1
    return _join(parts), i


def _args(tok: list[str], i: int, k: int, overrides: dict | None = None) -> tuple[list[str], int]:
    args = []
    if tok[i] == ")":
        return args, i + 1
    while True:
        text, i = _emit(tok, i, k, stop=(",", ")"), overrides=overrides)
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


@dataclass(frozen=True)
class Formula:
    """A float function written once. ``args``: its float arguments; ``p``: names bound,
    in order, to the entry's ``kernel_params()``; ``consts``: named numbers it uses
    (name → (value, why)); ``body``: (name, expression) assignments; ``result``."""
    name: str
    args: tuple[str, ...]
    result: str
    body: tuple[tuple[str, str], ...] = ()
    p: tuple[str, ...] = ()
    consts: tuple[tuple[str, float, str], ...] = ()
    doc: str = ""

    def uses(self, name: str) -> bool:
        return any(name in tokens(e) for e in [self.result, *(x for _, x in self.body)])

    def scalar_source(self, fn_name: str, extra_args: tuple[str, ...] = ("p",)) -> str:
        """The formula as plain Python for one point (``def fn_name(*args, p): ...``)."""
        lines = [f"def {fn_name}({', '.join(self.args + extra_args)}):"]
        if self.doc:
            lines.append(f'    """{self.doc.splitlines()[0]}"""')
        lines += [f"    {name} = p[{i}]" for i, name in enumerate(self.p)]
        lines += [f"    {name} = {literal(value)}" for name, value, _ in self.consts]
        lines += [f"    {name} = {translate(expr, 'scalar')}" for name, expr in self.body]
        lines.append(f"    return {translate(self.result, 'scalar')}")
        return "\n".join(lines) + "\n"


    def scalar32_source(self, fn_name: str, extra_args: tuple[str, ...] = ("p",)) -> str:
        """The formula as plain Python for one point in float32 (app/kernels' float32 f
        loop): the same assignments as :meth:`scalar_source`, every number typed float32
        (``f32(c)``, ``f32 = numpy.float32``: numba types a Python float as float64 and
        float32 · float64 as float64, which would run the loop in double), and the macros
        whose scalar form is not float32 replaced (SCALAR32). The arguments and ``p`` are
        float32 from the caller. A number float32 cannot hold (overflow, or a nonzero one
        that rounds to 0) is refused: the formula has no float32 form."""
        lines = [f"def {fn_name}({', '.join(self.args + extra_args)}):"]
        if self.doc:
            lines.append(f'    """{self.doc.splitlines()[0]} (float32)"""')
        lines += [f"    {name} = p[{i}]" for i, name in enumerate(self.p)]
        lines += [f"    {name} = f32({float32_literal(value)})" for name, value, _ in self.consts]
        lines += [f"    {name} = {translate(_f32_numbers(expr), 'scalar', SCALAR32)}"
                  for name, expr in self.body]
        lines.append(f"    return {translate(_f32_numbers(self.result), 'scalar', SCALAR32)}")
        return "\n".join(lines) + "\n"


#: The scalar forms that change in float32 (Formula.scalar32_source): +∞ as a float32;
#: erfcx has only scipy's float64 routine, so it is called in float64 on the float32
#: argument and its value rounded to float32 (one rounding more than float64's path);
#: floor returns an int in numba (an int times a float32 is a float64), so it is made
#: float32 again. Every other scalar macro (math.sqrt/exp/expm1/log/acos/atan2, abs, min,
#: max, **, comparisons, selects) keeps float32 arguments float32 in numba (checked in the
#: loop's LLVM IR by tests/kernels/test_float32.py).
SCALAR32 = {
    "INF": "f32(math.inf)",
    "erfcx": "f32(erfcx(float({0})))",
    "floor": "f32(math.floor({0}))",
}

_NUMBER = re.compile(r"[\d.]")


def float32_literal(x: float) -> str:
    """:func:`literal`, refused where float32 cannot hold the number."""
    import numpy as np
    with np.errstate(over="ignore", under="ignore"):
        y = np.float32(x)
    if not np.isfinite(y) or (x != 0.0 and y == 0.0):
        raise ValueError(f"constant {x!r} is outside float32's range")
    return literal(x)


def _f32_numbers(expr: str) -> str:
    """``expr`` with every number written f32(number) (a neutral-syntax call: f32 is no
    macro, so it passes through every translation as a call of that name)."""
    out = []
    for t in tokens(expr):
        out.append(f"f32({float32_literal(float(t))})" if _NUMBER.match(t) else t)
    return " ".join(out)


_counter = [0]


def scalar_function(formula: Formula, module: str, qualname: str,
                    extra_args: tuple[str, ...] = ("p",)):
    """The formula compiled as a ``@scalar`` Python function named ``qualname`` of
    ``module`` (where app/kernels resolves it); ``extra_args`` follow the formula's
    arguments (the kernels' fixed signature, e.g. ``p`` or the masking's NDF hooks)."""
    fn_name = qualname.rsplit(".", 1)[-1]
    source = formula.scalar_source(fn_name, extra_args)
    _counter[0] += 1
    filename = f"<formula {module}.{qualname} #{_counter[0]}>"
    linecache.cache[filename] = (len(source), None, source.splitlines(True), filename)
    namespace = {"math": math, "erfcx": scipy.special.erfcx, "__name__": module}
    exec(compile(source, filename, "exec"), namespace)
    fn = namespace[fn_name]
    fn.__module__ = module
    fn.__qualname__ = qualname
    fn.formula = formula
    return scalar(fn)
