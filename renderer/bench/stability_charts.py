#!/usr/bin/env python3
"""Stability where methods fail: the measurements of the Stability tests as charts.

Runs stability_table (bench/stability_table.cpp: the same probes as the
ctest Stability suite, whose hard limits keep ours at zero) and draws
- self-intersection against scene scale: the share of wrongly shadowed and of
  wrongly lit pixels for the 2020 report's fixed epsilon (1e-3), for 1e-5 and
  for ours;
- leaks through shared edges and vertices of closed meshes: a plain
  Moller-Trumbore test against ours, one million rays;
- the depth bound: the most rays a camera sample traced between facing mirrors
  and through nested glass against the bound the settings allow, and the time;
  with the count of NaN/Inf pixels over the degenerate cases beside it.
Each chart gets a PNG, a CSV and a Markdown page in --out, and the chart
index's stability section (chart_index.py); --replot redraws the PNGs from
those CSVs without measuring.
"""

from __future__ import annotations

import argparse
import csv
import subprocess
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from rt import charts_pb2  # noqa: E402

import chart_index  # noqa: E402
from accuracy_measure import machine_info  # noqa: E402

METHOD_LABELS = {"eps_1e-3": "fixed epsilon 1e-3 (the 2020 report's)", "eps_1e-5": "fixed epsilon 1e-5",
                 "ours": "ours: offset by the hit's error bound", "moller_trumbore": "Moller-Trumbore",
                 "ours_watertight": "ours: watertight"}
STYLE = {"eps_1e-3": ("o", "#d62728"), "eps_1e-5": ("s", "#ff7f0e"), "ours": ("^", "#2ca02c")}


def read_csv(path: Path) -> list[dict]:
    with path.open() as f:
        return list(csv.DictReader(f))


def self_intersection_chart(rows: list[dict], machine: dict, out: Path) -> charts_pb2.Chart:
    fig, axes = plt.subplots(1, 2, figsize=(12.4, 4.8))
    panels = [("wrongly_shadowed", "wrongly shadowed: lit surfaces (% of hits)"),
              ("wrongly_lit", "wrongly lit: floor under a roof 0.05 x scale above (% of hits)")]
    for ax, (column, title) in zip(axes, panels):
        for method, (marker, colour) in STYLE.items():
            mine = [r for r in rows if r["method"] == method]
            ax.plot([float(r["scale"]) for r in mine], [100 * float(r[column]) for r in mine], marker=marker,
                    color=colour, label=METHOD_LABELS[method], linestyle="-" if method == "ours" else "--")
        ax.set_xscale("log")
        ax.set_xlabel("scene scale (every coordinate times this)")
        ax.set_ylabel("%")
        ax.set_title(title, fontsize=10)
        ax.grid(True, linewidth=0.3, alpha=0.6)
    axes[0].legend(fontsize=8)
    fig.suptitle("Self-intersection against scene scale: where the shadow ray starts")
    chart_index.save_figure(fig, machine, out / "stability_self_intersection.png")

    def worst(method: str, column: str) -> float:
        return max(100 * float(r[column]) for r in rows if r["method"] == method)

    scales = sorted({float(r["scale"]) for r in rows})
    ours_bad = worst("ours", "wrongly_shadowed") + worst("ours", "wrongly_lit")
    headline = (f"Ours: {'no' if ours_bad == 0 else f'{ours_bad:.3g}%'} wrong pixels at every scale from "
                f"{scales[0]:g} to {scales[-1]:g}; the 2020 report's epsilon 1e-3 shadows up to "
                f"{worst('eps_1e-3', 'wrongly_shadowed'):.3g}% of lit pixels at large scales and lights up to "
                f"{worst('eps_1e-3', 'wrongly_lit'):.3g}% of shadowed ones at small scales")
    table = chart_index.table(
        ["method", "worst wrongly shadowed (%)", "worst wrongly lit (%)", "scales with any wrong pixel"],
        [[METHOD_LABELS[m], f"{worst(m, 'wrongly_shadowed'):.3g}", f"{worst(m, 'wrongly_lit'):.3g}",
          ", ".join(f"{float(r['scale']):g}" for r in rows if r["method"] == m
                    and (float(r["wrongly_shadowed"]) > 0 or float(r["wrongly_lit"]) > 0)) or "none"]
         for m in STYLE])
    return charts_pb2.Chart(slug="stability_self_intersection", title="Self-intersection against scene scale",
                            headline=headline, table=table)


