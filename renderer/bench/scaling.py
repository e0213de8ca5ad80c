#!/usr/bin/env python3
"""Scaling: render and BVH build time against triangle count, the 2020 report's
performance table with our figures beside it, and throughput against threads
and Dask workers with the projected curve for a larger cluster.

Over the sample scenes (the dragon at four resolutions, bunny, teapot, donut,
the Cornell boxes and the smooth sphere), each seen from its default camera at
the default settings: the BVH build on one thread and on all, the render on all,
and the BVH nodes visited and triangles tested per ray (rtcore's bvh_cost
layer over every ray traced). The dragons are one shape at four tessellations,
so their traversal cost is fitted to a + b log2(triangles). The cluster model
(cluster_model.py, drawn by cluster_model_chart.py) projects a 3840x2160
dragon onto 1 to 64 workers of 8 threads from Dask's and the renderer's costs
measured here, with the tile plan and Dask's dealing of tiles before and now.
Writes scaling_triangles, scaling_report_table, scaling_throughput and
scaling_cluster_model (PNG, CSV, Markdown) into --out and the chart index's
scaling section (--only cluster_model: that chart alone, the others kept;
--reuse-costs: on the costs it measured last, kept beside the chart).
"""

from __future__ import annotations

import argparse
import csv
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import rtcore  # noqa: E402
from rt import charts_pb2, render_pb2  # noqa: E402

import chart_index  # noqa: E402
import cluster_model_chart  # noqa: E402
import report_table  # noqa: E402
import scaling_cluster  # noqa: E402
from accuracy_measure import machine_info  # noqa: E402
from app.services.tile_plan import TILES_PER_THREAD  # noqa: E402  (scaling_cluster puts server/ on the path)

SCENES = ["cornell.obj", "cornell_sphere_light.obj", "smooth_sphere.glb", "bunny.glb", "teapot.glb", "donut.glb",
          "dragon_4.glb", "dragon_3.glb", "dragon_2.glb", "dragon_1.glb"]
DRAGONS = ["dragon_4.glb", "dragon_3.glb", "dragon_2.glb", "dragon_1.glb"]


def measure_scene(path: Path, size: int) -> dict:
    """Build on one thread and on all, render on all (median of 3 after a
    warm-up), and traversal cost per ray."""
    one = rtcore.Scene.load(str(path), threads=1).bvh_stats["build_ms"]
    scene = rtcore.Scene.load(str(path))
    stats = scene.bvh_stats
    camera = scene.default_camera
    settings = render_pb2.RenderSettings(width=size, height=size).SerializeToString()
    render_s = scaling_cluster.median_time(lambda: scene.render(camera, settings, 0, 32), 3)
    cost = scene.render_tile(camera, settings, 0, 0, size, size, aux=["bvh_cost"])
    layer = np.asarray(cost["bvh_cost"], dtype=np.float64)
    rays = int(cost["rays"])
    return {"scene": path.name, "triangles": stats["triangles"], "nodes": stats["nodes"], "depth": stats["depth"],
            "build_ms_1": one, "build_ms": stats["build_ms"], "render_ms": 1000 * render_s,
            "mrays_s": rays / render_s / 1e6, "rays": rays, "nodes_per_ray": layer[..., 0].sum() / rays,
            "triangles_per_ray": layer[..., 1].sum() / rays}


def log_fit(rows: list[dict], key: str) -> tuple[float, float, float]:
    """(a, b, r^2) of key = a + b log2(triangles)."""
    x = np.log2([r["triangles"] for r in rows])
    y = np.array([r[key] for r in rows])
    b, a = np.polyfit(x, y, 1)
    residual = y - (a + b * x)
    r2 = 1 - (residual @ residual) / max(((y - y.mean()) @ (y - y.mean())), 1e-12)
    return a, b, r2


