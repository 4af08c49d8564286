"""The identities a microfacet model must satisfy, computed numerically for one model and
one view direction v, each next to the value it must have, with its error and cost.

Rows (``ROW_IDS``; a request may ask for a subset), docs/identities.md §1–§4:

* ``1``  ∫_{H²} D(m)(n·m) dm = 1                         (Heitz 2014, eq. 4)
* ``2``  ∫_{S²} D(m)(v·m) dm = n·v, signed                (Heitz 2014, eq. 5)
* ``3``  ∫ G1(v,m) D(m)(v·m)⁺ dm = n·v                    (Heitz 2014, eq. 43: Smith's G1)
* ``4``  ∫_{S²} D(h) G1(v)/(4|n·v|) dl = 1                (weak white furnace, Heitz 2014 sec. 5)
* ``7``  E(μ) ≤ 1, single scattering, F = 1               (Kulla & Conty 2017)
* ``7-loss``     1 − E_sep(μ) ≥ 1 − E_hc(μ): the separable G2 loses more energy
* ``7-furnace``  E(μ) = 1 with F = 1 and Kulla-Conty compensation (Kulla & Conty 2017)

Rows 1–4 integrate over m (app/integrate/slope_quadrature.py), rows 7 take the albedo
quadrature of the model with fresnel=none, kd=0."""
from __future__ import annotations

import time
from dataclasses import asdict, dataclass

import numpy as np

from ..errors import ParameterError
from ..integrate import budget
from ..integrate import slope_quadrature as sq
from ..integrate.methods import albedo_by
from ..model import ModelSpec
from ..physics.brdf import BRDF
from ..physics.masking import G1
from ..physics.vectors import direction_deg, half_vector

ROW_IDS = ("1", "2", "3", "4", "7", "7-loss", "7-furnace")

#: Row 4 evaluates D at h = (l+v)/‖l+v‖: l + v cancels, so h's components carry absolute
#: rounding ~ε = 2.2e-16 where the peak of D has width α, and D's relative error per term
#: is up to ~2 r̃ ε/α (r̃ ≲ 5 where the mass is): this many ε/α_min is added to its floor
#: (seen: 1.5e-12 for Beckmann α = 1e-4 at θ = 89.9°, against a floor of 7e-13).
H_ROUNDING_EPS = 10.0
#: Row 4 leaves out nodes with (v·m) m_z below this: there h = (l+v)/‖l+v‖ has lost
#: more than 1e-7 of its relative accuracy in h_z (l + v cancels to ~4e-16 absolute).
H_MIN = 1e-8
#: The part row 4 leaves out is bounded by this many times its weight at the rule's own
#: nodes there: beyond the last node (r̃ ~ 1e58) a tail falling like r̃^{−0.04} (Student-t,
#: γ = 1.52) still holds as much again (seen: 2 % above 1×). Below γ ~ 1.7 row 4 is
#: then inconclusive: its error is of the order of its value.
DROPPED_SAFETY = 2.0
#: A row holds when |value − expected| ≤ error + HOLD_TOLERANCE (one-sided for ≤ / ≥).
#: Above every exact computation here: the tabulated Smith Λ (GTR, exponential power) is
#: within 1e-8 in G1 (physics/smith_table.py; measured 4e-9 in row 3 at α = 1); far below
#: every approximation the rows are meant to expose (Walter's Λ: ~1e-4 and more where it
#: differs from Beckmann's at all, Schlick-GGX ~1e-2).
HOLD_TOLERANCE = 1e-7
#: Quadrature tolerance of the albedo rows. 1e-7 (the API's smallest) took exponential
#: power at α = 1:1e-4, θ = 89.9° to 0.45 s a call (bench/checks.py), 1e-6 to 0.2 s; what
#: these rows compare is 1e-3 to 1e-1 apart (energy lost, separable against
#: height-correlated) or within the Kulla-Conty table's error (~2e-5). The reported error
#: is the quadrature's, whatever it reached (1.3e-6 at its highest order for α = 1e-4:1).
ALBEDO_TOL = 1e-6
#: Seconds each albedo of the rows 7 may refine for (a time budget of its own, inside the
#: request's): the quadrature stops before a level that would not fit, with its honest,
#: larger error and a note. Most models need a few ms; an anisotropic model with
#: masking=smith_numeric (a 192-node integral per μΛ) took 7–11 s per albedo to reach
#: tol. With at most three albedos (rows 7, 7-loss), a call stays under ~0.5 s.
ALBEDO_SECONDS = 0.15


@dataclass
class Row:
    id: str
    identity: str
    relation: str          # "=", "≤" or "≥": how value compares with expected
    value: float | None
    expected: float
    error: float | None    # estimated numerical error of value
    difference: float | None
    holds: bool | None     # None: the row does not apply to this model (see note)
    note: str
    evaluations: int
    seconds: float


