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
(cluster_model.py) projects a 3840x2160 dragon onto 1 to 64 workers of 8
threads from Dask's and the renderer's costs measured here, with the tile plan
before and after its scheduler limit. Writes scaling_triangles,
scaling_report_table, scaling_throughput and scaling_cluster_model (PNG, CSV,
Markdown) into --out and the chart index's scaling section (--only
cluster_model: that chart alone, the others kept).
"""

from __future__ import annotations

import argparse
import contextlib
import csv
import dataclasses
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
import cluster_model  # noqa: E402
import dask_costs  # noqa: E402
import report_table  # noqa: E402
import scaling_cluster  # noqa: E402
import tile_costs  # noqa: E402
from accuracy_measure import machine_info  # noqa: E402
from app.services import tile_plan  # noqa: E402  (scaling_cluster puts server/ on the path)
from app.services.tile_plan import TILES_PER_THREAD  # noqa: E402

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


# The jobs the cluster model projects: the viewer's default (one sample, an
# interactive job) and a final render (the README's anti-aliasing example, 16
# samples, as a batch job).
MODEL_JOBS = (("1 spp, interactive", 1, True), ("16 spp, batch", 16, False))
MODEL_SIZE = (3840, 2160)


@contextlib.contextmanager
def plan_before_scheduler_limit():
    """tile_plan as it was before the scheduler limit (issue 18): tiles
    counted per thread only."""
    saved = tile_plan.TASK_RAYS_PER_THREAD
    tile_plan.TASK_RAYS_PER_THREAD = 0
    try:
        yield
    finally:
        tile_plan.TASK_RAYS_PER_THREAD = saved


def measure_cluster_model(scenes: Path, quick: bool) -> tuple[dask_costs.DaskCosts, list[tile_costs.RenderCosts]]:
    """Dask's costs on a real scheduler and the dragon's render costs for each
    modelled job (quick: few tasks, small images read as if full size)."""
    dask = dask_costs.measure((1,), tasks=100, repeats=1, large=128) if quick else dask_costs.measure()
    scene = scenes / ("dragon_3.glb" if quick else "dragon_1.glb")
    renders = [tile_costs.measure(scene, *MODEL_SIZE, samples=samples, repeats=1 if quick else 3,
                                  scale=(16 if samples == 1 else 32) if quick else (1 if samples == 1 else 4))
               for _, samples, _ in MODEL_JOBS]
    return dask, renders


def model_costs(dask: dask_costs.DaskCosts, render: tile_costs.RenderCosts,
                interactive: bool) -> cluster_model.ClusterCosts:
    return cluster_model.ClusterCosts(
        width=render.width, height=render.height, pixel_rays=render.pixel_rays, interactive=interactive,
        pixel_s=render.pixel_s.median, tile_s=render.tile_s.median + dask.worker_s[min(dask.worker_s)].median,
        encode_s_per_pixel=render.encode_s_per_pixel, preview_factor=render.preview_factor,
        scheduler_s={n: s.median for n, s in dask.scheduler_s.items()}, server_s=dask.server_s.median,
        server_s_per_byte=dask.server_s_per_byte, latency_s=dask.latency_s.median,
        threads_per_worker=dask_costs.THREADS_PER_WORKER, cost_map=render.cost_map, cell=render.cell)


def measured_inputs_text(dask: dask_costs.DaskCosts, renders: list[tile_costs.RenderCosts]) -> str:
    """The measured inputs, medians and ranges, for the chart's page."""
    sched = "; ".join(f"{n} worker{'s' * (n > 1)}: {s.text(1e6, 'us')}" for n, s in dask.scheduler_s.items())
    work = "; ".join(f"{n}: {s.text(1e6, 'us')}" for n, s in dask.worker_s.items())
    lines = [f"Dask scheduler CPU per task (jobs of {dask.tasks} no-op tasks, median (range)): {sched}.",
             f"Server CPU per result: {dask.server_small_s.text(1e6, 'us')} with a {dask.small_side}x"
             f"{dask.small_side} tile's message, {dask.server_large_s.text(1e6, 'us')} with a {dask.large_side}x"
             f"{dask.large_side} one: {dask.server_s.median * 1e6:.0f} us + {dask.server_s_per_byte * 1e9:.2f} ns "
             f"per message byte.",
             f"Workers' CPU per task, summed over the workers (idle workers' upkeep included): {work}.",
             f"A one-task job's latency: {dask.latency_s.text(1e3, 'ms')}."]
    for (label, samples, _), r in zip(MODEL_JOBS, renders):
        size = f"{r.width // r.measured_scale}x{r.height // r.measured_scale}"
        lines.append(f"{r.scene}, {label} ({r.pixel_rays:g} rays a pixel), rendered at {size} on one thread: "
                     f"{r.pixel_s.text(1e9, 'ns')} of CPU per pixel, {r.render_s.text(1, 's')} per image; a "
                     f"preview pixel {r.preview_factor:.2f}x a full one; a 1x1 tile {r.tile_s.text(1e3, 'ms')}; "
                     f"sRGB encoding {r.encode_s_per_pixel * 1e9:.1f} ns per pixel; cost map of "
                     f"{r.cost_map.shape[1]}x{r.cost_map.shape[0]} cells from {r.cost_map.min():.2f} to "
                     f"{r.cost_map.max():.2f} times the mean.")
    return " ".join(lines)