def triangles_chart(rows: list[dict], size: int, machine: dict, out: Path) -> charts_pb2.Chart:
    dragons = [r for r in rows if r["scene"] in DRAGONS]
    fig, axes = plt.subplots(1, 2, figsize=(13, 5))
    by_tris = sorted(rows, key=lambda r: r["triangles"])
    n = [r["triangles"] for r in by_tris]
    for key, label, marker in (("render_ms", f"render {size}x{size}, all cores", "o"),
                               ("build_ms", "BVH build, all cores", "s"), ("build_ms_1", "BVH build, 1 thread", "^")):
        axes[0].plot(n, [r[key] for r in by_tris], marker=marker, label=label)
    for r in by_tris:
        axes[0].annotate(r["scene"].split(".")[0], (r["triangles"], r["render_ms"]), xytext=(3, 4),
                         textcoords="offset points", fontsize=6.5, color="#444")
    axes[0].set_xscale("log")
    axes[0].set_yscale("log")
    axes[0].set_xlabel("triangles")
    axes[0].set_ylabel("ms")
    axes[0].set_title("time against triangle count", fontsize=10)
    axes[0].legend(fontsize=8)
    axes[0].grid(True, which="both", linewidth=0.3, alpha=0.6)

    fits = {key: log_fit(dragons, key) for key in ("nodes_per_ray", "triangles_per_ray")}
    xs = np.geomspace(min(n), max(n), 50)
    for key, label, marker in (("nodes_per_ray", "BVH nodes visited per ray", "o"),
                               ("triangles_per_ray", "triangles tested per ray", "s")):
        others = [r for r in rows if r["scene"] not in DRAGONS]
        line, = axes[1].plot([r["triangles"] for r in dragons], [r[key] for r in dragons], marker=marker,
                             linestyle="none", label=f"{label}: the dragons")
        axes[1].plot([r["triangles"] for r in others], [r[key] for r in others], marker=marker, linestyle="none",
                     markerfacecolor="none", color=line.get_color(), label=f"{label}: other scenes")
        a, b, r2 = fits[key]
        axes[1].plot(xs, a + b * np.log2(xs), linestyle="--", color=line.get_color(),
                     label=f"fit over the dragons: {a:.1f} + {b:.2f} log2 N (r² {r2:.3f})")
    axes[1].set_xscale("log")
    axes[1].set_ylim(bottom=0)
    axes[1].set_xlabel("triangles (log scale)")
    axes[1].set_ylabel("per ray, every kind of ray traced")
    axes[1].set_title("traversal cost grows with log N (a linear scan would test N triangles)", fontsize=10)
    axes[1].legend(fontsize=7)
    axes[1].grid(True, which="both", linewidth=0.3, alpha=0.6)
    fig.suptitle("Scaling with triangle count: the sample scenes from their default cameras, default settings")
    chart_index.save_figure(fig, machine, out / "scaling_triangles.png")

    small, large = dragons[0], dragons[-1]
    a, b, r2 = fits["nodes_per_ray"]
    headline = (f"From {small['triangles']:,} to {large['triangles']:,} dragon triangles "
                f"({large['triangles'] / small['triangles']:.0f}x) the nodes visited per ray grow "
                f"{large['nodes_per_ray'] / small['nodes_per_ray']:.2f}x and render time "
                f"{large['render_ms'] / small['render_ms']:.2f}x: {b:.2f} more nodes per doubling "
                f"(r² {r2:.3f}); build time grows about linearly "
                f"({large['build_ms'] / small['build_ms']:.0f}x)")
    table = chart_index.table(
        ["scene", "triangles", "BVH depth", "build ms (1 thread)", "build ms (all)", "render ms", "Mrays/s",
         "nodes per ray", "triangles per ray"],
        [[r["scene"], f"{r['triangles']:,}", r["depth"], f"{r['build_ms_1']:.1f}", f"{r['build_ms']:.1f}",
          f"{r['render_ms']:.1f}", f"{r['mrays_s']:.2f}", f"{r['nodes_per_ray']:.1f}",
          f"{r['triangles_per_ray']:.2f}"] for r in by_tris])
    return charts_pb2.Chart(slug="scaling_triangles", title="Render and BVH build time against triangle count",
                            headline=headline, table=table)


REPORT_COLUMNS = ["2020 report scene", "2020 report triangles", "2020 report time", "2020 report BVH levels",
                  "our scene", "triangles", "BVH depth", "build ms", "render ms"]