IDENTITIES = {
    "1": ("∫ D(m)(n·m) dm = 1", "="),
    "2": ("∫_S² D(m)(v·m) dm = n·v", "="),
    "3": ("∫ G1(v,m) D(m)(v·m)⁺ dm = n·v", "="),
    "4": ("∫_S² D(h) G1(v)/(4|n·v|) dl = 1", "="),
    "7": ("E(μ) ≤ 1  (F = 1, single scattering)", "≤"),
    "7-loss": ("1 − E_sep(μ) ≥ 1 − E_hc(μ)  (F = 1)", "≥"),
    "7-furnace": ("E(μ) = 1  (F = 1, Kulla-Conty)", "="),
}


def holds(relation: str, difference: float, error: float) -> bool | None:
    """Whether the row holds; None where the quadrature did not converge (error inf):
    the check is then inconclusive, not passed."""
    if not np.isfinite(error):
        return None
    slack = error + HOLD_TOLERANCE
    if relation == "≤":
        return bool(difference <= slack)
    if relation == "≥":
        return bool(difference >= -slack)
    return bool(abs(difference) <= slack)


# --------------------------------------------------------------------- the rows

def _view(theta_deg: float, phi_deg: float) -> np.ndarray:
    return direction_deg(theta_deg, phi_deg)


def _masking_kind(brdf: BRDF) -> str:
    """'exact' where G1 is the NDF's own Smith G1, else 'approximate'."""
    return "exact" if brdf.masking.exact(brdf.ndf) is brdf.masking else "approximate"


def _masking_note(brdf: BRDF) -> str:
    """Whether Smith's identities (3, 4) can hold with this masking, first clause first
    (the figure shows it under a row that fails)."""
    name = brdf.masking.name
    if _masking_kind(brdf) == "exact":
        return (f"masking={name} is Smith's exact Λ: G1(v) = n·v / ∫ D(m)(v·m)⁺ dm "
                f"(Heitz 2014, eq. 43)")
    if brdf.masking.approximates is None:     # the NDF's closed-form Λ is the approximate one
        return (f"ndf={brdf.ndf.name}'s Λ is approximate (Walter's Beckmann substitution); "
                "Smith's identity holds only for the NDF's own Λ "
                f"(masking={brdf.masking.exact(brdf.ndf).name})")
    return (f"masking={name} approximates Smith's Λ; the identity holds only for the NDF's "
            "own Λ, so the difference is the approximation's error")


def _lobe_note(brdf: BRDF) -> str:
    return (f"; for the first lobe's D (α = {brdf.ndf.alpha_x:g}), the second obeys it alike"
            if brdf.lobe2 is not None and brdf.lobe_mix > 0 else "")


def _quadrature_row(rid: str, brdf: BRDF, v: np.ndarray, expected: float, note: str) -> Row:
    ndf = brdf.ndf
    ax, ay = ndf.alpha_x, ndf.alpha_y
    t0 = time.perf_counter()
    mu_v = float(v[2])
    g1 = 1.0
    if rid in ("3", "4"):
        g1 = float(G1(v[2], brdf.masking.mu_Lambda(ndf, v)))

    k = sq.tail_k(ndf)

    def level(n):
        rule = sq.rule(ax, ay, v, n, visible=rid in ("3", "4"), k=k)
        dropped = 0.0
        if rid == "1":
            terms = ndf.D(rule.m) * rule.m[:, 2] * rule.dm
        elif rid == "2":
            terms = ndf.D(rule.m) * (rule.m @ v) * rule.dm
        elif rid == "3":
            terms = ndf.D(rule.m) * np.maximum(rule.m @ v, 0.0) * rule.dm
        else:
            l, area = sq.l_area(ax, ay, v, rule)
            h, exists = half_vector(l, v)
            # l + v = 2(v·m) m is formed by cancellation: h_z keeps ~4e-16/(2(v·m) m_z)
            # relative accuracy, none where (v·m) m_z ≲ 1e-16 (the far tail, reached by
            # the tail map: m_z down to 1e-70). Nodes below H_MIN are left out and their
            # share bounded by what they weigh in row 3's sum (×4: dl = 4(v·m) dm there).
            vm = np.maximum(rule.m @ v, 0.0)
            keep = exists & (vm * rule.m[:, 2] > H_MIN)
            D = np.zeros(rule.size)
            D[keep] = ndf.D(h[keep])
            terms = D * area * rule.weight
            dropped = DROPPED_SAFETY * 4.0 * float(np.sum(np.where(keep, 0.0, ndf.D(rule.m) * vm * rule.dm)))
        return float(np.sum(terms)), float(np.sum(np.abs(terms))), rule.size, dropped

    floor = sq.ROUNDING_FLOOR
    if rid == "4":
        floor += H_ROUNDING_EPS * np.finfo(float).eps / min(ax, ay)
    res = sq.refine(level, floor, "checks")
    scale = {"1": 1.0, "2": 1.0, "3": g1, "4": g1 / (4.0 * mu_v) if mu_v > 0 else 0.0}[rid]
    value, error = scale * res.value, abs(scale) * res.error
    identity, relation = IDENTITIES[rid]
    diff = value - expected
    note = f"{note}; Gauss order {res.order} vs {res.order // 2}" + _lobe_note(brdf)
    if res.note:
        note += f"; {res.note}"
    return Row(rid, identity, relation, value, expected, error, diff, holds(relation, diff, error),
               note, res.evaluations, time.perf_counter() - t0)


