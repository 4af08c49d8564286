"""The importance-sampling view: directions drawn for a fixed v, with their pdf and the
χ² of the samples against it."""
from __future__ import annotations

from .. import figures, quantities
from ..config import Settings
from ..integrate.sampling import SAMPLERS
from ..model import make_spec
from . import schemas
from ..errors import ParameterError
from .views import View, _limit, register


def _check_samples(q, s: Settings):
    _limit("n", q.n, s.max_samples, "BRDF_MAX_SAMPLES")
    try:
        SAMPLERS[q.sampler].check(make_spec(**schemas.model_values(q)).brdf())
    except ValueError as exc:
        raise ParameterError("sampler", str(exc)) from None


register(View(
    "samples", "Directions l sampled for a fixed v, with pdf(l) and the weight f·cos θ_l/pdf; "
               "χ² of the samples against the pdf",
    schemas.SamplesQuery, schemas.SamplesQuery, _check_samples,
    lambda spec, q: quantities.samples(spec.brdf(), q.sampler, q.n, q.seed, q.theta_i_deg, q.phi_i_deg),
    lambda data, spec, q: figures.samples_figure(data, spec.values, q.theta_i_deg)))
