"""GET /api/v1/lut (a LUT with its error, or one of its files) and POST /api/v1/lut/check
(an uploaded LUT's error map against the reference)."""
from __future__ import annotations

from typing import Annotated, Literal

from fastapi import APIRouter, Query, Request, Response
from pydantic import Field
from starlette.concurrency import run_in_threadpool

from ... import work
from ...errors import TooLarge
from ...lut import build, check, export, infer, png
from ...lut.table import KINDS, QUANTISATIONS, make, model_label, orientation
from ...model import make_spec
from ...physics.ndf import NDFS
from ...shader.generate import model_query
from ...views import schemas
from ..encode import json_response
from ..deps import Route

router = APIRouter(prefix="/api/v1", route_class=Route)

#: bytes an uploaded LUT may have: a 256² RG table as 16-bit PNG is ~0.4 MB, as JSON ~3 MB
UPLOAD_MAX_BYTES = 4 * 1024 * 1024
TWO_AXES = ["split_sum", "dfg_filament", "kc_E"]


class LutQuery(schemas.ModelQuery):
    kind: Annotated[Literal[tuple(KINDS)], Field(
        description="split_sum: (scale, bias) of F0 (Karis 2013); dfg_filament: Filament's (x, y) with "
                    "multiple-scattering compensation; kc_E: E(μ, α); kc_E_avg: E_avg(α). Single "
                    "scattering of the model's NDF, masking and G2 (exact Smith, or the Schlick-GGX approximations "
                    "engines ship: masking=schlick_ibl, schlick_direct); its Fresnel is factored out")]
    size: Annotated[int, Field(ge=build.SIZE_MIN, le=build.SIZE_MAX,
                               description=f"texels per axis, [{build.SIZE_MIN}, {build.SIZE_MAX}]")] = 32
    mu_axis: Annotated[Literal[build.MU_AXES], Field(
        description="mu: columns are μ = cos θ_v; sqrt_mu: columns are √μ (denser at grazing)",
        json_schema_extra=schemas.applies_to(kind=TWO_AXES))] = "mu"
    roughness_axis: Annotated[Literal[build.ROUGHNESS_AXES], Field(
        description="roughness: rows are r, α = r²; alpha: rows are α")] = "roughness"
    quantisation: Annotated[Literal[tuple(QUANTISATIONS)], Field(
        description="how the values are stored: unorm8, unorm16, float16, float32")] = "unorm16"

    def check(self) -> None:
        """The rules the schema cannot state, before any work (the fuzz test's oracle calls
        this too): an option only where it applies, a masking whose Λ is the model's own."""
        schemas.applies_where_given(self)
        values = schemas.spec_of(self).values
        build.check_masking(NDFS[values["ndf"]], values["masking"])


class LutFileQuery(LutQuery):
    format: Annotated[Literal[export.FORMATS], Field(
        description="json (values and error), png (unorm8/16; RG tables in R and G), csv, c (header), "
                    "glsl, hlsl (array literals), f16 (zip: raw little-endian float16 + JSON side-car)")] = "json"
    per_texel: Annotated[bool, Field(description="json: include the per-texel error maps")] = True

    def check(self) -> None:
        """:meth:`LutQuery.check`, and a file format that holds the quantisation."""
        super().check()
        if self.format != "json":
            export.check_format(self.format, self.quantisation)


def _lut(q: LutQuery):
    spec = make_spec(**schemas.model_values(q))
    return spec, make(q.kind, build.LobeKey.of(spec.brdf()), q.size, q.mu_axis, q.roughness_axis)


def _meta(spec, lut, q: LutQuery, errors: dict) -> dict:
    return {"kind": q.kind, "model_query": _lobe_query(spec), "model_label": model_label(spec.brdf()), "axes": lut.axes, "channels": list(lut.channels),
            "orientation": orientation(lut.dims), "usage": KINDS[q.kind][1], "quantisation": q.quantisation,
            "lookup_max": errors["lookup"]["max"].tolist()}


def _lobe_query(spec) -> str:
    keep = ("ndf", "masking", "g2", "lambda_phi", "gamma", "p")
    return "&".join(part for part in model_query(spec).split("&") if part.split("=")[0] in keep)


