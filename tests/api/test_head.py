"""HEAD is answered wherever GET is (RFC 9110 9.3.2): the GET's status and headers, no
body (issue 34: ``HEAD /`` and ``HEAD /embed/lobe`` answered 405), and the guard judges
a HEAD's query as the GET's; the OpenAPI document lists no HEAD operations."""
from __future__ import annotations

import pytest

PATHS = ["/", "/embed/lobe", "/gallery", "/docs", "/favicon.ico", "/api/v1/health",
         "/api/v1/figures/ndf?alpha=0.2", "/api/v1/lobe?alpha=0.2", "/api/v1/views",
         "/api/v1/figures/ndf.csv?alpha=0.2", "/static/vendor/plotly.min.js",
         "/embed/nope", "/api/v1/figures/g1?alpha=7", "/api/v1/figures/ndf?alpha=0.2&alpha=0.3",
         "/api/v1/nope"]


@pytest.mark.parametrize("path", PATHS)
def test_head_answers_as_get_without_a_body(client, path):
    get, head = client.get(path), client.head(path)
    assert head.status_code == get.status_code != 405
    assert head.content == b""
    assert head.headers.get("content-type") == get.headers.get("content-type")


def test_the_document_lists_no_head_operations(client):
    paths = client.get("/openapi.json").json()["paths"]
    assert [p for p, item in paths.items() if "head" in item] == []
