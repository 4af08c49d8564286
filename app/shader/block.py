"""A program's tables as one uniform block (the parameterised form the GPU views run):
std140 vec4s, entry i at BRDF_TABLE4[i >> 2][i & 3], read through the same ``data_at(i)``
as the data texture (texture.py), so a table read is rewritten the same way.

Why, and when: a constant array indexed at run time is copied into each shader
invocation's private memory by SwiftShader (and by other compilers that lower GLSL to
SPIR-V), so its cost grows with its length; a block's grows with its reads. Measured in
headless Chromium, a 256² quad, the same program drawn warm, side by side: one Smith fit
(264 numbers, GTR γ = 1.2) 4.7 ms embedded against 5.4 ms from a block; two fits (528, the
two-lobe GTR) 15.8 ms against 10.3 ms — so tables of at least BLOCK_MIN_FLOATS numbers go
in the block, fewer stay embedded (bench/gpu_sphere.py draws every registry model). The data texture costs more than either (a scalar texelFetch per
coefficient: one fit 7.3 → 10.7 ms). The const form keeps its arrays: it is the
self-contained code a developer ships.
"""
from __future__ import annotations

from .dsl import Table
from .texture import layout

NAME = "BRDF_TABLES"
ARRAY = "BRDF_TABLE4"
#: floats a block may hold: WebGL2's (and Direct3D's feature level 10) smallest
#: MAX_UNIFORM_BLOCK_SIZE, 16 384 bytes; larger tables stay embedded arrays
MAX_FLOATS = 16384 // 4
#: fewer floats than this stay embedded: the crossover measured above lies between one
#: Smith fit (264) and two (528)
BLOCK_MIN_FLOATS = 400


def fits(tables: list[Table]) -> bool:
    """Whether ``tables`` (float tables only) belong in one block: large enough to pay
    for it, small enough to fit."""
    n = sum(len(t.values) for t in tables)
    return all(t.kind == "float" for t in tables) and BLOCK_MIN_FLOATS <= n <= MAX_FLOATS


def describe(tables: list[Table]) -> dict:
    """The block as /code's JSON gives it: its packing, its one member and the values
    (padded with 0 to whole vec4s), and where each table lies."""
    values = [float(x) for t in tables for x in t.values]
    vec4s = -(-len(values) // 4)
    values += [0.0] * (4 * vec4s - len(values))
    return {"name": NAME, "packing": "std140", "member": f"vec4 {ARRAY}[{vec4s}]",
            "index": f"entry i at {ARRAY}[i >> 2][i & 3]", "data": values,
            "parts": {name: {"offset": o, "length": n} for name, (o, n) in layout(tables).items()}}


def declaration(lang: str, tables: list[Table]) -> tuple[str, list[str]]:
    """The comment saying what the block holds (one paragraph), then its declaration and
    ``data_at(i)``."""
    d = describe(tables)
    vec4s = len(d["data"]) // 4
    parts = ", ".join(f"{name} at {p['offset']}" for name, p in d["parts"].items())
    comment = (f"{NAME}: these tables in one uniform block of {vec4s} vec4 (std140), entry i at "
               f"{ARRAY}[i >> 2][i & 3]: {parts}. Its values: GET /api/v1/code?format=json, \"blocks\" "
               "(the const form embeds the tables).")
    if lang == "glsl":
        return comment, [f"layout(std140) uniform {NAME} {{ vec4 {ARRAY}[{vec4s}]; }};",
                         "float data_at(int i) {", f"    return {ARRAY}[i >> 2][i & 3];", "}"]
    return comment, [f"cbuffer {NAME} {{ float4 {ARRAY}[{vec4s}]; }};",
                     "float data_at(int i) {", f"    return {ARRAY}[i >> 2][i & 3];", "}"]