def report_chart(rtrender: Path, scenes: Path, work: Path, machine: dict, out: Path,
                 width: int = 800, height: int = 600) -> charts_pb2.Chart:
    """The 2020 report's Table 2 (docs/origin.md) with our renders of the
    sample scenes that stand in for its rows."""
    rows = []
    for name, tris, seconds, levels, file in report_table.REPORT_ROWS:
        ours = report_table.render(rtrender, scenes / file, work, width, height)
        rows.append({"report_scene": name, "report_triangles": tris, "report_time": seconds,
                     "report_levels": levels, "scene": file, "triangles": int(ours["tris"]),
                     "depth": int(ours["depth"]), "build_ms": float(ours["build"]),
                     "render_ms": float(ours["render"])})
    draw_report_table(rows, width, height, machine, out)
    sphere = next(r for r in rows if "sphere light" in r["report_scene"])
    headline = (f"The 2020 report's slowest row, the Cornell box with a sphere light ({sphere['report_time']}), "
                f"takes {sphere['render_ms']:.0f} ms here at {width}x{height} with 16 shadow rays per light")
    table = chart_index.table(
        REPORT_COLUMNS,
        [[r["report_scene"], r["report_triangles"], r["report_time"], r["report_levels"], r["scene"],
          f"{r['triangles']:,}", r["depth"], f"{r['build_ms']:.1f}", f"{r['render_ms']:.1f}"] for r in rows])
    return charts_pb2.Chart(slug="scaling_report_table",
                            title="The 2020 report's performance table, with ours beside it",
                            headline=headline, table=table)


def draw_report_table(rows: list[dict], width: int, height: int, machine: dict, out: Path) -> None:
    def report_ms(text: str) -> float:
        value, unit = text.split()
        return float(value) * (1000 if unit == "s" else 1)

    fig, ax = plt.subplots(figsize=(10, 4.8))
    xs = np.arange(len(rows))
    ax.bar(xs - 0.2, [report_ms(r["report_time"]) for r in rows], 0.4, label="the 2020 report, Table 2",
           color="#bbbbbb")
    ax.bar(xs + 0.2, [r["render_ms"] for r in rows], 0.4, label=f"rtrender {width}x{height}, all cores",
           color="#1f77b4")
    for x, r in zip(xs, rows):
        ax.annotate(f"{r['render_ms']:.0f} ms", (x + 0.2, r["render_ms"]), ha="center", xytext=(0, 3),
                    textcoords="offset points", fontsize=7)
        ax.annotate(r["report_time"], (x - 0.2, report_ms(r["report_time"])), ha="center", xytext=(0, 3),
                    textcoords="offset points", fontsize=7, color="#555")
    ax.set_xticks(xs, [f"{r['report_scene']}\n({r['scene']})" for r in rows], fontsize=7)
    ax.set_yscale("log")
    ax.set_ylabel("render time (ms)")
    ax.legend(fontsize=8)
    ax.set_title("the 2020 report gives no image size or machine; its sphere-light row samples whole spheres",
                 fontsize=9)
    fig.suptitle("The 2020 report's performance table, with ours beside it")
    chart_index.save_figure(fig, machine, out / "scaling_report_table.png")


def replot_report_table(out: Path, width: int, height: int) -> None:
    """Redraws scaling_report_table.png from its committed CSV and the
    machine line in the index, without measuring anything."""
    with (out / "scaling_report_table.csv").open() as f:
        table = list(csv.reader(f))[1:]
    rows = [{"report_scene": c[0], "report_triangles": c[1], "report_time": c[2], "report_levels": c[3],
             "scene": c[4], "render_ms": float(c[8])} for c in table]
    section = next(s for s in chart_index.read_index(out).sections if s.key == "scaling")
    draw_report_table(rows, width, height, chart_index.machine_from_line(section.machine), out)


