"""POST/GET/DELETE /api/v1/datasets and the model exports: ids, summaries, and a 4xx
naming what is wrong for every bad upload."""
import asyncio
from concurrent.futures import ThreadPoolExecutor
import io
import os
import zipfile

import numpy as np
import pytest
from fastapi.testclient import TestClient

from app.datasets import merl
from app.datasets.store import DatasetStore
from app.main import create_app

from . import known

from .conftest import CSV, SETTINGS


def detail(response):
    return response.json()["detail"][0]


def test_upload_raw_or_multipart_get_and_delete(client):
    raw = client.post("/api/v1/datasets", content=CSV, headers={"content-type": "text/csv"})
    assert raw.status_code == 201
    body = raw.json()
    assert body["format"] == "samples_csv" and len(body["id"]) == 32
    assert body["summary"]["count"] == 2 and body["summary"]["range"]["f"] == [0.25, 1.5]
    form = client.post("/api/v1/datasets", files={"file": ("../../etc/evil.csv", CSV, "text/csv")})
    assert form.status_code == 201 and form.json()["id"] == body["id"]    # a content hash
    assert "evil" not in form.text and not os.path.exists("../../etc/evil.csv")
    again = client.get(f"/api/v1/datasets/{body['id']}")
    assert again.status_code == 200 and again.json()["summary"] == body["summary"]
    assert client.delete(f"/api/v1/datasets/{body['id']}").status_code == 403
    assert client.delete(f"/api/v1/datasets/{body['id']}", params={"token": body["token"]}).status_code == 204
    gone = client.get(f"/api/v1/datasets/{body['id']}")
    assert gone.status_code == 410 and "expired (deleted)" in detail(gone)["msg"]
    unknown = client.get("/api/v1/datasets/" + "0" * 32)
    assert unknown.status_code == 404 and detail(unknown)["loc"] == ["path", "data_id"]
    assert client.get("/api/v1/datasets/not-an-id").status_code == 422


def test_merl_upload_and_insisted_format(client):
    content = known.merl_bytes()
    response = client.post("/api/v1/datasets", content=content,
                           headers={"content-type": "application/octet-stream"})
    assert response.status_code == 201
    info = response.json()["summary"]
    assert response.json()["format"] == "merl" and info["bytes"] == merl.FILE_BYTES
    assert 0.7 < info["fraction_measured"] < 0.8
    wrong = client.post("/api/v1/datasets?format=samples_csv", content=content)
    assert wrong.status_code == 422 and "not text" in detail(wrong)["msg"]
    bad = client.post("/api/v1/datasets?format=xml", content=CSV)
    assert bad.status_code == 422 and detail(bad)["loc"][-1] == "format"


def _zip_bomb() -> bytes:
    """~80 KB of zip that would expand to 64 MB of a valid-looking CSV."""
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("data.csv", CSV[:CSV.index(b"\n") + 1] + b"0,0,0,0,0\n" * 6_400_000)
    return out.getvalue()


@pytest.mark.parametrize("content, says", [
    (b"", "the file is empty"),
    (np.array([90, 90, 180], "<i4").tobytes() + b"\0" * 4000, "truncated"),
    (np.array([90, 90, 90], "<i4").tobytes() + b"\0" * 4000, "the header says 90 × 90 × 90"),
    (CSV.replace(b"phi_o_deg", b"phi_o"), "unknown column 'phi_o' (did you mean 'phi_o_deg'?)"),
    (CSV.replace(b",phi_o_deg", b"").replace(b",180,", b",").replace(b",90,", b","),
     "phi_o_deg is missing"),
    (CSV.replace(b"1.5", b"NaN"), "f must be a finite number; data row 1 has nan"),
    (CSV.replace(b"1.5", b"inf"), "data row 1 has inf"),
    (CSV.replace(b"0.25", b"-0.25"), "f must be ≥ 0"),
    (b"theta_deg,D\n10,-1\n", "D must be ≥ 0"),
    (None, "zip archive"),
])
def test_every_bad_upload_gets_a_422_naming_it(client, content, says):
    content = _zip_bomb() if content is None else content
    response = client.post("/api/v1/datasets", content=content, headers={"content-type": "text/csv"})
    assert response.status_code == 422, response.text
    assert says in detail(response)["msg"] and detail(response)["loc"] == ["body", "file"]


def test_compressed_transfer_is_refused(client):
    response = client.post("/api/v1/datasets", content=b"\x1f\x8b\x08\x00",
                           headers={"content-encoding": "gzip", "content-type": "text/csv"})
    assert response.status_code == 415 and "uncompressed" in detail(response)["msg"]


def _asgi_post(app, headers, chunk=b"0" * (1 << 20)):
    """POST /api/v1/datasets straight to the ASGI app with a body that never ends;
    (status, body, bytes the app pulled)."""
    pulled, sent = [0], []

    async def receive():
        pulled[0] += len(chunk)
        return {"type": "http.request", "body": chunk, "more_body": True}

    async def send(message):
        sent.append(message)

    scope = {"type": "http", "method": "POST", "path": "/api/v1/datasets", "raw_path": b"/api/v1/datasets",
             "query_string": b"", "headers": headers, "http_version": "1.1", "scheme": "http",
             "server": ("127.0.0.1", 80), "client": ("127.0.0.1", 1234), "root_path": ""}
    # in a thread of its own: the browser tests (pytest-playwright's sync API) leave an
    # event loop running in the main thread, where asyncio.run() refuses to start
    with ThreadPoolExecutor(max_workers=1) as pool:
        pool.submit(asyncio.run, app(scope, receive, send)).result()
    status = next(m["status"] for m in sent if m["type"] == "http.response.start")
    body = b"".join(m.get("body", b"") for m in sent if m["type"] == "http.response.body")
    return status, body, pulled[0]