@router.get("/lut", tags=["code"], summary="A lookup table users ship (split sum, DFG, Kulla-Conty) with its error",
            description="Texel centres on both axes; every answer carries its error against the converged "
                        "integral: of the table, after quantisation, and after bilinear lookup.",
            responses={200: {"content": {"application/json": {},
                                         **{media.split(";")[0]: {} for media in export.MEDIA.values()}}}})
def lut(q: Annotated[LutFileQuery, Query()]) -> Response:
    q.check()
    spec, table = _lut(q)
    errors = table.errors(q.quantisation)
    meta = _meta(spec, table, q, errors)
    if q.format != "json":
        body = export.render(q.format, errors["values"], meta)
        name = f"{q.kind}_{q.size}_{q.quantisation}.{export.EXTENSIONS[q.format]}"
        return Response(body, media_type=export.MEDIA[q.format],
                        headers={"Content-Disposition": f'attachment; filename="{name}"'})
    error = {"reference": f"adaptive Gauss quadrature of E(μ) (tol {build.LUT_TOL:g}), its bound added",
             "step": errors["step"]}
    for part in ("table", "quantised", "lookup"):
        entry = {"max": dict(zip(table.channels, errors[part]["max"].tolist())),
                 "max_overall": float(errors[part]["max"].max())}
        if q.per_texel:
            entry["per_texel"] = errors[part]["per_texel"]
        if part == "lookup":
            entry["offsets"] = errors[part]["offsets"]
        error[part] = entry
    return json_response({**{k: v for k, v in meta.items() if k != "lookup_max"}, "model": meta["model_query"],
                          "model_label": meta["model_label"],
                          "size": q.size, "values": errors["values"], "error": error,
                          "build": {"seconds": table.seconds, "evaluations": table.evaluations}})


CHECK_DESCRIPTION = (
    f"Body: a PNG (8/16-bit; RG tables in R, G) or JSON {{\"values\": [i][j][c]}}, at most {UPLOAD_MAX_BYTES} "
    "bytes, n × n texels (kc_E_avg: n) with n ≥ 4; its size is read from it. The query says what it should be "
    "(kind, axes, model). Every combination of α = r² or r, μ = x or x², texel centres or edges per axis, "
    "G2 separable or height-correlated (or the query's), split form (scale/bias or DFG), axis order, "
    "orientation and channel order is built at the upload's resolution and fitted; the answer names the best, "
    "its residual, each convention's runner-up and margin, what differs from the query, and the error map of "
    "the upload read with bilinear filtering against the integral at the inferred positions.")
CHECK_BODY = {"required": True, "description": "the table: a PNG, or JSON {\"values\": [i][j][c]}", "content": {
    "image/png": {"schema": {"type": "string", "format": "binary"}},
    "application/json": {"schema": {"type": "object", "required": ["values"], "properties": {"values": {
        "type": "array", "description": "[rows][columns][channels] numbers (0–1, or 0–255 / 0–65535 integers)",
        "items": {"type": "array", "items": {"type": "array", "items": {"type": "number"}}}}}}}}}


@router.post("/lut/check", tags=["code"], summary="An uploaded LUT: its conventions inferred, its error map",
             description=CHECK_DESCRIPTION, openapi_extra={"requestBody": CHECK_BODY})
async def lut_check(request: Request, q: Annotated[LutQuery, Query()]) -> Response:
    q.check()
    body = await request.body()
    if len(body) > UPLOAD_MAX_BYTES:
        raise TooLarge("body", f"the upload has {len(body)} bytes; the limit is {UPLOAD_MAX_BYTES}", loc="body")
    # the conventions inferred in the heavy pool: a 256² table took ~8 s of the server's
    # GIL in a thread that could not be stopped (SIGTERM waited it out past the graceful
    # timeout). A PNG is read here (bounded: its size from its header before a byte is
    # inflated, so a bomb costs no pool place), a JSON table there (its 3 MB took seconds
    # of a server thread at load 19, which shutdown waited for)
    ctype = request.headers.get("content-type", "")
    if body.startswith(png.SIGNATURE) or ctype.startswith("image/png"):
        raw, bits = await run_in_threadpool(_parsed, q, body, ctype)
        return json_response(await work.run_heavy(_check, q, raw, bits))
    return json_response(await work.run_heavy(_check_body, q, body, ctype))