def edge_leak_chart(rows: list[dict], machine: dict, out: Path) -> charts_pb2.Chart:
    meshes = list(dict.fromkeys(r["mesh"] for r in rows))
    fig, ax = plt.subplots(figsize=(7.5, 4.8))
    width = 0.38
    for i, (method, colour) in enumerate((("moller_trumbore", "#d62728"), ("ours", "#2ca02c"))):
        leaks = [int(next(r["leaks"] for r in rows if r["mesh"] == m and r["method"] == method)) for m in meshes]
        xs = [j + (i - 0.5) * width for j in range(len(meshes))]
        # A bar of zero has no height on a log axis: its count stands on the axis instead.
        ax.bar(xs, [v if v else float("nan") for v in leaks], width, color=colour,
               label=METHOD_LABELS["ours_watertight" if method == "ours" else method])
        for x, v in zip(xs, leaks):
            ax.annotate(f"{v:,}", (x, max(v, 1)), ha="center", xytext=(0, 3), textcoords="offset points",
                        fontsize=9 if v else 11, color="#000" if v else colour, weight="normal" if v else "bold")
    rays = sum(int(r["rays"]) for r in rows if r["method"] == "ours")
    ax.set_xticks(range(len(meshes)), meshes)
    ax.set_xlim(-0.6, len(meshes) - 0.4)
    ax.set_yscale("log")
    ax.set_ylim(0.7, 20 * max(int(r["leaks"]) for r in rows))
    ax.set_ylabel("rays that passed through the closed mesh")
    ax.set_title(f"{rays:,} rays aimed exactly at edges and vertices, in the renderer's BVH", fontsize=10)
    ax.legend(fontsize=8, loc="upper center", ncols=2)
    fig.suptitle("Leaks through shared edges and vertices")
    chart_index.save_figure(fig, machine, out / "stability_edge_leaks.png")
    ours = sum(int(r["leaks"]) for r in rows if r["method"] == "ours")
    mt = sum(int(r["leaks"]) for r in rows if r["method"] == "moller_trumbore")
    headline = (f"Ours: {ours:,} leaks in {rays:,} rays; Moller-Trumbore lets {mt:,} through "
                f"({100 * mt / rays:.2g}%)")
    table = chart_index.table(["mesh", "rays", "Moller-Trumbore leaks", "ours"],
                              [[m, next(r["rays"] for r in rows if r["mesh"] == m),
                                next(r["leaks"] for r in rows if r["mesh"] == m and r["method"] == "moller_trumbore"),
                                next(r["leaks"] for r in rows if r["mesh"] == m and r["method"] == "ours")]
                               for m in meshes])
    return charts_pb2.Chart(slug="stability_edge_leaks", title="Leaks through shared edges and vertices",
                            headline=headline, table=table)


def depth_chart(depth: list[dict], non_finite: list[dict], machine: dict, out: Path) -> charts_pb2.Chart:
    fig, axes = plt.subplots(1, 3, figsize=(17, 5), gridspec_kw={"width_ratios": (1, 1, 1.15)})
    scenes = list(dict.fromkeys(r["scene"] for r in depth))
    for scene in scenes:
        mine = [r for r in depth if r["scene"] == scene]
        d = [int(r["max_depth"]) for r in mine]
        line, = axes[0].plot(d, [int(r["closest_rays"]) for r in mine], marker="o", label=scene.replace("_", " "))
        axes[0].plot(d, [int(r["bound"]) for r in mine], linestyle=":", color=line.get_color(),
                     label="dotted: the bound its settings allow" if scene == scenes[0] else None)
        axes[1].plot(d, [1000 * float(r["seconds"]) for r in mine], marker="o", color=line.get_color())
    for ax in axes[:2]:
        ax.set_xscale("log", base=2)
        ax.set_yscale("log")
        ax.set_xlabel("max_depth (min_contribution 0.001)")
        ax.grid(True, which="both", linewidth=0.3, alpha=0.6)
    axes[0].set_ylabel("closest-hit rays of one camera sample (the most)")
    axes[0].legend(fontsize=7)
    axes[1].set_ylabel("ms for the 16x16 image on one thread")
    groups: dict[str, list[int]] = {}
    for r in non_finite:
        group = "scales 1e-30..1e30" if r["case"].startswith(("scale_", "size_")) else r["case"].replace("_", " ")
        counts = groups.setdefault(group, [0, 0])
        counts[0] += int(r["pixels"])
        counts[1] += int(r["non_finite"])
    names = list(groups)
    axes[2].barh(names, [groups[n][0] for n in names], color="#9ecae1", label="pixels rendered")
    axes[2].barh(names, [groups[n][1] for n in names], color="#d62728", label="NaN or Inf pixels")
    for i, n in enumerate(names):
        axes[2].annotate(f"{groups[n][1]} of {groups[n][0]:,}", (1, i), xytext=(4, -3),
                         textcoords="offset points", fontsize=8)
    axes[2].set_xscale("log")
    axes[2].set_xlim(1, 30 * max(g[0] for g in groups.values()))
    axes[2].invert_yaxis()
    axes[2].set_xlabel("pixels")
    axes[2].legend(fontsize=7, loc="upper right")
    axes[2].set_title("no NaN or Inf reaches a pixel", fontsize=10)
    fig.suptitle("Two facing mirrors and glass in glass stop at the depth limit; degenerate input stays finite")
    chart_index.save_figure(fig, machine, out / "stability_depth_bound.png")
    deepest = max(int(r["max_depth"]) for r in depth)
    worst = max((r for r in depth if int(r["max_depth"]) == deepest), key=lambda r: float(r["seconds"]))
    over = [r for r in depth if int(r["closest_rays"]) > int(r["bound"])]
    bad = sum(int(r["non_finite"]) for r in non_finite)
    pixels = sum(int(r["pixels"]) for r in non_finite)
    headline = (f"Every path stops within its bound ({len(over)} over); at max_depth {deepest} the worst scene "
                f"({worst['scene'].replace('_', ' ')}) traces at most {int(worst['closest_rays']):,} rays per "
                f"camera sample and takes {1000 * float(worst['seconds']):.3g} ms for 256 pixels; {bad} NaN or Inf "
                f"pixels in {pixels:,} over {len(non_finite)} degenerate cases")
    table = chart_index.table(["scene", "max_depth", "most rays per sample", "bound", "ms (16x16, 1 thread)"],
                              [[r["scene"].replace("_", " "), r["max_depth"], r["closest_rays"], r["bound"],
                                f"{1000 * float(r['seconds']):.3g}"]
                               for r in depth if int(r["max_depth"]) in (1, 8, deepest)])
    return charts_pb2.Chart(slug="stability_depth_bound", title="Depth bound and non-finite pixels",
                            headline=headline, table=table)


