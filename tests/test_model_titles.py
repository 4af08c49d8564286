"""Panel headings name what the user chose (issue 34): the measured material by its name
(not its Fresnel kind), the diffuse model and its parameters, the principled model's
diffuse when it is not the paper's; a family without its own form by its label and the
parameters that differ. The expected names are the materials' and diffuse models'
own labels (the registries), written here as a reader expects them."""
from fastapi.testclient import TestClient

from app.figures.titles import file_stem, model_title
from app.main import create_app
from app.model import make_spec
from tests.budget import settings_for_tests


def test_a_measured_material_is_named_in_the_title():
    title = model_title(make_spec(material="gold").values)
    assert "Gold" in title and "Conductor" not in title
    assert "material-gold" in file_stem("lobe", make_spec(material="gold").values)


def test_the_diffuse_model_is_named_with_its_parameters():
    assert "diffuse Burley" in model_title(make_spec(diffuse="burley", kd=0.5).values)
    title = model_title(make_spec(diffuse="oren_nayar", kd=0.5, sigma=0.3).values)
    assert "diffuse Oren–Nayar σ=0.3" in title
    assert "diffuse" not in model_title(make_spec(kd=0.5).values)      # Lambert, the default


def test_the_principled_diffuse_is_named_when_not_the_papers():
    assert "EON diffuse" in model_title(make_spec(model="principled", principled_diffuse="eon").values)
    assert "diffuse" not in model_title(make_spec(model="principled").values)


def test_panel_headings_carry_them():
    client = TestClient(create_app(settings_for_tests()))
    fig = client.get("/api/v1/figures/lobe", params={"material": "copper", "diffuse": "burley", "kd": 0.3}).json()
    text = fig["layout"]["title"]["text"]
    assert "Copper" in text and "diffuse Burley" in text