def throughput_chart(t: scaling_cluster.Throughput, machine: dict, out: Path) -> charts_pb2.Chart:
    fig, ax = plt.subplots(figsize=(9, 5))
    mpix = lambda s: scaling_cluster.pixels_per_second(t, s) / 1e6  # noqa: E731
    counts = [2 ** k for k in range(9)]
    ax.plot(counts, [mpix(t.projected(n)) for n in counts], linestyle="--", color="#1f77b4",
            label=f"projected: Dask, N workers of 1 thread, the service's tiles (at least {TILES_PER_THREAD} "
                  "per thread)")
    ax.plot(counts, [mpix(t.projected(n, t.best_side(n))) for n in counts], linestyle="-.", color="#2ca02c",
            label="projected: the same with the model's best tile size for N")
    ax.plot(counts, [mpix(scaling_cluster.ideal(t, n)) for n in counts], linestyle=":", color="#999",
            label="ideal: the one-worker time split N ways")
    ax.plot(list(t.workers), [mpix(s) for s in t.workers.values()], marker="o", linestyle="none", markersize=8,
            color="#1f77b4", label="measured: Dask LocalCluster, N worker processes")
    ax.plot(list(t.threads), [mpix(s) for s in t.threads.values()], marker="s", linestyle="none", markersize=8,
            color="#ff7f0e", label="measured: rtcore Scene.render on N threads")
    ax.set_xscale("log", base=2)
    ax.set_yscale("log")
    ax.set_xlabel("workers (or threads)")
    ax.set_ylabel("Mpixels per second")
    ax.set_title(f"{t.scene}, {t.size}x{t.size}, default settings, the service's tiles as Dask tasks; model: "
                 + scaling_cluster.model_text(t), fontsize=7.5, wrap=True)
    ax.legend(fontsize=8)
    ax.grid(True, which="both", linewidth=0.3, alpha=0.6)
    fig.suptitle("Throughput against threads and Dask workers")
    chart_index.save_figure(fig, machine, out / "scaling_throughput.png")
    two = t.workers[1] / t.workers[2]
    best = max(counts, key=lambda n: mpix(t.projected(n)))
    ceiling = max(mpix(t.projected(n, t.best_side(n))) for n in counts)
    headline = (f"2 Dask workers render {two:.2f}x as fast as 1 ({t.threads[1] / t.threads[2]:.2f}x for 2 threads "
                f"in one process); the model projects {mpix(t.projected(8)) / mpix(t.projected(1)):.1f}x at 8 "
                f"workers, but with the service's tiles (at least {TILES_PER_THREAD} per thread, as large as the ray "
                f"budget allows) the scheduler's {t.serial_s * 1000:.1f} ms per "
                f"task caps it at {mpix(t.projected(best)) / mpix(t.projected(1)):.1f}x ({best} workers) and it falls "
                f"beyond; larger tiles would reach {ceiling / mpix(t.projected(1)):.1f}x")
    table = chart_index.table(["configuration", "", "tiles", "ms per image", "Mpixels/s"],
                              scaling_cluster.summary_rows(t))
    return charts_pb2.Chart(slug="scaling_throughput", title="Throughput against threads and Dask workers",
                            headline=headline, table=table)