def write_pages(chart: charts_pb2.Chart, csv_sources: list[Path], summary: str, machine: dict, out: Path) -> None:
    """<slug>.csv (the table's rows joined from the sources) and <slug>.md."""
    with (out / f"{chart.slug}.csv").open("w", newline="") as f:
        for i, source in enumerate(csv_sources):
            if i:
                f.write("\n")
            f.write(source.read_text())
    lines = [f"# {chart.title}", "", f"![{chart.title}]({chart.slug}.png)", "", f"**{chart.headline}**.", "",
             summary, "", f"Machine: {chart_index.machine_line(machine)}.", ""]
    for source in csv_sources:
        rows = read_csv(source)
        table = chart_index.table(list(rows[0]), [list(r.values()) for r in rows])
        lines += [f"## {source.stem.replace('_', ' ')}", "", *chart_index.markdown_table(table), ""]
    (out / f"{chart.slug}.md").write_text("\n".join(lines))


def replot(out: Path, only: str) -> None:
    """Redraws the charts' PNGs from the CSVs write_pages left in `out` (the
    depth chart's holds two tables, a blank line apart), with the foot of the
    run that measured them."""
    def tables(slug: str) -> list[list[dict]]:
        text = (out / f"{slug}.csv").read_text()
        return [list(csv.DictReader(part.strip("\n").splitlines())) for part in text.split("\n\n")]

    section = next(s for s in chart_index.read_index(out).sections if s.key == "stability")
    machine = chart_index.machine_from_line(section.machine)
    draw = {"stability_self_intersection": lambda: self_intersection_chart(tables("stability_self_intersection")[0],
                                                                           machine, out),
            "stability_edge_leaks": lambda: edge_leak_chart(tables("stability_edge_leaks")[0], machine, out),
            "stability_depth_bound": lambda: depth_chart(*tables("stability_depth_bound"), machine, out)}
    for slug, redraw in draw.items():
        if only in slug:
            redraw()
            print(f"redrew {slug}.png from {slug}.csv")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--table", type=Path, default=Path("build/renderer/stability_table"),
                        help="the stability_table program (make build)")
    parser.add_argument("--out", type=Path, default=Path("docs/charts"))
    parser.add_argument("--cache", type=Path, default=Path("build/charts/stability"), help="its CSV output")
    parser.add_argument("--replot", action="store_true",
                        help="only redraw the PNGs in --out from their CSVs there (no measuring)")
    parser.add_argument("--only", default="", help="with --replot: only the charts whose name contains this")
    args = parser.parse_args()
    if args.replot:
        replot(args.out, args.only)
        return 0
    if not args.table.exists():
        sys.exit(f"stability_charts: no {args.table}: run `make build`")
    machine = machine_info()
    args.cache.mkdir(parents=True, exist_ok=True)
    args.out.mkdir(parents=True, exist_ok=True)
    result = subprocess.run([str(args.table), "--out", str(args.cache)], capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"stability_charts: stability_table failed: {result.stderr.strip()}")
    tables = {name: args.cache / f"{name}.csv" for name in
              ("self_intersection", "edge_leaks", "non_finite", "depth_bound")}
    summary = ("Measured by bench/stability_table.cpp with the probes of the ctest Stability suite, whose hard "
               "limits hold ours at zero: the renderer's own BVH and shading, the scenes built in "
               "tests/stability_scenes.h.")
    charts = [
        (self_intersection_chart(read_csv(tables["self_intersection"]), machine, args.out),
         [tables["self_intersection"]]),
        (edge_leak_chart(read_csv(tables["edge_leaks"]), machine, args.out), [tables["edge_leaks"]]),
        (depth_chart(read_csv(tables["depth_bound"]), read_csv(tables["non_finite"]), machine, args.out),
         [tables["depth_bound"], tables["non_finite"]]),
    ]
    for chart, sources in charts:
        write_pages(chart, sources, summary, machine, args.out)
        print(f"{chart.slug}: {chart.headline}")
    chart_index.put_section(args.out, charts_pb2.ChartSection(
        key="stability", title="Stability where methods fail", summary=summary,
        machine=chart_index.machine_line(machine), charts=[c for c, _ in charts]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