#: what an arrangement difference is called in the query's own axes (the words /lut/check
#: used before it inferred conventions, which the tools page and users know)
ARRANGEMENT_WORDS = {"roughness_direction": ": flipped along axes[0]", "mu_direction": ": flipped along axes[1]",
                     "axis_order": ": transposed (axes swapped)", "channels": ": channels swapped"}


def _expected(q: LutQuery, spec, dims: int, channels: int) -> dict:
    """The conventions the query names (this project's own: texel centres, rows roughness
    ascending, columns μ ascending, channels as named)."""
    model = infer.Model(spec.brdf().g2.name, q.roughness_axis, q.mu_axis if dims == 2 else None, "centres",
                        "centres" if dims == 2 else None, q.kind if channels == 2 else None)
    return infer.describe(model, infer.Arrangement("roughness", True, True, False))


def _shape(q: LutQuery) -> tuple[int, int]:
    """(axes, channels) of the table the query names."""
    return (1 if q.kind == "kc_E_avg" else 2), len(KINDS[q.kind][0])


def _parsed(q: LutQuery, body: bytes, content_type: str):
    """(values, PNG bit depth or None) of an uploaded table, its size checked."""
    dims, channels = _shape(q)
    raw, bits = check.parse(body, content_type, channels, dims)
    infer.check_size(raw.shape[0])
    return raw, bits


def _check_body(q: LutQuery, body: bytes, content_type: str) -> dict:
    """The answer of /lut/check for an uploaded body (read here: a JSON table)."""
    return _check(q, *_parsed(q, body, content_type))


def _check(q: LutQuery, raw, bits: int) -> dict:
    """The answer of /lut/check for the uploaded table ``raw`` (read by check.parse)."""
    dims, channels = _shape(q)
    values, stored = infer.storage(raw, bits)
    given = schemas.model_values(q)
    specs = {g2: make_spec(**{**given, "g2": g2}) for g2 in infer.G2_CANDIDATES}
    spec = make_spec(**given)
    specs.setdefault(spec.brdf().g2.name, spec)
    keys = {g2: build.LobeKey.of(s.brdf()) for g2, s in specs.items()}
    ranked = infer.fit(values, keys, dims)
    rms, worst, model, arrangement = ranked[0]
    found = infer.describe(model, arrangement)
    expected = _expected(q, spec, dims, channels)
    differs = {k: {"found": v, "expected": expected[k]} for k, v in found.items() if expected.get(k) != v}
    if "0–" in stored:
        differs["storage"] = {"found": stored, "expected": "unit values"}
    runner = ranked[1]
    runner_found = infer.describe(runner[2], runner[3])
    errors = infer.error_map(arrangement.canonical(values, dims), keys[model.g2], model, dims)
    return {
        "kind": q.kind, "model": _lobe_query(specs[model.g2]), "model_label": model_label(specs[model.g2].brdf()),
        "size": int(raw.shape[0]), "channels": list(KINDS[q.kind][0]), "storage": stored,
        "conventions": found, "expected": expected, "differs": differs,
        "diagnosis": None if not differs else "this table differs from the query in "
        + "; ".join(f"{k}: {d['found']}{ARRANGEMENT_WORDS.get(k, '')} (query: {d['expected']})"
                    for k, d in differs.items()),
        "fit": {"residual_rms": rms, "residual_max": worst,
                "sampled_indices": infer.sample(int(raw.shape[0]), infer.SAMPLE_PER_AXIS),
                "hypotheses": len(ranked),
                "runner_up": {"residual_rms": runner[0], "ratio": infer.ratio(runner[0], rms),
                              "differs_in": {k: v for k, v in runner_found.items() if found.get(k) != v}},
                "margins": infer.margins(ranked)},
        "error": {**errors, "note": "after bilinear filtering at the upload's own resolution, in the inferred "
                                    "conventions (the upload rearranged to rows roughness, columns μ)"},
    }
