"""The gallery's cards for the capabilities that are not one view's figure: an example
data set on a view, a fit to it, the model as shader code, a LUT, the roughness
conventions. Each builder turns an entry's state into the card's links, all GET links the
page and its reader may follow (every one answers 200) and, for the fit, the one POST the
page sends when the card scrolls into view; nothing here computes anything.

A card's fields besides the entry's own: ``open`` (the place in the product where the
capability lives, with its label), ``links`` (the raw API answers, each with its media
type) and what the page draws: ``figure`` (a Plotly figure's JSON, as a view's card),
``fit`` (the request, then the figure of the fitted model, whose query the page appends),
``excerpt`` (generated code, shown from its ``brdf`` function on) or ``image`` (a table
as a picture, with the JSON that states its error).
"""
from __future__ import annotations

from typing import Callable
from urllib.parse import urlencode

from ..datasets import examples
from ..views.schemas import ModelQuery

API = "/api/v1"
JSON, TEXT, CSV, PNG = "application/json", "text/plain", "text/csv", "image/png"


def _text(value) -> str:
    return ("true" if value else "false") if isinstance(value, bool) else str(value)


def query(params: dict) -> str:
    """A state as a URL's query: booleans as the API spells them (true/false)."""
    return urlencode({k: _text(v) for k, v in params.items()})


def _model(state: dict) -> dict:
    """The model's parameters of a state (what GET /api/v1/code, /lut, /fit take)."""
    return {k: v for k, v in state.items() if k in ModelQuery.model_fields}


def _link(label: str, href: str, media: str) -> dict:
    return {"label": label, "href": href, "type": media}


def _explorer_with_data(data_id: str, view: str, params: dict) -> str:
    """The explorer in this state with the data set open (data.js reads ``data`` once)."""
    return "/?" + query({**params, "show": view, "data": data_id})


def dataset(state: dict) -> dict:
    """An example data set drawn on a view with the model, and its summary."""
    data_id = examples.example_id(state["data"])
    view, params = state["view"], {k: v for k, v in state.items() if k not in ("data", "view")}
    example = examples.EXAMPLES[state["data"]]
    return {
        "figure": f"{API}/datasets/{data_id}/figures/{view}?{query(params)}",
        "open": {"href": _explorer_with_data(data_id, view, params), "label": "Open in the explorer with the data →"},
        "links": [_link("data set summary (JSON)", f"{API}/datasets/{data_id}", JSON),
                  _link("data on the view (JSON)", f"{API}/datasets/{data_id}/{view}?{query(params)}", JSON),
                  _link("model − data (JSON)", f"{API}/datasets/{data_id}/difference?{query(_model(params))}", JSON),
                  _link("the model.csv export it was written by (CSV)", f"{API}/export/model.csv?{query({**example.model, **example.grid})}", CSV)],
    }


def fit(state: dict) -> dict:
    """A least-squares fit to an example data set, then the fitted model on a view."""
    data_id = examples.example_id(state["data"])
    view = state["view"]
    rest = {k: v for k, v in state.items() if k not in ("data", "view", "free", "measure")}
    model, shown = _model(rest), {k: v for k, v in rest.items() if k not in ModelQuery.model_fields}
    return {
        "fit": {"url": f"{API}/fit", "body": {"data": data_id, "model": model, "free": state["free"].split(","),
                                              "measure": state["measure"]},
                "figure": f"{API}/datasets/{data_id}/figures/{view}?{query(shown)}"},
        "open": {"href": _explorer_with_data(data_id, view, rest), "label": "Open in the explorer, then Fit →"},
        "links": [_link("data set summary (JSON)", f"{API}/datasets/{data_id}", JSON),
                  _link("POST /api/v1/fit (API docs)", "/docs#/datasets/fit_api_v1_fit_post", "text/html")],
    }


def code(state: dict) -> dict:
    """The model as GLSL (the excerpt), HLSL and Python, and the JSON that describes it."""
    model = _model(state)

    def url(**extra) -> str:
        return f"{API}/code?{query({**model, **extra})}"
    return {
        "excerpt": {"href": url(lang=state["lang"]), "lang": state["lang"]},
        "open": {"href": f"/tools?{query(model)}#code", "label": "Open in the shader tools →"},
        "links": [_link("GLSL", url(lang="glsl"), TEXT), _link("HLSL", url(lang="hlsl"), TEXT),
                  _link("Python", url(lang="python"), TEXT),
                  _link("uniforms and errors (JSON)", url(lang=state["lang"], format="json"), JSON)],
    }


def lut(state: dict) -> dict:
    """A lookup table as its PNG, and the JSON that states its error."""
    def url(**extra) -> str:
        return f"{API}/lut?{query({**state, **extra})}"
    return {
        "image": {"src": url(format="png"), "summary": url(per_texel=False)},
        "open": {"href": "/tools#lut", "label": "Open in the LUT workbench →"},
        "links": [_link("values and error (JSON)", url(per_texel=False), JSON), _link("PNG", url(format="png"), PNG),
                  _link("CSV", url(format="csv"), CSV), _link("C header", url(format="c"), "text/x-c")],
    }


def conventions(state: dict) -> dict:
    """Each ecosystem's α for one roughness value, and the albedo error of mixing two."""
    r = state["roughness"]
    return {
        "figure": f"{API}/conventions/figure?{query(state)}",
        "open": {"href": "/tools#conventions", "label": "Open in the shader tools →"},
        "links": [_link("α per ecosystem (JSON)", f"{API}/conventions?{query(state)}", JSON),
                  _link("D at α = r², G at α = r (JSON)",
                        f"{API}/conventions/check?{query({'alpha': r * r, 'alpha_G': r})}", JSON)],
    }


#: the capabilities a card shows besides one view's figure, by the entry's ``kind``
BUILDERS: dict[str, Callable[[dict], dict]] = {
    "dataset": dataset, "fit": fit, "code": code, "lut": lut, "conventions": conventions}