def test_a_2_gb_upload_is_refused_before_it_is_read(app):
    status, body, pulled = _asgi_post(app, [(b"content-length", b"2147483648"),
                                            (b"content-type", b"application/octet-stream")])
    assert status == 413 and pulled == 0
    assert b"BRDF_MAX_" in body and b"2147483648" in body


def test_a_chunked_upload_stops_at_the_limit(app):
    status, body, pulled = _asgi_post(app, [(b"content-type", b"application/octet-stream"),
                                            (b"transfer-encoding", b"chunked")])
    assert status == 413 and b"BRDF_MAX_" in body
    assert pulled <= SETTINGS.max_upload_bytes + (1 << 20)


def test_the_store_is_bounded_and_says_when_an_id_expired():
    app = create_app(SETTINGS)
    client = TestClient(app)
    app.state.datasets = DatasetStore(max_bytes=6000)      # a few small CSVs
    ids = []
    for k in range(4):
        text = CSV + b"".join(b"%d,0,%d,180,%d\n" % (k, j, j) for j in range(60))
        response = client.post("/api/v1/datasets", content=text)
        assert response.status_code == 201
        ids.append(response.json()["id"])
    expired = client.get(f"/api/v1/datasets/{ids[0]}")
    assert expired.status_code == 410
    assert "least recently used" in detail(expired)["msg"] and "BRDF_MAX_DATASETS_BYTES" in detail(expired)["msg"]
    assert client.get(f"/api/v1/datasets/{ids[-1]}").status_code == 200


def test_merl_export_beyond_the_whole_budget_is_413_naming_the_model():
    # 1.46 M cells cannot be tabulated in 1 ms on any machine: no retry helps, so not 503
    from app.config import Settings
    with TestClient(create_app(Settings(max_seconds=0.001))) as tiny:
        response = tiny.get("/api/v1/export/model.binary", params=known.model("r"))
    assert response.status_code == 413, response.text
    assert detail(response)["loc"] == ["query", "model"] and "BRDF_MAX_SECONDS" in detail(response)["msg"]


def test_export_a_model_as_merl_and_as_samples(client):
    model = known.model("r")
    response = client.get("/api/v1/export/model.binary", params=model)
    assert response.status_code == 200 and len(response.content) == merl.FILE_BYTES
    table = merl.read(response.content)
    _, i, j, k = np.unravel_index(np.argmax(table), table.shape)
    assert i == 0      # the peak is in the first θ_h row, at the specular direction
    csv = client.get("/api/v1/export/model.csv", params={**model, "n_theta": 4, "n_phi": 4})
    assert csv.status_code == 200
    rows = np.loadtxt(io.StringIO(csv.text), delimiter=",", skiprows=1)
    assert ((rows[:, 0] < 90) | (rows[:, 2] < 90)).sum() == 4 * 4 * 4 - 4   # all but both grazing
    l = np.stack([np.sin(np.radians(rows[:, 0])), 0 * rows[:, 0], np.cos(np.radians(rows[:, 0]))], -1)
    t, p = np.radians(rows[:, 2]), np.radians(rows[:, 3])
    v = np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], -1)
    inside = (rows[:, 0] < 90) & (rows[:, 2] < 90)
    np.testing.assert_allclose(rows[inside, 4], known.ggx_f(l[inside], v[inside]), rtol=1e-9)
    uploaded = client.post("/api/v1/datasets", content=csv.content)
    assert uploaded.status_code == 201 and uploaded.json()["summary"]["count"] == len(rows)


def test_every_worker_and_a_restart_serve_an_upload(tmp_path):
    """Two applications sharing a cache directory stand for two workers (or a worker and
    its replacement after a restart): an id uploaded to one is served by the other, 100
    of 100 times, and its delete token works on either."""
    import dataclasses
    settings = dataclasses.replace(SETTINGS, cache_dir=str(tmp_path))
    first, second = TestClient(create_app(settings)), TestClient(create_app(settings))
    body = first.post("/api/v1/datasets", content=CSV, headers={"content-type": "text/csv"}).json()
    answers = [(first if i % 2 else second).get(f"/api/v1/datasets/{body['id']}").status_code
               for i in range(100)]
    assert answers == [200] * 100
    restarted = TestClient(create_app(settings))
    assert restarted.get(f"/api/v1/datasets/{body['id']}").json()["summary"] == body["summary"]
    assert restarted.delete(f"/api/v1/datasets/{body['id']}", params={"token": body["token"]}).status_code == 204
    gone = first.get(f"/api/v1/datasets/{body['id']}")
    assert gone.status_code == 410 and "deleted" in detail(gone)["msg"]
