"""A :class:`~app.shader.dsl.Program` written out as GLSL ES 3.00, HLSL or Python (numpy).

Constants and table entries: 9 significant digits in the shaders (every float32 round
trips through 9 digits), 17 in Python (float64).
"""
from __future__ import annotations

import functools
import textwrap

from . import block, texture
from .dsl import LANGS, TYPES, Fn, Program, literal
from .dsl import translate as _translate

#: The translation of an expression depends on its text and the language only, and the
#: same few hundred expressions recur in every program: translated once each.
translate = functools.lru_cache(maxsize=8192)(_translate)

PY_PRELUDE = '''import functools

import numpy as np


def _quiet(fn):
    """numpy evaluates both sides of every np.where: the side not chosen may divide by
    zero; its value is discarded, so its warnings are silenced."""
    @functools.wraps(fn)
    def inner(*args):
        with np.errstate(all="ignore"):
            return fn(*[a if np.asarray(a).dtype == bool else np.asarray(a, dtype=float) for a in args])
    return inner


def _vec3(a, b, c):
    return np.stack(np.broadcast_arrays(a, b, c), axis=-1)


def _splat(a):
    a = np.asarray(a, dtype=float)
    return _vec3(a, a, a)


def _dot(a, b):
    return np.sum(np.asarray(a) * np.asarray(b), axis=-1)


def _normalize(a):
    return a / np.sqrt(_dot(a, a))[..., None]
'''


def _shader_number(x) -> str:
    text = f"{float(x):.9g}"
    return text if ("." in text or "e" in text or "n" in text) else text + ".0"


def _number(x, lang: str, kind: str = "float") -> str:
    if kind == "int":
        return str(int(x))
    text = literal(x)            # refuses inf and NaN
    return text if lang == "python" else _shader_number(x)


def _comment(lang: str) -> str:
    return "#" if lang == "python" else "//"


def _wrap(items: list[str], indent: str, width: int = 100) -> list[str]:
    return textwrap.wrap(", ".join(items), width=width, initial_indent=indent,
                         subsequent_indent=indent, break_on_hyphens=False)


def write(program: Program, lang: str) -> str:
    """The program's source text in ``lang`` (one of LANGS)."""
    if lang not in LANGS:
        raise ValueError(f"lang must be one of {', '.join(LANGS)}")
    c = _comment(lang)
    out: list[str] = []
    if lang == "python":
        out.append('"""' + "\n".join(program.header) + '\n"""')
        out.append(PY_PRELUDE)
    else:
        out += [f"{c} {line}".rstrip() for line in program.header]
        out.append("")
    for k in program.consts:
        value = _number(k.value, lang)
        if k.uniform:
            out.append(f"{k.name} = {value}  # uniform: {k.comment}" if lang == "python" else
                       f"uniform float {k.name};  {c} {k.comment} (e.g. {value})")
        elif lang == "python":
            out.append(f"{k.name} = {value}  # {k.comment}")
        else:
            prefix = "const float" if lang == "glsl" else "static const float"
            out.append(f"{prefix} {k.name} = {value};  {c} {k.comment}")
    in_texture = program.texture and lang != "python" and program.tables
    in_block = program.block and not in_texture and lang != "python" and program.tables
    parts = texture.layout(program.tables) if in_texture or in_block else {}
    if in_texture:
        out.append("")
        comment, sampler = texture.declaration(lang, program.tables)
        out += [f"{c} {line}" for line in textwrap.wrap(comment, 96)] + [sampler]
        out += texture.reader(lang, texture.describe(program.tables)["width"])
    elif in_block:
        out.append("")
        comment, lines = block.declaration(lang, program.tables)
        out += [f"{c} {line}" for line in textwrap.wrap(comment, 96)] + lines
    for t in ([] if in_texture or in_block else program.tables):
        out.append("")
        out += [f"{c} {line}" for line in textwrap.wrap(t.comment, 96)]
        items = [_number(x, lang, t.kind) for x in t.values]
        n = len(items)
        if lang == "python":
            dtype = "np.int64" if t.kind == "int" else "float"
            out.append(f"{t.name} = np.array([")
            out += _wrap(items, "    ")
            out.append(f"], dtype={dtype})")
        elif lang == "glsl":
            out.append(f"const {t.kind} {t.name}[{n}] = {t.kind}[{n}](")
            out += _wrap(items, "    ")
            out.append(");")
        else:
            out.append(f"static const {t.kind} {t.name}[{n}] = {{")
            out += _wrap(items, "    ")
            out.append("};")
    for fn in program.functions:
        out.append("")
        out += _function(fn, lang, parts)
    return "\n".join(out) + "\n"


def _function(fn: Fn, lang: str, parts: dict | None = None) -> list[str]:
    """The function in ``lang``; ``parts``: tables read through ``data_at`` (the data
    texture, texture.py, or the uniform block, block.py)."""
    if parts:
        fn = Fn(fn.name, fn.ret, fn.params, [(t, n, texture.rewrite(e, parts)) for t, n, e in fn.body],
                texture.rewrite(fn.result, parts), fn.doc, fn.notes)
    c = _comment(lang)
    k = 0 if lang == "glsl" else 1
    lines: list[str] = []
    doc = [line for line in fn.doc.strip().splitlines()] if fn.doc.strip() else []
    if lang == "python":
        args = ", ".join(name for _, name in fn.params)
        lines.append("@_quiet")
        lines.append(f"def {fn.name}({args}):")
        if doc:
            lines.append('    """' + "\n    ".join(doc) + '"""')
        for typ, name, expr in fn.body:
            note = fn.notes.get(name)
            lines.append(f"    {name} = {translate(expr, lang)}" + (f"  # {note}" if note else ""))
        lines.append(f"    return {translate(fn.result, lang)}")
        return lines
    lines += [f"{c} {line}".rstrip() for line in doc]
    params = ", ".join(f"{TYPES[t][k]} {name}" for t, name in fn.params)
    lines.append(f"{TYPES[fn.ret][k]} {fn.name}({params}) {{")
    for typ, name, expr in fn.body:
        note = fn.notes.get(name)
        lines.append(f"    {TYPES[typ][k]} {name} = {translate(expr, lang)};" + (f"  {c} {note}" if note else ""))
    lines.append(f"    return {translate(fn.result, lang)};")
    lines.append("}")
    return lines
