"""Errors that say how to fix the file (issue 34): a `;`-separated CSV is told its
separator and to use commas; columns named r, g, b are pointed to f_r, f_g, f_b."""
from __future__ import annotations

import pytest

from tests.datasets.conftest import app, client  # noqa: F401  (fixtures)

ROW = "30,0,30,180"


@pytest.mark.parametrize("sep, name", [(";", "semicolon"), ("\t", "tab")])
def test_a_csv_with_another_separator_is_told_which_and_to_use_commas(client, sep, name):
    text = sep.join(["theta_i_deg", "phi_i_deg", "theta_o_deg", "phi_o_deg", "f"]) + "\n"
    text += sep.join(["30", "0", "30", "180", "1.5"]) + "\n"
    res = client.post("/api/v1/datasets", content=text.encode())
    assert res.status_code == 422, res.text
    msg = res.json()["detail"][0]["msg"]
    assert name in msg and "comma" in msg and "unknown column" not in msg


def test_columns_r_g_b_get_a_hint_towards_f_r_f_g_f_b(client):
    text = f"theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,r,g,b\n{ROW},0.1,0.2,0.3\n"
    res = client.post("/api/v1/datasets", content=text.encode())
    assert res.status_code == 422, res.text
    msg = res.json()["detail"][0]["msg"]
    assert "'f_r'" in msg and "'f_g'" in msg and "'f_b'" in msg


def test_a_single_alias_gets_its_name(client):
    text = f"theta_i,phi_i_deg,theta_o_deg,phi_o_deg,f\n{ROW},0.1\n"
    msg = client.post("/api/v1/datasets", content=text.encode()).json()["detail"][0]["msg"]
    assert "did you mean 'theta_i_deg'" in msg
