"""What a view is: its query, the arrays it computes for a model, the figure it draws.

A view is data, not routes: ``app/api`` turns each into a data route, a figure route
and exports; the CLI, the gallery and the exports call :func:`app.views.run` on it.
Each field of its query (besides the model's own) has a role, which the page uses to
group the controls: geometry | shape | resolution | method | display.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable, Mapping

from ..config import Settings
from ..errors import ParameterError
from ..model import ModelSpec
from . import schemas

ROLES = ("geometry", "shape", "resolution", "method", "display")
#: half: one cell of a two-column grid; wide: the whole width, two rows high (a surface,
#: a table); strip: the whole width, one row (a short table)
LAYOUTS = ("half", "wide", "strip")

#: The role of a field by its name, the same in every view; a view may override it.
ROLE_BY_NAME = {
    **dict.fromkeys(("theta_i_deg", "phi_i_deg", "theta_deg", "phi_deg", "phi_h_deg",
                     "phi_d_deg", "theta_max_deg"), "geometry"),
    **dict.fromkeys(("alpha_min", "alpha_max"), "shape"),
    **dict.fromkeys(("n", "n_theta", "n_phi", "mu"), "resolution"),
    **dict.fromkeys(("method", "tol", "order", "samples", "seed", "sampler", "methods",
                     "max_budget", "quantity", "albedo_methods", "ids", "metric"), "method"),
    **dict.fromkeys(("log", "cosine", "display", "exposure", "x", "y_range"), "display"),
}


def no_limits(q, settings: Settings) -> None:
    """A view whose query models bound every field already."""


def limit(name: str, value: int, most: int, env: str) -> None:
    """Refuse ``value`` above the setting ``env`` (422 naming ``name``)."""
    if value > most:
        raise ParameterError(name, f"{name}={value} exceeds the limit {most} (setting {env})")


@dataclass(frozen=True)
class View:
    """``summary``: one sentence shown under the plot; ``title``: its heading.
    ``query``: the data route's query model; ``figure_query``: the figure's (the same
    plus display fields). ``limits`` refuses a query before any work."""
    name: str
    title: str
    summary: str
    query: type
    figure_query: type
    compute: Callable[[ModelSpec, Any], dict]
    figure: Callable[[dict, ModelSpec, Any], dict]
    limits: Callable[[Any, Settings], None] = no_limits
    roles: Mapping[str, str] = field(default_factory=dict)
    #: an image costly enough that a client asks for it coarser while a slider moves
    heavy: bool = False
    #: its figure is curves, which pins and `vary` overlay (several models in one figure)
    overlayable: bool = False
    #: room it wants beside others: one of LAYOUTS
    layout: str = "half"
    #: why the view cannot take a measured material (``material=``), or "" where it does:
    #: declared here, refused by :meth:`check` with this reason (422 naming ``material``)
    refuses_material: str = ""

    def __post_init__(self):
        if self.layout not in LAYOUTS:
            raise ValueError(f"view {self.name}: layout {self.layout!r} is not one of {', '.join(LAYOUTS)}")

    def declared(self) -> dict:
        """What the view declares of itself for clients (GET /api/v1/views): heavy,
        overlayable (``vary`` and pins overlay its curves), layout, and material (it takes
        ``material=``; where not, ``material_refused`` says why)."""
        out = {"heavy": self.heavy, "overlayable": self.overlayable, "layout": self.layout,
               "material": not self.refuses_material}
        if self.refuses_material:
            out["material_refused"] = self.refuses_material
        return out

    def fields(self) -> list[str]:
        """The figure query's own fields (not the model's): geometry, resolution…"""
        return [n for n in self.figure_query.model_fields if n not in schemas.ModelQuery.model_fields]

    def role(self, name: str) -> str:
        return self.roles.get(name) or ROLE_BY_NAME[name]

    def check(self, q, settings: Settings) -> None:
        """Refuse the query before any work: a parameter given where it does not apply
        (schemas.applies_to), then the view's own limits."""
        schemas.applies_where_given(q)
        if self.refuses_material and schemas.model_values(q).get("material"):
            raise ParameterError("material", f"material: {self.refuses_material}")
        self.limits(q, settings)


def curve_limits(q, s: Settings) -> None:
    limit("n", q.n, s.max_curve_points, "BRDF_MAX_CURVE_POINTS")


def grid_limits(q, s: Settings) -> None:
    limit("n_theta×n_phi", q.n_theta * q.n_phi, s.max_grid_points, "BRDF_MAX_GRID_POINTS")


def square_grid_limits(q, s: Settings) -> None:
    if q.n * q.n > s.max_grid_points:
        raise ParameterError("n", f"n={q.n} gives n²={q.n * q.n} grid points, above the limit "
                                  f"{s.max_grid_points} (setting BRDF_MAX_GRID_POINTS)")
