"""The fast query-model path (app/api/http/query_route.py) against FastAPI's own: the
same query strings give the same model or the same errors through both."""
from __future__ import annotations

from typing import Annotated

import pytest
from fastapi import FastAPI, Query, Request
from fastapi.responses import JSONResponse, Response
from fastapi.routing import APIRoute
from fastapi.testclient import TestClient

from app.api.deps import takes_the_fast_path
from app.api.http.query_route import QueryModelRoute
from app.api.routes import figures as figure_routes, views as view_routes
from app.views import schemas


def _app(route_class) -> FastAPI:
    app = FastAPI()

    def albedo(request: Request, q: Annotated[schemas.AlbedoFigureQuery, Query()]) -> Response:
        return JSONResponse(q.model_dump(mode="json"))

    app.router.add_api_route("/albedo", albedo, methods=["GET"], route_class_override=route_class)
    return app


QUERIES = [
    "", "alpha=0.3", "alpha=0.3&ndf=beckmann&fresnel=conductor", "mu=0.1&mu=0.5&mu=0.9",
    "mu=0.1", "alpha=0.3&alpha=0.4",                    # a scalar given twice: the last
    "alpha=abc", "alpha=-1", "alpha=2", "method=nope", "unknown=1", "unknown=1&unknown=2",
    "mu=", "mu=2", "n=1", "tol=1e-9", "alpha=", "theta_i_deg=95", "alpha=0.3&samples=8",
]


@pytest.mark.parametrize("query", QUERIES)
def test_the_same_model_or_the_same_errors_as_fastapi(query):
    ours = TestClient(_app(QueryModelRoute)).get(f"/albedo?{query}")
    theirs = TestClient(_app(APIRoute)).get(f"/albedo?{query}")
    assert ours.status_code == theirs.status_code, (ours.text, theirs.text)
    if ours.status_code == 200:
        assert ours.json() == theirs.json()
    else:
        strip = lambda errs: [{k: e[k] for k in ("loc", "type", "input") if k in e} for e in errs]  # noqa: E731
        assert strip(ours.json()["detail"]) == strip(theirs.json()["detail"])


def test_every_figure_and_data_route_takes_the_fast_path():
    figures = [r for r in figure_routes.router.routes if "GET" in r.methods and "{" not in r.path
               and not r.path.endswith((".svg", ".png"))]      # images take the renderer too
    data = [r for r in view_routes.router.routes if r.path in ("/api/v1/lobe", "/api/v1/albedo")
            and "GET" in r.methods]                                    # not their HEAD twins
    assert len(data) == 2 and len(figures) > 20
    assert [r.path for r in figures + data if not takes_the_fast_path(r)] == []
