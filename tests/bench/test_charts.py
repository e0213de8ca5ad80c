"""The stability and scaling chart scripts (make charts) in their quick form:
each writes its pictures, tables and its section of the chart index, and the
index keeps the other scripts' sections."""
import json
import subprocess
import sys
from pathlib import Path

import pytest
from google.protobuf import json_format
from rt import charts_pb2

ROOT = Path(__file__).resolve().parents[2]
BENCH = ROOT / "renderer" / "bench"
BUILD = ROOT / "build"


def run(*args: str) -> str:
    result = subprocess.run([sys.executable, *args], capture_output=True, text=True, timeout=300, cwd=ROOT)
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    return result.stdout


def index(out: Path) -> charts_pb2.ChartIndex:
    return json_format.Parse((out / "index.json").read_text(), charts_pb2.ChartIndex())


@pytest.fixture(scope="module")
def charts(scenes_dir, tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("charts")
    # An earlier section from another script, which both runs must keep.
    earlier = charts_pb2.ChartIndex(sections=[charts_pb2.ChartSection(key="speed_accuracy", title="earlier")])
    (out / "index.json").write_text(json_format.MessageToJson(earlier))
    run(str(BENCH / "stability_charts.py"), "--table", str(BUILD / "renderer" / "stability_table"),
        "--out", str(out), "--cache", str(out / "stability"))
    run(str(BENCH / "scaling.py"), "--quick", "--scenes", str(scenes_dir), "--rtrender", str(BUILD / "rtrender"),
        "--out", str(out), "--work", str(out / "scaling"))
    return out


def test_sections_in_order_and_every_chart_with_its_files(charts):
    sections = index(charts).sections
    assert [s.key for s in sections] == ["speed_accuracy", "stability", "scaling"]
    readme = (charts / "README.md").read_text()
    for section in sections[1:]:
        assert section.charts and "cores" in section.machine
        for chart in section.charts:
            assert (charts / f"{chart.slug}.png").read_bytes()[:4] == b"\x89PNG", chart.slug
            assert (charts / f"{chart.slug}.csv").stat().st_size > 0
            assert f"({chart.slug}.png)" in (charts / f"{chart.slug}.md").read_text()
            assert f"({chart.slug}.md)" in readme
            assert chart.table.rows and all(len(r.cells) == len(chart.table.columns) for r in chart.table.rows)


def charts_by_slug(out: Path) -> dict[str, charts_pb2.Chart]:
    return {c.slug: c for s in index(out).sections for c in s.charts}


def test_stability_headlines_say_ours_never_fails(charts):
    by_slug = charts_by_slug(charts)
    assert by_slug["stability_self_intersection"].headline.startswith("Ours: no wrong pixels at every scale")
    assert by_slug["stability_edge_leaks"].headline.startswith("Ours: 0 leaks in 1,000,000 rays")
    assert "(0 over)" in by_slug["stability_depth_bound"].headline
    assert " 0 NaN or Inf pixels" in by_slug["stability_depth_bound"].headline


def test_scaling_measures_every_scene_and_both_cluster_sizes(charts):
    by_slug = charts_by_slug(charts)
    rows = by_slug["scaling_triangles"].table.rows
    triangles = [int(r.cells[1].replace(",", "")) for r in rows]
    assert triangles == sorted(triangles) and len(rows) == 3
    configurations = [r.cells[0] for r in by_slug["scaling_throughput"].table.rows]
    for measured in ("rtcore, 1 thread", "rtcore, 2 threads", "Dask, 1 worker x 1 thread", "Dask, 2 workers x 1 thread"):
        assert measured in configurations
    report_rows = by_slug["scaling_report_table"].table.rows
    assert [r.cells[0] for r in report_rows][:2] == ["Cornell box", "Cornell box sphere light"]
    assert json.loads((charts / "index.json").read_text())["sections"][0]["title"] == "earlier"


def test_replot_redraws_from_the_csvs_without_measuring(charts):
    """--replot redraws the PNGs from the CSVs the run left, the foot naming the
    machine of that run."""
    for slug in ("stability_self_intersection", "scaling_report_table"):
        (charts / f"{slug}.png").unlink()
    run(str(BENCH / "stability_charts.py"), "--replot", "--only", "self_intersection", "--out", str(charts))
    run(str(BENCH / "scaling.py"), "--replot", "--quick", "--out", str(charts))
    for slug in ("stability_self_intersection", "scaling_report_table"):
        assert (charts / f"{slug}.png").read_bytes()[:4] == b"\x89PNG", slug
