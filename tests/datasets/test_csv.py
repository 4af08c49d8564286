"""The CSV formats: what they accept, and a 422 naming the column and row otherwise."""
import numpy as np
import pytest

from app.datasets import formats
from app.errors import ParameterError

SAMPLES = "theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,f\n30,0,30,180,1.5\n45,0,20,90,0.25\n"


def load(text, format=None):
    return formats.load(text.encode(), format)


def test_samples_are_read_in_any_column_order_and_case():
    data = load("f, Phi_O_deg,theta_o_deg,phi_i_deg,THETA_I_DEG\n# a comment\n2.0,180,30,0,60\n")
    assert data.format == "samples_csv" and data.channels == ("f",)
    np.testing.assert_allclose(data.f, [[2.0]])
    np.testing.assert_allclose(data.l[0], [np.sin(np.pi / 3), 0, 0.5], atol=1e-15)
    np.testing.assert_allclose(data.v[0], [-0.5, 0, np.cos(np.pi / 6)], atol=1e-15)


def test_rgb_samples_and_terms():
    rgb = load("theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,f_r,f_g,f_b\n10,0,10,180,1,2,3\n")
    assert rgb.channels == ("r", "g", "b")
    term = load("theta_deg,D,G1\n0,1,1\n45,0.5,0.9\n")
    assert term.kind == "term" and term.axis == "theta_deg" and set(term.terms) == {"D", "G1"}
    assert load("mu,E\n0.5,0.9\n1,0.95\n").axis == "mu"


@pytest.mark.parametrize("text, says", [
    ("theta_i_deg,phi_i_deg,theta_o_deg,f\n1,2,3,4\n", "phi_o_deg is missing"),
    ("theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,fr\n1,2,3,4,5\n", "did you mean 'f_r'"),
    ("thetai_deg,phi_i_deg,theta_o_deg,phi_o_deg,f\n1,2,3,4,5\n", "did you mean 'theta_i_deg'"),
    ("theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,f_r,f_g\n1,2,3,4,5,6\n", "f (or f_r, f_g, f_b)"),
    (SAMPLES.replace("1.5", "nan"), "f must be a finite number; data row 1 has nan"),
    (SAMPLES.replace("0.25", "inf"), "data row 2 has inf"),
    (SAMPLES.replace("0.25", "-0.25"), "f must be ≥ 0"),
    (SAMPLES.replace("45,0,20", "95,0,20"), "theta_i_deg must be in [0, 90]; data row 2 has 95"),
    (SAMPLES.replace("1.5", "abc"), "comma-separated numbers"),
    (SAMPLES + "1,2,3\n", "comma-separated numbers"),
    ("theta_deg,D\n", "no data rows"),
    ("theta_deg,D,E\n1,2,3\n", "'E' does not go with theta_deg"),
    ("mu,E\n1.5,0.9\n", "mu must be in [0, 1]"),
    ("theta_deg,G1\n10,-0.1\n", "G1 must be ≥ 0"),
    ("theta_deg,D,D\n1,2,3\n", "appears twice"),
    ("theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,F\n1,2,3,4,5\n", "f (or f_r, f_g, f_b) is missing"),
    ("# only a comment\n", "no header row"),
])
def test_bad_csv_names_the_column_and_row(text, says):
    with pytest.raises(ParameterError) as info:
        load(text)
    assert says in info.value.message, info.value.message
    assert info.value.status == 422 and info.value.param == "file"


def test_format_insisted_on():
    with pytest.raises(ParameterError, match="needs a theta_deg or mu column"):
        load(SAMPLES, "term_csv")
    with pytest.raises(ParameterError, match="theta_i_deg"):
        load("theta_deg,D\n1,2\n", "samples_csv")
    with pytest.raises(ParameterError, match="not text"):
        formats.load(b"\xff\xfe\x00\x01binary", "samples_csv")
    with pytest.raises(ParameterError) as info:
        load(SAMPLES, "xml")
    assert info.value.param == "format"


@pytest.mark.parametrize("content, says", [
    (b"", "empty"),
    (b"PK\x03\x04" + b"\0" * 100, "zip archive"),
    (b"\x1f\x8b\x08" + b"\0" * 100, "gzip"),
    (b"\x00\x01\x02\x03" * 10, "neither text nor a MERL"),
])
def test_detection_refuses_what_it_cannot_read(content, says):
    with pytest.raises(ParameterError, match=says):
        formats.load(content)