# ------------------------------------------------------------- the albedo rows

class _Albedos:
    """E(μ) of variants of the model with F = 1, kd = 0, each computed at most once."""

    def __init__(self, spec: ModelSpec, mu: float, phi: float):
        self.spec, self.mu, self.phi = spec, mu, phi
        self.done: dict[tuple, dict] = {}

    def get(self, **overrides) -> tuple[dict, int]:
        """(albedo_by's result, its evaluations if computed now, else 0: a row that
        reuses another row's albedo does not count its cost twice)."""
        key = tuple(sorted(overrides.items()))
        if key in self.done:
            return self.done[key], 0
        spec = self.spec.with_(fresnel="none", kd=0.0, **overrides)
        outer = budget.current()
        seconds = ALBEDO_SECONDS
        if outer is not None:
            seconds = max(0.0, min(seconds, outer.seconds - outer.elapsed()))
        with budget.limit(seconds) as own:
            res = albedo_by(spec.brdf(), [self.mu], self.phi, method="quadrature",
                            tol=ALBEDO_TOL, average=False)
        if own.notes:
            res = dict(res, cut=(f"albedo stopped before reaching tol {ALBEDO_TOL:g}: this view "
                                 f"gives each albedo {seconds:.2g} s (ALBEDO_SECONDS in "
                                 "app/checks.py, or what the request's budget had left)"))
            if outer is not None and seconds < ALBEDO_SECONDS:
                outer.cut(f"checks: {res['cut']}")
        self.done[key] = res
        return res, int(res["evaluations"])


def _albedo_row(rid: str, brdf: BRDF, spec: ModelSpec, albedos: _Albedos) -> Row:
    t0 = time.perf_counter()
    identity, relation = IDENTITIES[rid]
    g2 = spec.values["g2"]
    if rid == "7":
        r, evaluations = albedos.get(multiscatter="none", g2=g2)
        value, error, expected = float(r["E"][0]), float(r["E_error"][0]), 1.0
        note = (f"g2={g2}, masking={spec.values['masking']}, fresnel=none, kd=0, no compensation: "
                f"the single-scattering albedo loses {1.0 - value:.3g} of the energy")
        if value > 1.0 + error + HOLD_TOLERANCE:
            note = f"E > 1: this model creates energy; {_masking_note(brdf)}; " + note
        if "cut" in r:
            note += f"; {r['cut']}"
    elif rid == "7-loss":
        sep, ev_sep = albedos.get(multiscatter="none", g2="separable")
        hc, ev_hc = albedos.get(multiscatter="none", g2="height_correlated")
        value, expected = 1.0 - float(sep["E"][0]), 1.0 - float(hc["E"][0])
        error = float(sep["E_error"][0] + hc["E_error"][0])
        evaluations = ev_sep + ev_hc
        note = (f"value: energy lost with the separable G2, expected: with the height-correlated "
                f"one (masking={spec.values['masking']}); G1(l)G1(v) ≤ 1/(1 + Λ(l) + Λ(v)) "
                "(identity 6): the separable form shadows more")
        if ev_hc == 0 or ev_sep == 0:
            note += "; one of the two albedos is row 7's, computed once (its cost counted there)"
        for cut in {x["cut"] for x in (sep, hc) if "cut" in x}:
            note += f"; {cut}"
    else:
        return _furnace_row(brdf, spec, albedos, t0)
    diff = value - expected
    return Row(rid, identity, relation, value, expected, error, diff, holds(relation, diff, error),
               note, int(evaluations), time.perf_counter() - t0)


