"""Query models generated from the model registry.

``ModelQuery`` has the fields every model family declares (app/model/registry.py), so a
new family, NDF or shape parameter appears in the API, its validation and ``/docs`` with
no change here. Exact per-choice ranges and applicability are checked by
:func:`app.model.make_spec`.
"""
from typing import Annotated, Literal, Optional

from pydantic import BaseModel, BeforeValidator, ConfigDict, Field, create_model

from ..integrate.albedo import ORDER_MAX
from ..integrate.methods import DEFAULT_SAMPLES, MC_METHODS, MC_SAMPLES_MAX, METHODS
from ..errors import ParameterError
from ..model import ModelSpec, make_spec, query_fields

STRICT = ConfigDict(extra="forbid", allow_inf_nan=False)


def applies_to(**when: list) -> dict:
    """OpenAPI extension ``x-applies-to`` of a parameter that matters only when another
    one takes certain values (``samples`` only with a Monte Carlo ``method``). Given
    otherwise, the request is refused (applies_where_given); the page hides the field
    and does not send it."""
    return {"x-applies-to": when}


def applies_where_given(q: BaseModel) -> None:
    """Raise ParameterError (→ 422 naming the parameter) for a parameter given explicitly
    where its ``x-applies-to`` condition does not hold: silently ignoring it would let a
    script believe it had set the samples of a quadrature."""
    for name in q.model_fields_set:
        extra = type(q).model_fields[name].json_schema_extra
        when = extra.get("x-applies-to") if isinstance(extra, dict) else None
        for other, allowed in (when or {}).items():
            value = getattr(q, other)
            if value not in allowed:
                raise ParameterError(name, f"{name} applies to {other}={'|'.join(allowed)} only, "
                                       f"not {other}={value}")


def _split_commas(value):
    """Accept ``?x=1,2,3``, ``?x=1&x=2``, JSON lists and a JSON scalar (one value, as
    ``?x=1`` is) alike."""
    if isinstance(value, (str, int, float)) and not isinstance(value, bool):
        value = [value]
    if isinstance(value, (list, tuple)):
        out = []
        for item in value:
            if isinstance(item, str):
                parts = [p.strip() for p in item.split(",")]
                if any(p == "" for p in parts):
                    raise ValueError("empty list element (lists are comma-separated numbers)")
                out.extend(parts)
            else:
                out.append(item)
        return out
    return value


def float_list(lo: float, hi: float, description: str):
    item = Annotated[float, Field(ge=lo, le=hi, allow_inf_nan=False)]
    # minItems documents the "at least one value" rule the routes check (with a message
    # that says so), so a schema-driven client never builds an empty list.
    return Annotated[list[item], BeforeValidator(_split_commas),
                     Field(description=description, json_schema_extra={"minItems": 1})]


ThetaList = float_list(0.0, 90.0, "polar angles in degrees, [0, 90]; comma-separated")
PhiList = float_list(-360.0, 360.0, "azimuths in degrees, [-360, 360]; comma-separated")
MuList = float_list(0.0, 1.0, "cosines μ in [0, 1]; comma-separated")

# examples=: what /docs (OpenAPI) shows and pre-fills for every endpoint that takes them
Theta = Annotated[float, Field(ge=0.0, le=90.0, description="polar angle in degrees, [0, 90]",
                               examples=[60.0])]
Phi = Annotated[float, Field(ge=-360.0, le=360.0, description="azimuth in degrees, [-360, 360]",
                             examples=[0.0])]


ModelQuery = create_model("ModelQuery", __config__=STRICT, **query_fields())
ModelQuery.__doc__ = "The BRDF model: options and parameters, as every evaluating endpoint takes them."


def model_values(q: BaseModel) -> dict:
    """The model part of a query, only what the request set (make_spec fills defaults and
    must know whether alpha was given, to refuse two roughness forms at once)."""
    return {name: getattr(q, name) for name in ModelQuery.model_fields if name in q.model_fields_set}


def spec_of(q: BaseModel) -> ModelSpec:
    """The validated model of a query."""
    return make_spec(**model_values(q))