def write_pages(chart: charts_pb2.Chart, summary: str, machine: dict, out: Path, extra: str = "") -> None:
    with (out / f"{chart.slug}.csv").open("w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(list(chart.table.columns) + ["cpu", "cores", "commit", "date"])
        for row in chart.table.rows:
            writer.writerow(list(row.cells) + [machine[k] for k in ("cpu", "cores", "commit", "date")])
    lines = [f"# {chart.title}", "", f"![{chart.title}]({chart.slug}.png)", "", f"**{chart.headline}**.", "",
             summary + extra, "", f"Machine: {chart_index.machine_line(machine)}.", "",
             *chart_index.markdown_table(chart.table)]
    (out / f"{chart.slug}.md").write_text("\n".join(lines) + "\n")


def put_chart(out: Path, chart: charts_pb2.Chart, summary: str, machine: dict) -> None:
    """Puts one chart into the index's scaling section in place of its earlier
    run, keeping the section's other charts (a section of its own if none)."""
    section = next((s for s in chart_index.read_index(out).sections if s.key == "scaling"), None)
    if section is None:
        section = charts_pb2.ChartSection(key="scaling", title="Scaling", summary=summary,
                                          machine=chart_index.machine_line(machine))
    charts = [c for c in section.charts if c.slug != chart.slug] + [chart]
    del section.charts[:]
    section.charts.extend(charts)
    chart_index.put_section(out, section)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenes", type=Path, default=Path("build/scenes"))
    parser.add_argument("--rtrender", type=Path, default=Path("build/rtrender"))
    parser.add_argument("--out", type=Path, default=Path("docs/charts"))
    parser.add_argument("--work", type=Path, default=Path("build/charts/scaling"), help="images rendered")
    parser.add_argument("--size", type=int, default=512, help="image size for the triangle-count chart")
    parser.add_argument("--cluster-size", type=int, default=1024, help="image size for the throughput chart")
    parser.add_argument("--quick", action="store_true", help="small images, two scenes: to test the script")
    parser.add_argument("--replot", action="store_true",
                        help="only redraw scaling_report_table.png in --out from its CSV (no measuring)")
    parser.add_argument("--only", choices=["cluster_model"],
                        help="measure and write only this chart, keeping the section's others")
    parser.add_argument("--reuse-costs", action="store_true",
                        help="model the cluster from the costs the last run measured (in --out) instead of measuring")
    args = parser.parse_args()
    if args.replot:
        replot_report_table(args.out, *((160, 120) if args.quick else (800, 600)))
        return 0
    if not (args.scenes / "dragon_1.glb").exists():
        sys.exit(f"scaling: no sample scenes in {args.scenes}: run `make samples`")
    machine = machine_info()
    args.out.mkdir(parents=True, exist_ok=True)
    args.work.mkdir(parents=True, exist_ok=True)
    summary = ("Measured by renderer/bench/scaling.py through rtcore and rtrender; times are wall clock, the "
               "median of 3 after a warm-up (of 5 for the Dask runs, the noisiest).")
    if args.only == "cluster_model":
        dask, renders, machine = cluster_model_chart.measure(args.scenes, args.quick, args.out, machine,
                                                             args.reuse_costs)
        chart, text = cluster_model_chart.chart(dask, renders, machine, args.out)
        print(chart.headline, flush=True)
        write_pages(chart, cluster_model_chart.SUMMARY, machine, args.out, text)
        put_chart(args.out, chart, summary, machine)
        return 0
    scenes = ["cornell.obj", "dragon_4.glb", "dragon_3.glb"] if args.quick else SCENES
    size = 64 if args.quick else args.size
    rows = []
    for name in scenes:
        rows.append(measure_scene(args.scenes / name, size))
        r = rows[-1]
        print(f"{name:26} {r['triangles']:>8} triangles  build {r['build_ms_1']:8.1f} ms (1 thread) "
              f"{r['build_ms']:8.1f} ms (all)  render {r['render_ms']:8.1f} ms  {r['nodes_per_ray']:6.1f} nodes/ray",
              flush=True)
    charts = [triangles_chart(rows, size, machine, args.out)]
    print(charts[-1].headline, flush=True)
    charts.append(report_chart(args.rtrender, args.scenes, args.work, machine, args.out,
                               *((160, 120) if args.quick else (800, 600))))
    print(charts[-1].headline, flush=True)
    cluster_size = 128 if args.quick else args.cluster_size
    throughput = scaling_cluster.measure(args.scenes / ("dragon_3.glb" if args.quick else "dragon_1.glb"),
                                         size=cluster_size, repeats=1 if args.quick else 5)
    charts.append(throughput_chart(throughput, machine, args.out))
    print(charts[-1].headline, flush=True)
    model = (" " + (scaling_cluster.__doc__ or "").split("\n\n", 1)[1].replace("\n", " ").replace("  ", " ")
             + " Measured: " + scaling_cluster.model_text(throughput) + ".")
    dask, renders, _ = cluster_model_chart.measure(args.scenes, args.quick, args.out, machine)
    chart, cluster_text = cluster_model_chart.chart(dask, renders, machine, args.out)
    charts.append(chart)
    print(charts[-1].headline, flush=True)
    extra = {"scaling_throughput": model, "scaling_cluster_model": cluster_text}
    for chart in charts:
        write_pages(chart, cluster_model_chart.SUMMARY if chart.slug == "scaling_cluster_model" else summary, machine,
                    args.out, extra.get(chart.slug, ""))
    chart_index.put_section(args.out, charts_pb2.ChartSection(
        key="scaling", title="Scaling", summary=summary + (" Quick mode: a test of the script." if args.quick else ""),
        machine=chart_index.machine_line(machine), charts=charts))
    return 0


if __name__ == "__main__":
    sys.exit(main())
