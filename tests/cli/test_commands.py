"""brdf-explorer's commands beyond the exports: help on stdout in plain text, one command
per capability (generated from the API's query-only operations), datasets and fit from
a file, and output into a directory only if it exists or --mkdir asks for it."""
from __future__ import annotations

import csv
import io
import json
import math
import os
import subprocess
import sys
from pathlib import Path

import pytest

from app.cli import main

ROOT = Path(__file__).resolve().parents[2]
CAPABILITIES = ("serve", "export", "export-batch", "export-gallery", "figures", "datasets", "fit",
                "code", "lut", "conventions", "materials", "principled", "models")


def test_help_is_plain_text_on_stdout_and_exits_0():
    run = subprocess.run([sys.executable, "-m", "app.cli", "--help"], cwd=ROOT, capture_output=True,
                         text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    assert run.stderr == ""
    assert run.stdout.startswith("usage: brdf-explorer COMMAND")
    assert "``" not in run.stdout and "::" not in run.stdout       # no reStructuredText
    listed = {line.split()[0] for line in run.stdout.splitlines() if line.startswith("  ") and line.split()}
    assert set(CAPABILITIES) <= listed


@pytest.mark.parametrize("command", CAPABILITIES)
def test_every_command_has_help(command, capsys):
    with pytest.raises(SystemExit) as stop:
        main([command, "--help"])
    assert stop.value.code == 0
    out = capsys.readouterr().out
    assert out.startswith("usage:") and f"brdf-explorer {command}" in out


def test_no_command_prints_usage_and_exit_2_unknown_names_it(capsys):
    assert main([]) == 2
    assert "usage: brdf-explorer" in capsys.readouterr().out
    assert main(["paint"]) == 2
    assert "unknown command 'paint'" in capsys.readouterr().err


def test_a_missing_directory_is_named_not_created(tmp_path, capsys):
    out = tmp_path / "missing" / "dir" / "x.csv"
    assert main(["export", "ndf", "--n", "5", "-o", str(out)]) == 2
    assert f"directory {out.parent} does not exist" in capsys.readouterr().err
    assert not (tmp_path / "missing").exists()
    assert main(["code", "-o", str(out)]) == 2
    assert not (tmp_path / "missing").exists()
    assert main(["export", "ndf", "--n", "5", "--mkdir", "-o", str(out)]) == 0
    assert out.read_text().splitlines()[-1].startswith("90.0,")


def test_export_gallery_refuses_a_missing_directory(tmp_path, capsys):
    assert main(["export-gallery", str(tmp_path / "nope"), "--formats", "csv"]) == 2
    assert "does not exist" in capsys.readouterr().err and not (tmp_path / "nope").exists()


def test_figures_lists_every_view(capsys):
    from app.views import VIEWS
    assert main(["figures"]) == 0
    names = [line.split()[0] for line in capsys.readouterr().out.splitlines()[:len(VIEWS)]]
    assert names == list(VIEWS)


def test_code_is_what_the_api_answers_and_runs(tmp_path, client):
    out = tmp_path / "brdf.py"
    assert main(["code", "--ndf", "beckmann", "--alpha", "0.4", "--fresnel", "none", "--lang", "python",
                 "-o", str(out)]) == 0
    api = client.get("/api/v1/code?ndf=beckmann&alpha=0.4&fresnel=none&lang=python")
    assert out.read_text() == api.text
    namespace: dict = {}
    exec(compile(out.read_text(), str(out), "exec"), namespace)
    import numpy as np
    n = np.array([0.0, 0.0, 1.0])
    f = namespace["brdf"](n, n, n)                     # normal incidence and view: h = n
    # Beckmann D(0) = 1/(π α²), G2 ≈ 1 at normal incidence, F = 1: f = D/4
    assert np.allclose(f, 1.0 / (math.pi * 0.4 ** 2) / 4.0, rtol=1e-6)


def test_conventions_gltf_alpha_is_roughness_squared(capsys):
    assert main(["conventions", "--roughness", "0.5"]) == 0
    rows = json.loads(capsys.readouterr().out)
    gltf = next(r for r in rows if r["ecosystem"].startswith("glTF"))
    assert gltf["alpha"] == pytest.approx(0.25)        # glTF 2.0: α = roughness²


def test_bad_values_name_the_option_and_its_range(capsys):
    assert main(["conventions", "--roughness", "2"]) == 2
    err = capsys.readouterr().err
    assert "--roughness" in err and "[0, 1]" in err
    assert main(["code", "--lang", "cobol"]) == 2
    assert "--lang" in capsys.readouterr().err
    assert main(["lut", "--kind", "split_sum", "--size", "100000"]) == 2
    assert "--size" in capsys.readouterr().err


def test_lut_file_is_what_the_api_answers(tmp_path, client):
    out = tmp_path / "dfg.csv"
    assert main(["lut", "--kind", "split_sum", "--size", "8", "--format", "csv", "-o", str(out)]) == 0
    assert out.read_bytes() == client.get("/api/v1/lut?kind=split_sum&size=8&format=csv").content


def test_materials_lists_gold(capsys):
    assert main(["materials"]) == 0
    slugs = [m["slug"] for m in json.loads(capsys.readouterr().out)["materials"]]
    assert "gold" in slugs and "copper" in slugs


SAMPLES = "theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,f\n30,0,30,180,1.5\n45,0,20,90,0.25\n"


def test_datasets_summarises_a_file(tmp_path, capsys):
    path = tmp_path / "two.csv"
    path.write_text(SAMPLES)
    assert main(["datasets", str(path)]) == 0
    answer = json.loads(capsys.readouterr().out)
    assert answer["format"] == "samples_csv" and len(answer["id"]) == 32
    assert answer["summary"]["count"] == 2 and answer["summary"]["range"]["f"] == [0.25, 1.5]
    assert main(["datasets", str(tmp_path / "none.csv")]) == 2
    assert "no such file" in capsys.readouterr().err


def _beckmann_samples(alpha: float) -> str:
    """f = D G2 / (4 cos θ_i cos θ_o) of a Beckmann lobe with F = 1 in the plane of
    incidence, written from the closed forms (Walter et al. 2007, eqs. 25 and 27: D and the
    exact Smith Λ; Heitz 2014, eq. 99: height-correlated G2), not from the app's code."""
    rows = ["theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,f"]

    def lam(theta):
        a = 1.0 / (alpha * math.tan(theta)) if theta > 0 else math.inf
        if math.isinf(a):
            return 0.0
        return (math.erf(a) - 1.0) / 2.0 + math.exp(-a * a) / (2.0 * a * math.sqrt(math.pi))

    for ti in range(0, 41, 5):
        for to in range(0, 41, 5):
            t_i, t_o = math.radians(ti), math.radians(to)
            l = (math.sin(t_i), 0.0, math.cos(t_i))
            v = (-math.sin(t_o), 0.0, math.cos(t_o))         # φ_o = 180°: the mirror side
            h = [a + b for a, b in zip(l, v)]
            norm = math.sqrt(sum(c * c for c in h))
            cos_m = h[2] / norm
            tan2 = (1.0 - cos_m ** 2) / cos_m ** 2
            D = math.exp(-tan2 / alpha ** 2) / (math.pi * alpha ** 2 * cos_m ** 4)
            G2 = 1.0 / (1.0 + lam(t_i) + lam(t_o))            # height-correlated (Heitz 2014, eq. 99)
            rows.append(f"{ti},0,{to},180,{D * G2 / (4 * l[2] * v[2])!r}")
    return "\n".join(rows) + "\n"


def test_fit_recovers_the_alpha_of_closed_form_data(tmp_path, capsys):
    path = tmp_path / "beckmann.csv"
    path.write_text(_beckmann_samples(0.2))
    assert main(["fit", str(path), "--ndf", "beckmann", "--fresnel", "none", "--free", "alpha"]) == 0
    answer = json.loads(capsys.readouterr().out)
    assert answer["params"]["alpha"] == pytest.approx(0.2, rel=1e-4)
    assert answer["model"]["ndf"] == "beckmann"
    assert main(["fit", str(path), "--free", "bogus"]) == 2
    assert "--free" in capsys.readouterr().err


def test_datasets_and_fit_load_no_web_layer(tmp_path):
    """The file commands answer what the API would without importing it (FastAPI, the
    routes, the heavy pool): a command line is not a server."""
    path = tmp_path / "beckmann.csv"
    path.write_text(_beckmann_samples(0.3))
    script = ("import sys; from app.cli import main; "
              f"assert main(['datasets', {str(path)!r}]) == 0; "
              f"assert main(['fit', {str(path)!r}, '--ndf', 'beckmann', '--fresnel', 'none', "
              "'--free', 'alpha', '--seconds', '2']) == 0; "
              "print(sorted(m for m in sys.modules if m == 'fastapi' or m.startswith(('app.api', 'app.work'))), "
              "file=sys.stderr)")
    run = subprocess.run([sys.executable, "-c", script], cwd=ROOT, capture_output=True, text=True,
                         timeout=300)
    assert run.returncode == 0, run.stderr[-2000:]
    assert run.stderr.strip().splitlines()[-1] == "[]"


def test_model_csv_round_trips_through_datasets(tmp_path, capsys):
    out = tmp_path / "model.csv"
    assert main(["export-model-csv", "--n-theta", "3", "--n-phi", "2", "-o", str(out)]) == 0
    rows = list(csv.reader(io.StringIO(out.read_text())))
    assert rows[0][:4] == ["theta_i_deg", "phi_i_deg", "theta_o_deg", "phi_o_deg"]
    assert main(["datasets", str(out)]) == 0
    assert json.loads(capsys.readouterr().out)["format"] == "samples_csv"


def test_a_command_keeps_no_server_time_budget(tmp_path):
    """BRDF_MAX_SECONDS protects a server's workers; a command line has none to protect:
    with a budget far shorter than starting a worker process, export-model-csv answers
    (it ran out of it under CI's load, an 18-row table refused as "busy")."""
    out = tmp_path / "model.csv"
    script = ("from app.cli import main; "
              f"raise SystemExit(main(['export-model-csv', '--n-theta', '3', '--n-phi', '2', "
              f"'-o', {str(out)!r}]))")
    run = subprocess.run([sys.executable, "-c", script], cwd=ROOT, capture_output=True, text=True,
                         timeout=300, env={**os.environ, "BRDF_MAX_SECONDS": "0.001"})
    assert run.returncode == 0, run.stderr[-2000:]
    lines = out.read_text().splitlines()
    # a header and 3 × 3 × 2 pairs but one: θ_i = θ_o = 90° in the mirror direction, where
    # f diverges (CSV has no inf)
    assert lines[0].startswith("theta_i_deg,") and len(lines) == 1 + 3 * 3 * 2 - 1


def test_commands_run_where_an_event_loop_already_runs(tmp_path):
    """From a notebook (whose thread runs an event loop) the commands work as from a
    shell: export-model-csv's route is a coroutine, which asyncio.run refuses there."""
    import asyncio
    import concurrent.futures
    out = tmp_path / "model.csv"

    async def notebook_cell():
        return main(["export-model-csv", "--n-theta", "2", "--n-phi", "2", "-o", str(out)])

    # the cell's loop in a thread of its own: this one may already run Playwright's
    with concurrent.futures.ThreadPoolExecutor(max_workers=1) as kernel:
        assert kernel.submit(asyncio.run, notebook_cell()).result(timeout=300) == 0
    rows = list(csv.reader(io.StringIO(out.read_text())))
    assert len(rows) > 1 and rows[0][0] == "theta_i_deg"


def test_a_reader_that_stops_early_is_no_error():
    """``brdf-explorer figures | head -1`` exits 0 with no traceback (a closed pipe)."""
    run = subprocess.run(["bash", "-o", "pipefail", "-c", f"'{sys.executable}' -m app.cli figures | head -c 10"],
                         cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert run.returncode == 0 and "Traceback" not in run.stderr, run.stderr
    assert len(run.stdout) == 10
