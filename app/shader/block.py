"""A program's tables as one uniform block (the parameterised form the GPU views run):
std140 vec4s, entry i at BRDF_TABLE4[i >> 2][i & 3], read through the same ``data_at(i)``
as the data texture (texture.py), so a table read is rewritten the same way.

Why not the embedded array: a constant array indexed at run time is copied into each
shader invocation's private memory by SwiftShader (and by other compilers that lower
GLSL to SPIR-V), so its cost grows with its length, not with the reads. Measured in
headless Chromium, 256² pixels, the two-lobe GTR (γ = 1.2) whose Smith fits are 544
numbers: 25.1 ms a frame embedded, 15.5 ms from a uniform block; one lobe 11.9 → 7.7 ms
(bench/gpu_sphere.py draws every registry model). Why not the data texture: a scalar
texelFetch per coefficient cost more than the copy (one lobe 7.3 → 10.7 ms). The const
form keeps the arrays: it is the self-contained code a developer ships."""
from __future__ import annotations

from .dsl import Table
from .texture import layout

NAME = "BRDF_TABLES"
ARRAY = "BRDF_TABLE4"
#: floats a block may hold: WebGL2's (and Direct3D's feature level 10) smallest
#: MAX_UNIFORM_BLOCK_SIZE, 16 384 bytes; larger tables stay embedded arrays
MAX_FLOATS = 16384 // 4


def fits(tables: list[Table]) -> bool:
    """Whether ``tables`` (float tables only) fit one block."""
    return bool(tables) and all(t.kind == "float" for t in tables) and \
        sum(len(t.values) for t in tables) <= MAX_FLOATS


def describe(tables: list[Table]) -> dict:
    """The block as /code's JSON gives it: its layout, its one member and the values
    (padded with 0 to whole vec4s), and where each table lies."""
    values = [float(x) for t in tables for x in t.values]
    vec4s = -(-len(values) // 4)
    values += [0.0] * (4 * vec4s - len(values))
    return {"name": NAME, "layout": "std140", "member": f"vec4 {ARRAY}[{vec4s}]",
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
