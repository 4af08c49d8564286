"""The server's float64 references for the page's GPU views (static/js/gpu/):

* ``GET /api/v1/reference/sphere``: the lit sphere's radiance per unit irradiance
  L_o/E = f(l, v)·⟨n·l⟩ at the n×n pixel centres, for a light given as the exact vector the
  GPU used — the same frame as the GPU's, so that their difference is the GPU's arithmetic
  alone (the server's sphere view averages the highlight's pixels and takes the light as
  angles: a different frame). Raw little-endian float64, RGB per pixel, rows from the top,
  NaN off the disk: binary, as JSON cannot carry NaN and 256²·3 numbers as text cost ~4 MB.
* ``GET /api/v1/reference/slice``: f at the θ_h × θ_d pixel centres of the GPU's slice
  (90°·(k + ½)/n), from the very float32 directions the GPU reads (l and v formed in
  float64 by rusinkiewicz_directions, rounded to float32), rows θ_d from 0; NaN where l
  or v is below the horizon. Same binary form.
* ``POST /api/v1/environments/hdr``: a Radiance .hdr read (app/environment/hdr.py) and
  described — size, mean and peak radiance; a clear 4xx for anything that is not one —
  or, with ``format=f32``, its cells for the page's GPU environment sphere (averaged to
  at most ``map_width`` × ``map_width``/2 over solid angle; float32 RGB, rows from the top).
"""
from __future__ import annotations

from typing import Annotated, Literal

import numpy as np
from fastapi import APIRouter, Query, Request, Response
from pydantic import Field

from ... import kernels
from ...quantities import rusinkiewicz_directions
from ...environment.hdr import MAX_FILE_BYTES, equirect_cells, read_hdr
from ...errors import ParameterError, TooLarge
from ...integrate import cost
from ...materials import evaluate_rgb
from ...views import schemas
from ..deps import Route
from ..encode import json_response

router = APIRouter(prefix="/api/v1", tags=["data"], route_class=Route)

#: |l| may differ from 1 by this much: a float32 rounding of a unit vector is within
#: 3·2⁻²⁴ ≈ 1.8e-7 of it; anything further is not a direction the GPU drew with.
UNIT_TOLERANCE = 1e-6
#: The GPU's map: at most this many cells across (2048 × 1024 float32 RGBA: 32 MB of texture).
MAX_MAP_WIDTH = 2048
#: Bytes held per pixel while the frame is made: directions, frames, three channels.
BYTES_PER_PIXEL = 400


class ReferenceSphereQuery(schemas.ModelQuery):
    lx: Annotated[float, Field(ge=-1.0, le=1.0, description="light direction, x (image right), as the GPU used it")] = 0.0
    ly: Annotated[float, Field(ge=-1.0, le=1.0, description="light direction, y (image up)")] = 0.0
    lz: Annotated[float, Field(ge=-1.0, le=1.0, description="light direction, z (towards the viewer)")] = 1.0
    n: Annotated[int, Field(ge=8, le=512, description="pixels across the sphere (n×n image)")] = 256

    def check(self) -> None:
        """The cross-parameter rule the schema cannot state: (lx, ly, lz) is a unit vector."""
        length = float(np.linalg.norm([self.lx, self.ly, self.lz]))
        if abs(length - 1.0) > UNIT_TOLERANCE:
            raise ParameterError("lx", f"(lx, ly, lz) must be a unit vector to {UNIT_TOLERANCE:g}; "
                                       f"its length is {length:.9g}")


def pixel_centres(n: int) -> tuple[np.ndarray, np.ndarray]:
    """x, y (n×n, rows from the top) at pixel centres −1 + (2k + 1)/n, the sphere view's
    grid (environment.sphere.lit_sphere) and the GPU's (gl_FragCoord at k + ½)."""
    centres = -1.0 + (2.0 * np.arange(n) + 1.0) / n
    y, x = np.meshgrid(centres[::-1], centres, indexing="ij")
    return x, y


