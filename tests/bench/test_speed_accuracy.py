"""renderer/bench/speed_accuracy.py in its quick mode: every chart comes with
its CSV and Markdown table, and the sampled methods' error falls as their
samples rise (deterministic: the samplers are seeded by pixel and sample)."""
import csv
import json
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "renderer" / "bench" / "speed_accuracy.py"
CHARTS = ["soft_shadows_cornell", "soft_shadows_dragon", "antialiasing_cornell", "antialiasing_dragon",
          "motion_cornell", "motion_dragon", "depth_cornell", "depth_cornell_spheres", "depth_dragon"]
MAIN_METHOD = {"soft": "cone", "antialiasing": "box", "motion": "time", "depth": "cutoff_0"}


@pytest.fixture(scope="module")
def charts(scenes_dir, tmp_path_factory) -> Path:
    work = tmp_path_factory.mktemp("speed_accuracy")
    result = subprocess.run([sys.executable, str(SCRIPT), "--quick", "--scenes", str(scenes_dir),
                             "--out", str(work / "charts"), "--cache", str(work / "cache")],
                            capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    return work / "charts"


def rows(charts: Path, chart: str, method: str, reference: str | None = None) -> list[dict]:
    with (charts / f"{chart}.csv").open() as f:
        return [r for r in csv.DictReader(f) if r["method"] == method and reference in (None, r["reference"])]


def test_every_chart_has_its_picture_and_tables(charts):
    readme = (charts / "README.md").read_text()
    for chart in CHARTS:
        assert (charts / f"{chart}.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", chart
        table = (charts / f"{chart}.md").read_text()
        assert f"({chart}.png)" in table and "Machine:" in table, chart
        assert len(rows(charts, chart, MAIN_METHOD[chart.split("_")[0]])) >= 2, chart
        assert f"({chart}.md)" in readme and f"({chart}.png)" in readme
    assert "quick mode" in readme.lower()


def test_the_index_lists_every_chart_with_its_key_figures(charts):
    from google.protobuf import json_format
    from rt import charts_pb2

    index = json_format.Parse((charts / "index.json").read_text(), charts_pb2.ChartIndex())
    section = next(s for s in index.sections if s.key == "speed_accuracy")
    assert [c.slug for c in section.charts] == CHARTS
    assert "cores" in section.machine
    for chart in section.charts:
        assert chart.table.rows and all(len(r.cells) == len(chart.table.columns) for r in chart.table.rows), chart.slug
        assert chart.headline[:1].isupper(), chart.slug


def falling(values: list[float]) -> bool:
    return all(later < earlier for earlier, later in zip(values, values[1:]))


@pytest.mark.parametrize("chart", ["soft_shadows_cornell", "soft_shadows_dragon"])
def test_cone_error_falls_as_shadow_rays_rise(charts, chart):
    cone = rows(charts, chart, "cone")
    samples = [json.loads(r["settings"])["light_samples"] for r in cone]
    assert samples == sorted(samples) and len(samples) >= 3
    assert falling([float(r["rmse"]) for r in cone]), cone
    assert falling([float(r["flip"]) for r in cone]), cone
    assert float(cone[-1]["rmse"]) < float(cone[0]["rmse"]) / 4, "16 times the rays, a quarter of the error at least"


@pytest.mark.parametrize("chart,method,reference", [
    ("antialiasing_cornell", "box", "box"), ("antialiasing_dragon", "grid", "box"),
    ("motion_cornell", "time", "time"), ("motion_dragon", "frames", "frames")])
def test_other_methods_converge_too(charts, chart, method, reference):
    points = rows(charts, chart, method, reference)
    assert falling([float(r["rmse"]) for r in points]), points


def test_depth_error_vanishes_towards_the_reference(charts):
    deep = rows(charts, "depth_cornell_spheres", "cutoff_0")
    errors = [float(r["rmse"]) for r in deep]
    assert errors[0] > 0.01, "the reflective spheres are black at max_depth 0"
    assert all(later <= earlier for earlier, later in zip(errors, errors[1:]))
    assert "saved" in (charts / "depth_dragon.md").read_text()


def test_replot_redraws_the_sampling_charts_from_their_csvs(charts):
    """--replot renders nothing: it redraws each sampling chart's PNG from its
    CSV (the depth charts, whose time saving the CSV lacks, stay as they are)."""
    before = {p.name: p.read_bytes() for p in charts.glob("*.png")}
    for png in charts.glob("soft_shadows_*.png"):
        png.unlink()
    result = subprocess.run([sys.executable, str(SCRIPT), "--replot", "--out", str(charts)],
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    redrawn = sorted(line.split()[1] for line in result.stdout.splitlines() if line.startswith("redrew "))
    assert redrawn == sorted(f"{c}.png" for c in CHARTS if not c.startswith("depth_"))
    for chart in CHARTS:
        png = (charts / f"{chart}.png").read_bytes()
        assert png[:8] == b"\x89PNG\r\n\x1a\n", chart
        if chart.startswith("depth_"):
            assert png == before[f"{chart}.png"], chart
