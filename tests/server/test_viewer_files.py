"""The built viewer as the server hands it out: files as they are, the pages
without their .html (/charts), index.html for the viewer's own routes, and
nothing from outside the viewer's folder."""
import pytest
from fastapi.testclient import TestClient

from app.main import create_app
from service import service_settings


@pytest.fixture(scope="module")
def viewer(tmp_path_factory):
    data = tmp_path_factory.mktemp("viewer")
    web = data / "dist"
    (web / "assets").mkdir(parents=True)
    (web / "charts").mkdir()
    (web / "index.html").write_text("<title>viewer</title>")
    (web / "charts.html").write_text("<title>charts</title>")
    (web / "assets" / "main.js").write_text("export {};")
    (web / "charts" / "index.json").write_text('{"sections": []}')
    (data / "secret.html").write_text("outside the viewer")
    with TestClient(create_app(service_settings(data / "data", web_dir=web))) as client:
        yield client


@pytest.mark.parametrize("path,title", [("/", "viewer"), ("/jobs/abc123", "viewer"), ("/charts", "charts"),
                                        ("/charts/", "charts"), ("/charts.html", "charts")])
def test_pages(viewer, path, title):
    response = viewer.get(path)
    assert response.status_code == 200
    assert f"<title>{title}</title>" in response.text


def test_files_as_they_are(viewer):
    assert viewer.get("/charts/index.json").json() == {"sections": []}
    assert viewer.get("/assets/main.js").text == "export {};"


@pytest.mark.parametrize("path", ["/../secret", "/%2e%2e/secret", "/charts/../../secret"])
def test_nothing_from_outside(viewer, path):
    assert "outside the viewer" not in viewer.get(path).text


def test_unknown_api_routes_are_json_404(viewer):
    response = viewer.get("/api/nothing-here")
    assert response.status_code == 404
    assert "no route /api/nothing-here" in response.json()["detail"]
