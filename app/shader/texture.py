"""A program's tables as one R32F data texture, read by index with texelFetch (GLSL) or
Load (HLSL): no filtering, so there is no texel-centre or α-mapping convention to get
wrong, and the values read are the float32 roundings of the tables the Python form embeds.

Entry i of the concatenated tables is texel (i mod WIDTH, i div WIDTH); each table starts
at its offset (``layout``). A table read ``NAME[expr]`` in the program's expressions is
written ``data_at(offset + (expr))``."""
from __future__ import annotations

import math

from .dsl import Table

NAME = "BRDF_DATA"
WIDTH = 256


def layout(tables: list[Table]) -> dict[str, tuple[int, int]]:
    """name → (offset, length) in the texture, the tables in the program's order."""
    out, at = {}, 0
    for t in tables:
        if t.kind != "float":
            raise ValueError(f"table {t.name}: an R32F texture holds floats, not {t.kind}")
        out[t.name] = (at, len(t.values))
        at += len(t.values)
    return out


def describe(tables: list[Table]) -> dict:
    """The texture as /code's JSON gives it: size, format, the values row by row (the last
    row padded with 0) and where each table lies."""
    parts = layout(tables)
    values = [float(x) for t in tables for x in t.values]
    height = max(1, math.ceil(len(values) / WIDTH))
    width = min(WIDTH, max(1, len(values))) if height == 1 else WIDTH
    values += [0.0] * (width * height - len(values))
    return {"name": NAME, "format": "R32F", "width": width, "height": height, "filter": "none (texelFetch / Load)",
            "index": f"entry i at texel (i mod {width}, i div {width}), row 0 first",
            "parts": {name: {"offset": o, "length": n} for name, (o, n) in parts.items()}, "data": values}


def declaration(lang: str, tables: list[Table]) -> list[str]:
    """The comment saying what the texture holds (one paragraph), then the sampler."""
    d = describe(tables)
    parts = ", ".join(f"{name} at {p['offset']}" for name, p in d["parts"].items())
    comment = (f"{NAME}: these tables in one {d['width']}×{d['height']} R32F texture, unfiltered, entry i at "
               f"texel (i mod {d['width']}, i div {d['width']}): {parts}. Its values: GET /api/v1/code?format=json, "
               "\"textures\" (the Python form embeds the tables).")
    return [comment, f"uniform highp sampler2D {NAME};" if lang == "glsl" else f"Texture2D<float> {NAME};"]


def reader(lang: str, width: int) -> list[str]:
    """``data_at(i)``: entry i of the data texture."""
    if lang == "glsl":
        fetch = f"texelFetch({NAME}, ivec2(i % {width}, i / {width}), 0).r"
    else:
        fetch = f"{NAME}.Load(int3(i % {width}, i / {width}, 0))"
    return [f"float data_at(int i) {{", f"    return {fetch};", "}"]


def rewrite(expr: str, parts: dict[str, tuple[int, int]]) -> str:
    """``NAME[e]`` of each table in ``parts`` as ``data_at(offset + (e))``."""
    if "[" not in expr:
        return expr
    out, i = [], 0
    while i < len(expr):
        j = expr.find("[", i)
        if j < 0:
            out.append(expr[i:])
            break
        k = j
        while k > 0 and (expr[k - 1].isalnum() or expr[k - 1] == "_"):
            k -= 1
        name = expr[k:j]
        if name not in parts:
            out.append(expr[i:j + 1])
            i = j + 1
            continue
        depth, e = 1, j + 1
        while depth:
            depth += {"[": 1, "]": -1}.get(expr[e], 0)
            e += 1
        inner = rewrite(expr[j + 1:e - 1], parts)
        out.append(expr[i:k] + f"data_at({parts[name][0]} + ({inner}))")
        i = e
    return "".join(out)
