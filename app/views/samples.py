"""The importance-sampling view: directions drawn for a fixed v, with their pdf and the
χ² of the samples against it."""
from __future__ import annotations

from .. import quantities
from ..config import Settings
from ..figures.samples import samples_figure
from ..integrate.sampling import SAMPLERS
from . import schemas
from ..errors import ParameterError
from .view import View, limit


def _check_samples(q, s: Settings):
    limit("n", q.n, s.max_samples, "BRDF_MAX_SAMPLES")
    brdf = schemas.spec_of(q).brdf()         # a model error names its own parameter
    try:
        SAMPLERS[q.sampler].check(brdf)
    except ValueError as exc:
        raise ParameterError("sampler", str(exc)) from None


VIEW = View(
    "samples", "Importance samples",
    "Directions l sampled for a fixed v, with pdf(l) and the weight f·cos θ_l/pdf, and the "
    "χ² of the samples against the pdf.",
    schemas.SamplesQuery, schemas.SamplesQuery,
    lambda spec, q: quantities.samples(spec.brdf(), q.sampler, q.n, q.seed, q.theta_i_deg, q.phi_i_deg),
    lambda data, spec, q: samples_figure(data, spec.values, q.theta_i_deg),
    _check_samples,
    heavy=True)
