"""brdf-explorer export: every format written with no server running, options spelled
like the API's parameters, batches with a progress bar, usage errors named."""
from __future__ import annotations

import json
import xml.etree.ElementTree as ET

import pytest

from app.cli import main

from tests.export.conftest import read_csv
from tests.export.test_images import png_size


def test_export_writes_csv_json_html(tmp_path, client):
    for name in ("ndf.csv", "ndf.json", "ndf.plotly.json", "ndf.html"):
        out = tmp_path / name
        assert main(["export", "ndf", "--ndf", "beckmann", "--alpha", "0.3", "--n", "11",
                     "--no-log", "-o", str(out)]) == 0
        assert out.stat().st_size > 0
    api = client.get("/api/v1/ndf?ndf=beckmann&alpha=0.3&n=11").json()
    assert json.loads((tmp_path / "ndf.json").read_text()) == api
    comments, header, rows = read_csv((tmp_path / "ndf.csv").read_text())
    assert header == ["theta_deg", "D_per_sr"] and [float(r[1]) for r in rows] == api["D"]
    assert comments["ndf"] == "beckmann" and comments["log"] == "false"
    fig = json.loads((tmp_path / "ndf.plotly.json").read_text())
    assert fig["layout"]["yaxis"].get("type") != "log"             # --no-log reached the figure
    html = (tmp_path / "ndf.html").read_text()
    assert html.lower().startswith("<!doctype html>") and "Plotly.newPlot" in html
    assert 'src="http' not in html                  # plotly.js inlined: opens offline


def test_geometry_options_use_dashes(tmp_path, client):
    out = tmp_path / "lobe.json"
    assert main(["export", "lobe", "--theta-i-deg", "40", "--cosine", "--n", "5", "-o", str(out)]) == 0
    api = client.get("/api/v1/lobe?theta_i_deg=40&cosine=true&n=5").json()
    assert json.loads(out.read_text()) == api


def test_varied_json_lists_each_value(tmp_path):
    out = tmp_path / "albedo.json"
    assert main(["export", "albedo", "--n", "3", "--vary", "alpha", "--values", "0.2,0.6", "-o", str(out)]) == 0
    body = json.loads(out.read_text())
    assert body["vary"] == "alpha" and [v["value"] for v in body["variants"]] == ["0.2", "0.6"]


@pytest.mark.parametrize("argv, needle", [
    (["export", "ndf", "--alpha", "2", "-o", "x.csv"], "--alpha"),
    (["export", "nope", "-o", "x.csv"], "one of"),
    (["export", "ndf", "-o", "x.txt"], ".svg"),
    (["export", "ndf", "--vary", "alpha", "--values", "0.1,9", "-o", "x.csv"], "alpha=9"),
])
def test_usage_errors_name_the_problem(tmp_path, monkeypatch, capsys, argv, needle):
    monkeypatch.chdir(tmp_path)
    assert main(argv) == 2
    assert needle in capsys.readouterr().err
    assert not list(tmp_path.iterdir())                    # nothing half-written


def test_no_chromium_exit_3_with_the_install_hint(tmp_path, monkeypatch, capsys):
    monkeypatch.setenv("BRDF_CHROMIUM", "/nonexistent/chromium")
    assert main(["export", "ndf", "-o", str(tmp_path / "x.svg")]) == 3
    assert "apt-get install chromium" in capsys.readouterr().err


@pytest.mark.e2e
def test_batch_writes_images_with_a_progress_bar(tmp_path, capsys):
    deck = tmp_path / "deck.txt"
    deck.write_text("# a lecture's figures\n"
                    f"lobe --alpha 0.1 --theta-i-deg 60 --n 31 -o {tmp_path}/lobe.svg\n"
                    f"ndf --vary ndf --values ggx,beckmann --n 31 --width 600 --height 300 --scale 2 -o {tmp_path}/ndf.png\n"
                    f"sphere --n 32 --display render -o {tmp_path}/sphere.csv\n")
    assert main(["export-batch", str(deck)]) == 0
    err = capsys.readouterr().err
    assert "[" in err and "1/3" in err and "3/3" in err
    assert ET.parse(tmp_path / "lobe.svg").getroot().tag.endswith("svg")
    assert png_size((tmp_path / "ndf.png").read_bytes()) == (1200, 600)
    assert read_csv((tmp_path / "sphere.csv").read_text())[1] == ["y", "x", "radiance_per_sr"]