def local_directions(x: np.ndarray, y: np.ndarray, light: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """l and v in each point's local frame (t, b, n): n = (x, y, √(1−x²−y²)), t = +x
    projected onto the tangent plane, b = n × t; the viewer along +z (lit_sphere's frame)."""
    normal = np.stack([x, y, np.sqrt(np.maximum(1.0 - x * x - y * y, 0.0))], axis=-1)
    t = np.array([1.0, 0.0, 0.0]) - normal[:, :1] * normal
    t /= np.linalg.norm(t, axis=-1, keepdims=True)
    frame = np.stack([t, np.cross(normal, t), normal], axis=-2)
    return frame @ light, frame @ np.array([0.0, 0.0, 1.0])


def f_rgb(brdf, l: np.ndarray, v: np.ndarray) -> np.ndarray:
    """f per channel (…, 3): a model with its own colours (the principled BRDF: its drawn
    lobes' f_rgb), a material's per-channel Fresnel through evaluate_rgb, else the grey f
    thrice. (The principled BRDF has no f_rgb method of its own: the old test for one sent
    it to the grey path, its luminance in all three channels.)"""
    if getattr(brdf, "material", None) is not None:     # its own colours (the principled BRDF)
        return np.asarray(brdf.evaluate(l, v, ("f_rgb",))["f_rgb"], dtype=float)
    if getattr(brdf.fresnel, "channels", None) is not None:
        return evaluate_rgb(brdf, l, v, ("f",))["f_rgb"]
    return np.repeat(np.asarray(kernels.f(brdf, l, v), dtype=float)[:, None], 3, axis=1)


def sphere_frame(brdf, light: np.ndarray, n: int) -> np.ndarray:
    """L_o/E (n, n, 3) at the pixel centres, NaN off the disk, 0 where n·l ≤ 0."""
    x, y = pixel_centres(n)
    on = x * x + y * y < 1.0
    out = np.full((n, n, 3), np.nan)
    l, v = local_directions(x[on], y[on], light)
    mu_l = l[:, 2]
    lit = mu_l > 0.0
    values = np.zeros((int(on.sum()), 3))
    if lit.any():
        values[lit] = f_rgb(brdf, l[lit], v[lit]) * mu_l[lit, None]
    out[on] = values
    return out


@router.get("/reference/sphere", summary="The lit sphere in float64 at the GPU's exact frame (binary)",
            description="L_o/E = f·⟨n·l⟩ at the n×n pixel centres for the light vector (lx, ly, lz) "
                        "as given (unit to 1e-6), no supersampling: the truth the page's GPU sphere "
                        "is compared with. Little-endian float64, RGB per pixel, rows from the top "
                        "(y = 1), NaN off the disk.",
            responses={200: {"content": {"application/octet-stream": {}}}})
def reference_sphere(q: Annotated[ReferenceSphereQuery, Query()]) -> Response:
    q.check()
    light = np.array([q.lx, q.ly, q.lz], dtype=float)
    brdf = schemas.spec_of(q).brdf()
    cost.require_evaluations(brdf, q.n * q.n, q.n * q.n * BYTES_PER_PIXEL, "n", f"a {q.n}² sphere")
    frame = sphere_frame(brdf, light, q.n)
    return Response(frame.astype("<f8").tobytes(), media_type="application/octet-stream",
                    headers={"X-Frame-Shape": f"{q.n},{q.n},3", "Cache-Control": "no-store"})


class ReferenceSliceQuery(schemas.ModelQuery):
    phi_h_deg: Annotated[float, Field(ge=-180.0, le=180.0, description="azimuth of h")] = 0.0
    phi_d_deg: Annotated[float, Field(ge=-180.0, le=180.0, description="azimuth of d about h")] = 90.0
    n: Annotated[int, Field(ge=8, le=512, description="pixels per axis (n×n image)")] = 256


def slice_directions(n: int, phi_h_deg: float, phi_d_deg: float) -> tuple[np.ndarray, np.ndarray]:
    """l, v (n·n, 3) at the slice's pixel centres, rows θ_d = 90°·(j + ½)/n, columns
    θ_h likewise, rounded to float32 as the GPU's direction textures hold them."""
    centres = 90.0 * (np.arange(n) + 0.5) / n
    theta_d, theta_h = np.meshgrid(centres, centres, indexing="ij")
    l, v = rusinkiewicz_directions(theta_h.ravel(), phi_h_deg, theta_d.ravel(), phi_d_deg)
    return l.astype(np.float32).astype(float), v.astype(np.float32).astype(float)


@router.get("/reference/slice", summary="The θ_h × θ_d slice in float64 at the GPU's exact directions (binary)",
            description="f at the n×n pixel centres θ = 90°·(k + ½)/n (columns θ_h, rows θ_d from 0), "
                        "from l and v rounded to float32 as the page's GPU slice reads them: the truth the "
                        "GPU slice is compared with. Little-endian float64, RGB per pixel, NaN below the horizon.",
            responses={200: {"content": {"application/octet-stream": {}}}})
def reference_slice(q: Annotated[ReferenceSliceQuery, Query()]) -> Response:
    brdf = schemas.spec_of(q).brdf()
    cost.require_evaluations(brdf, q.n * q.n, q.n * q.n * BYTES_PER_PIXEL, "n", f"a {q.n}² slice")
    l, v = slice_directions(q.n, q.phi_h_deg, q.phi_d_deg)
    out = np.full((q.n * q.n, 3), np.nan)
    above = (l[:, 2] > 0.0) & (v[:, 2] > 0.0)
    if above.any():
        out[above] = f_rgb(brdf, l[above], v[above])
    return Response(out.astype("<f8").tobytes(), media_type="application/octet-stream",
                    headers={"X-Frame-Shape": f"{q.n},{q.n},3", "Cache-Control": "no-store"})


_HDR_BODY = {"requestBody": {"required": True, "content": {
    "application/octet-stream": {"schema": {"type": "string", "format": "binary"}},
    "image/vnd.radiance": {"schema": {"type": "string", "format": "binary"}}}}}
_HDR_ANSWER = {200: {"content": {"application/json": {"example": {
    "width": 512, "height": 256, "mean_rgb": [0.81, 0.77, 0.74], "max_rgb": [41.0, 38.5, 33.2]}}}}}


@router.post("/environments/hdr", openapi_extra=_HDR_BODY, responses=_HDR_ANSWER, summary="Read a Radiance .hdr environment (equirectangular) and describe it",
             description="The request body is the file's bytes. Answers its width, height, mean and "
                         "largest radiance per channel (format=f32: its cells, for the GPU); 422 naming what is wrong for a file that is not "
                         f"a readable .hdr, 413 over {MAX_FILE_BYTES} bytes or the pixel limits.")
async def upload_hdr(request: Request,
                     format: Annotated[Literal["json", "f32"], Query(
                         description="json: the description; f32: the map's cells, little-endian float32 RGB, "
                                     "rows from the top (θ = 0 at +y), shape in X-Map-Shape")] = "json",
                     map_width: Annotated[int, Query(ge=8, le=MAX_MAP_WIDTH, description=
                         "with format=f32: at most this many cells across (and half as many down)")] = 256,
                     ) -> Response:
    declared = request.headers.get("content-length")
    if declared is not None and declared.isdigit() and int(declared) > MAX_FILE_BYTES:
        raise TooLarge("file", f"{declared} bytes: at most {MAX_FILE_BYTES}", loc="body")
    data = bytearray()
    async for chunk in request.stream():
        data += chunk
        if len(data) > MAX_FILE_BYTES:
            raise TooLarge("file", f"more than {MAX_FILE_BYTES} bytes", loc="body")
    image = read_hdr(bytes(data))
    if format == "f32":
        cells = equirect_cells(image, map_width)
        return Response(cells.astype("<f4").tobytes(), media_type="application/octet-stream",
                        headers={"X-Map-Shape": f"{cells.shape[0]},{cells.shape[1]},3", "Cache-Control": "no-store"})
    return json_response({"width": int(image.shape[1]), "height": int(image.shape[0]),
                          "mean_rgb": [float(x) for x in image.reshape(-1, 3).mean(axis=0, dtype=np.float64)],
                          "max_rgb": [float(x) for x in image.reshape(-1, 3).max(axis=0)]})