def cluster_model_chart(dask: dask_costs.DaskCosts, renders: list[tile_costs.RenderCosts], machine: dict,
                        out: Path) -> tuple[charts_pb2.Chart, str]:
    width, height = MODEL_SIZE
    fig, axes = plt.subplots(1, 2, figsize=(13, 5))
    counts = list(cluster_model.WORKER_COUNTS)
    axes[0].plot(counts, counts, linestyle=":", color="#999", label="ideal")
    axes[1].plot(counts, [100] * len(counts), linestyle=":", color="#999", label="ideal")
    axes[1].axhline(80, color="#d62728", linewidth=0.6, alpha=0.6)
    rows, results = [], {}
    for (label, _, interactive), render, color in zip(MODEL_JOBS, renders, ("#1f77b4", "#2ca02c")):
        costs = model_costs(dask, render, interactive)
        with plan_before_scheduler_limit():
            before = cluster_model.scaling(costs)
        after = cluster_model.scaling(costs)
        # What the same plan would give if each worker took its next tile only
        # when free, instead of Dask starting as many as it has threads at once.
        one_at_a_time = cluster_model.scaling(dataclasses.replace(costs, slots_per_worker=1))
        results[label] = (before, after, one_at_a_time)
        for plan, found, style in (("before", before, "--"), ("after", after, "-"),
                                   ("after, a tile a worker at a time", one_at_a_time, ":")):
            name = f"{label}, plan {plan}"
            axes[0].plot(counts, [r.speedup for r in found], linestyle=style, marker="o", markersize=4,
                         color=color, label=name)
            axes[1].plot(counts, [100 * r.efficiency for r in found], linestyle=style, marker="o", markersize=4,
                         color=color, label=name)
            rows += [[label, plan, *cells] for cells in cluster_model.table_rows(found)]
    for ax, what in ((axes[0], "speed-up against one worker"), (axes[1], "efficiency (%)")):
        ax.set_xscale("log", base=2)
        ax.set_xlabel("workers of 8 threads")
        ax.set_ylabel(what)
        ax.grid(True, which="both", linewidth=0.3, alpha=0.6)
        ax.legend(fontsize=7)
    axes[0].set_yscale("log", base=2)
    axes[1].set_ylim(0, 110)
    axes[0].set_title(f"{renders[0].scene}, {width}x{height}: modelled from Dask's and the renderer's costs "
                      "measured here", fontsize=8)
    axes[1].set_title("before: 2 tiles a thread; after: the scheduler's limit; dotted: a tile a worker at a time",
                      fontsize=8)
    fig.suptitle("Cluster scale on paper: a 4K dragon on 1 to 64 Dask workers")
    chart_index.save_figure(fig, machine, out / "scaling_cluster_model.png")

    def at(label: str, workers: int) -> list[cluster_model.Row]:
        return [next(r for r in found if r.modelled.workers == workers) for found in results[label]]

    final, default = MODEL_JOBS[1][0], MODEL_JOBS[0][0]
    (fb, fa, fo), (db, da, _) = at(final, 32), at(default, 32)
    headline = (f"At 32 workers of 8 threads a {width}x{height} {renders[1].scene} at {final} runs at "
                f"{100 * fb.efficiency:.0f}% efficiency with the old plan ({fb.modelled.tiles} tiles of "
                f"{fb.modelled.tile_side}, {fb.modelled.bound}-bound) and {100 * fa.efficiency:.0f}% with the new "
                f"({fa.modelled.tiles} tiles of {fa.modelled.tile_side}, {fa.modelled.bound}-bound: Dask starts "
                f"8 tiles on each worker at once, so the last round is uneven), {100 * fo.efficiency:.0f}% if workers took a tile at a time; "
                f"at {default} {100 * db.efficiency:.0f}% -> {100 * da.efficiency:.0f}% ({da.modelled.bound}-bound: "
                f"{renders[0].pixel_s.median * width * height / 256 * 1e3:.0f} ms of rendering per thread)")
    table = chart_index.table(["job", "plan", *cluster_model.TABLE_COLUMNS], rows)
    chart = charts_pb2.Chart(slug="scaling_cluster_model", title="Cluster scale on paper: a 4K dragon on 1 to 64 "
                             "Dask workers", headline=headline, table=table)
    text = (" " + (cluster_model.__doc__ or "").split("\n\n", 1)[0].replace("\n", " ") + " Measured inputs: "
            + measured_inputs_text(dask, renders)
            + " The before plan is tile_plan.py with TASK_RAYS_PER_THREAD 0 (no scheduler limit).")
    return chart, text


# The cluster model's page: its inputs are CPU times, not the section's wall clock.
CLUSTER_MODEL_SUMMARY = ("Modelled by renderer/bench/cluster_model.py from costs measured by dask_costs.py and "
                         "tile_costs.py in CPU seconds of each process (steadier than wall time on shared cores), "
                         "medians of 3 runs with their ranges.")


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
        chart, text = cluster_model_chart(*measure_cluster_model(args.scenes, args.quick), machine, args.out)
        print(chart.headline, flush=True)
        write_pages(chart, CLUSTER_MODEL_SUMMARY, machine, args.out, text)
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
    chart, cluster_text = cluster_model_chart(*measure_cluster_model(args.scenes, args.quick), machine, args.out)
    charts.append(chart)
    print(charts[-1].headline, flush=True)
    extra = {"scaling_throughput": model, "scaling_cluster_model": cluster_text}
    for chart in charts:
        write_pages(chart, CLUSTER_MODEL_SUMMARY if chart.slug == "scaling_cluster_model" else summary, machine,
                    args.out, extra.get(chart.slug, ""))
    chart_index.put_section(args.out, charts_pb2.ChartSection(
        key="scaling", title="Scaling", summary=summary + (" Quick mode: a test of the script." if args.quick else ""),
        machine=chart_index.machine_line(machine), charts=charts))
    return 0


if __name__ == "__main__":
    sys.exit(main())