class EvalQuery(ModelQuery):
    theta_i_deg: ThetaList = [45.0]
    phi_i_deg: PhiList = [0.0]
    theta_o_deg: ThetaList = [45.0]
    phi_o_deg: PhiList = [180.0]
    quantities: Annotated[list[Literal["f", "f_diffuse", "f_rgb", "D", "G1_i", "G1_o", "G2", "F"]],
                          BeforeValidator(_split_commas),
                          Field(description="which quantities to return; default all but f_rgb "
                                            "(f_diffuse: the diffuse term of f; f_rgb: per channel, "
                                            "for a coloured model)")] = \
        ["f", "f_diffuse", "D", "G1_i", "G1_o", "G2", "F"]
    precision: Annotated[Literal["float64", "float32"], Field(
        description="float64 (the default: the reference path) or float32 (f only, GGX models: "
                    "a float32 compiled loop, faster; the answer states its measured relative "
                    "error bound against float64 for these pairs)")] = "float64"

    def check(self, loc: str = "query") -> None:
        """The rule the schema cannot state (before any work): precision=float32 only for
        f of a model that has a float32 loop. The fuzz test's oracle calls this too."""
        if self.precision == "float32":
            from ..quantities import check_float32
            check_float32(spec_of(self).brdf(), tuple(dict.fromkeys(self.quantities)), loc=loc)


class CurveQuery(ModelQuery):
    phi_deg: Phi = 0.0
    n: Annotated[int, Field(ge=2, description="number of angles, both ends included")] = 181


class NdfQuery(CurveQuery):
    cosine: Annotated[bool, Field(description="D·cos θ_m (the projected-area density, "
                                              "integrates to 1) instead of D")] = False


class NdfFigureQuery(NdfQuery):
    log: Annotated[bool, Field(description="draw the values on a log axis (decades) instead of a linear one")] = True


class LobeQuery(ModelQuery):
    theta_i_deg: Theta = 45.0
    phi_i_deg: Phi = 0.0
    n: Annotated[int, Field(ge=3, description="number of θ_o samples over [−90°, 90°]")] = 181
    cosine: Annotated[bool, Field(description="f·cos θ_o (the radiance leaving each way per "
                                              "unit irradiance) instead of f")] = False


class LobeFigureQuery(LobeQuery):
    log: Annotated[bool, Field(description="draw the values on a log axis (decades) instead of a linear one")] = False


class Lobe3dQuery(ModelQuery):
    theta_i_deg: Theta = 45.0
    phi_i_deg: Phi = 0.0
    n_theta: Annotated[int, Field(ge=2, description="rows θ_o = 0..90°, both ends included")] = 46
    n_phi: Annotated[int, Field(ge=3, description="columns φ_o over a full turn, both ends "
                                                  "included")] = 91


class Lobe3dFigureQuery(Lobe3dQuery):
    log: Annotated[bool, Field(description="draw the values on a log axis (decades) instead of a linear one")] = False


class AlbedoQuery(ModelQuery):
    n: Annotated[int, Field(ge=2, description="μ_k = k/(n−1), k = 0..n−1 (ignored when mu is given)")] = 17
    mu: Optional[MuList] = None
    phi_deg: Annotated[Phi, Field(description="azimuth of v (matters when anisotropic)")] = 0.0
    method: Annotated[Literal[METHODS], Field(
        description="quadrature: deterministic, E_error a bound; mc_uniform, mc_cosine, mc_ndf, "
                    "mc_vndf: Monte Carlo with `samples` per μ and `seed`, E_error one standard "
                    "error; table: the interpolated E(μ, α) table (isotropic, fresnel none or "
                    "schlick), E_error its measured bound; auto: the cheapest of table and "
                    "quadrature whose bound meets `tol` (the response names it)")] = "quadrature"
    tol: Annotated[float, Field(ge=1e-7, le=1e-2, description="target error of the quadrature "
                                "(and of E_avg); auto's tolerance")] = 1e-5
    order: Annotated[Optional[int], Field(
        ge=2, le=ORDER_MAX // 2, description=f"quadrature only: fixed Gauss order N (one "
        f"comparison N vs 2N, E_error from it) instead of refining to tol; [2, {ORDER_MAX // 2}]",
        json_schema_extra=applies_to(method=["quadrature"]))] = None
    samples: Annotated[int, Field(ge=2, le=MC_SAMPLES_MAX, description=f"Monte Carlo only: "
                                  f"directions per μ, [2, {MC_SAMPLES_MAX}]",
                                  json_schema_extra=applies_to(method=list(MC_METHODS)))] = DEFAULT_SAMPLES
    seed: Annotated[int, Field(ge=0, le=2 ** 63 - 1, description="Monte Carlo only: seed of the "
                               "random generator (same seed, same numbers)",
                               json_schema_extra=applies_to(method=list(MC_METHODS)))] = 0