def furnace_refusal(brdf: BRDF, spec: ModelSpec) -> str | None:
    """Why the compensated furnace does not apply to this model, or None."""
    if not brdf.ndf.isotropic:
        return ("does not apply to anisotropic roughness; Kulla-Conty compensation is for "
                "isotropic roughness only (its E(μ, α) table is isotropic)")
    if _masking_kind(brdf) != "exact":
        return ("does not apply with an approximate Λ; compensation needs the exact Smith Λ "
                f"(its table and the albedo it compensates): {_masking_note(brdf)}")
    if spec.values.get("multiscatter") != "kulla_conty":
        return ("not computed: set multiscatter=kulla_conty to run it; the model's E(μ, α) "
                "table, which takes 1–25 s to build (GGX 0.9 s, direction-correlated G2 "
                "25 s), is built then, as for every view of that model, and this row costs "
                "a millisecond")
    return None


def _furnace_row(brdf: BRDF, spec: ModelSpec, albedos: _Albedos, t0: float) -> Row:
    identity, relation = IDENTITIES["7-furnace"]
    why = furnace_refusal(brdf, spec)
    if why is not None:
        return Row("7-furnace", identity, relation, None, 1.0, None, None, None, why, 0,
                   time.perf_counter() - t0)
    try:
        r, evaluations = albedos.get(multiscatter="kulla_conty")
    except ParameterError as exc:      # a combination make_spec refuses: say why
        return Row("7-furnace", identity, relation, None, 1.0, None, None, None,
                   f"does not apply; {exc.message}", 0, time.perf_counter() - t0)
    value = float(r["E"][0])
    error = float(r["E_single_error"][0]) + float(r["compensation_error"])
    diff = value - 1.0
    note = (f"E = E_single {float(r['E_single'][0]):.6f} + E_ms {value - float(r['E_single'][0]):.6f}; "
            f"error = quadrature + the E(μ, α) table's measured error "
            f"{float(r['compensation_error']):.1e}")
    if "cut" in r:
        note += f"; {r['cut']}"
    return Row("7-furnace", identity, relation, value, 1.0, error, diff, holds(relation, diff, error),
               note, evaluations, time.perf_counter() - t0)


# ------------------------------------------------------------------------ entry

def check_rows(spec: ModelSpec, theta_deg: float = 60.0, phi_deg: float = 0.0,
               ids=None) -> list[Row]:
    """The rows ``ids`` (default all, in ROW_IDS order) for the model and the view
    direction v at (θ, φ) in degrees, θ ∈ [0, 90)."""
    wanted = [r for r in ROW_IDS if ids is None or r in set(ids)]
    brdf = spec.brdf()
    brdf = brdf.single() if hasattr(brdf, "single") else brdf
    v = _view(theta_deg, phi_deg)
    mu = float(v[2])
    albedos = _Albedos(spec, mu, float(np.deg2rad(phi_deg)))
    notes = {
        "1": "D is normalised (docs/conventions.md §2)",
        "2": "signed projected area: the facets facing away from v count negatively",
        "3": _masking_note(brdf),
        "4": "weak white furnace, over l with l's own area element",
    }
    if _masking_kind(brdf) != "exact":     # the reason these rows fail comes first
        notes["4"] = f"{_masking_note(brdf)}; {notes['4']}"
    expected = {"1": 1.0, "2": mu, "3": mu, "4": 1.0}
    rows = []
    for rid in wanted:
        if rid in expected:
            rows.append(_quadrature_row(rid, brdf, v, expected[rid], notes[rid]))
        else:
            rows.append(_albedo_row(rid, brdf, spec, albedos))
    return rows


def checks(spec: ModelSpec, theta_deg: float = 60.0, phi_deg: float = 0.0, ids=None) -> dict:
    """The rows as columns (one list per field, equal lengths: what the CSV export
    writes; each row's seconds in ``seconds_by_row``) plus the view direction, the
    tolerance and the totals."""
    t0 = time.perf_counter()
    rows = check_rows(spec, theta_deg, phi_deg, ids)
    # One list per field, the seconds apart (keyed by row): the lists are the table's
    # columns, which the CSV export writes (the numeric ones) and its test compares with
    # the JSON of another request, and a time is not the same twice.
    columns = {f: [asdict(r)[f] for r in rows] for f in Row.__dataclass_fields__ if f != "seconds"}
    b = budget.current()
    # row_order: the ids as one line of text, so that a CSV export (which writes the
    # numeric lists only) still says which row is which.
    out = {**columns, "row_order": ", ".join(r.id for r in rows),
           "theta_deg": float(theta_deg), "phi_deg": float(phi_deg),
           "mu": float(_view(theta_deg, phi_deg)[2]), "hold_tolerance": HOLD_TOLERANCE,
           "seconds_by_row": {r.id: r.seconds for r in rows},
           "total_evaluations": int(sum(r.evaluations for r in rows)),
           "total_seconds": time.perf_counter() - t0,
           "complete": not (b and b.notes)}
    if not out["complete"]:
        out["budget_note"] = "; ".join(b.notes) + " (setting BRDF_MAX_SECONDS)"
    return out