class AlbedoFigureQuery(AlbedoQuery):
    y_range: Annotated[Literal["fit", "unit"], Field(
        description="vertical axis: fit (the data's own span, E ± error) or unit (0 to 1)")] = "fit"


class G2Query(ModelQuery):
    phi_deg: Annotated[Phi, Field(
        description="azimuth of v in degrees, [-360, 360], with l at azimuth 0 (along t, the "
                    "direction of α_x): the azimuth difference of l and v. 180 is the plane "
                    "of incidence with v on the mirror side")] = 180.0
    n: Annotated[int, Field(ge=2, description="angles per axis, θ = 0..90° both ends; n² points")] = 46


class FresnelQuery(ModelQuery):
    n: Annotated[int, Field(ge=2, description="number of angles θ = 0..90°, both ends included")] = 91


class SphereQuery(ModelQuery):
    theta_i_deg: Annotated[Theta, Field(description="angle between the light and the viewer, "
                                                    "degrees, [0, 90]")] = 45.0
    phi_i_deg: Annotated[Phi, Field(description="azimuth of the light in the image plane, "
                                                "from +x (right), degrees")] = 0.0
    n: Annotated[int, Field(ge=8, description="pixels across the sphere (n×n image)")] = 161


class SphereFigureQuery(SphereQuery):
    display: Annotated[Literal["heatmap", "log", "render"], Field(
        description="heatmap: L_o/E in false colour; log: log10 of it; render: grey levels "
                    "as a display shows them (sRGB, values above 1 clipped)")] = "heatmap"
    exposure: Annotated[float, Field(ge=-10.0, le=10.0,
                                     description="render only: multiply by 2^exposure")] = 0.0


class SliceQuery(ModelQuery):
    phi_h_deg: Annotated[Phi, Field(description="azimuth of h (matters when anisotropic)")] = 0.0
    phi_d_deg: Annotated[Phi, Field(description="azimuth of the difference vector about h; "
                                                "90 is the Disney explorer's default slice")] = 90.0
    n: Annotated[int, Field(ge=2, description="angles per axis, θ = 0..90° both ends; n² points")] = 91
    cosine: Annotated[bool, Field(description="f·cos θ_l instead of f")] = False


class SliceFigureQuery(SliceQuery):
    log: Annotated[bool, Field(description="colour by log10 f (decades) instead of f")] = True


class SamplesQuery(ModelQuery):
    sampler: Annotated[Literal["uniform", "cosine", "ndf", "vndf"], Field(
        description="uniform: hemisphere; cosine: cos θ/π (Malley); ndf: D(m)(n·m) reflected; "
                    "vndf: visible normals reflected (GGX, Beckmann)")] = "vndf"
    n: Annotated[int, Field(ge=2, description="number of sampled directions")] = 4096
    seed: Annotated[int, Field(ge=0, le=2 ** 63 - 1, description="seed of the random generator")] = 0
    theta_i_deg: Annotated[Theta, Field(description="polar angle of the fixed direction (v of the "
                                                    "sampler), degrees, [0, 90]")] = 45.0
    phi_i_deg: Annotated[Phi, Field(description="its azimuth, degrees")] = 0.0
