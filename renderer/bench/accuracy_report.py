"""What speed_accuracy.py writes: per chart a PNG (log-log error against
time, one curve per method), a CSV and a Markdown table; and README.md listing
the chart index's section (chart_index.py) with each chart's headline and key figures."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib import ticker  # noqa: E402
from rt import charts_pb2  # noqa: E402

import chart_index  # noqa: E402

MARKERS = ["o", "s", "^", "D", "v", "P"]
METRICS = [("rmse", "RMSE (linear radiance)"), ("flip", "mean FLIP (HDR)")]
TIME_AXIS = "render time (s, wall clock, all cores)"
DEFAULTS = ("everything else at its default: max_depth 5, min_contribution 0.001, light_samples 16, "
            "samples_per_pixel 1, Gaussian filter, cone light sampling, time-sampled motion blur")
CSV_FIELDS = ["chart", "scene", "method", "label", "point", "time_s", "renders_timed", "rmse", "flip", "mean_spp",
              "reference", "settings", "cpu", "cores", "commit", "date"]


def _short(point: str) -> str:
    for prefix in ("N=", "K=", "depth "):
        if point.startswith(prefix):
            return point[len(prefix):]
    return point


def time_to_reach(points: list[tuple[float, float]], target: float) -> tuple[float | None, str]:
    """When a curve of (time, error) points first reaches `target`,
    interpolated on log-log axes: (seconds, '') or (its first time, '<=') when
    even its cheapest point is better, (None, '>') when it never gets there."""
    points = sorted(points)
    for i, (t, e) in enumerate(points):
        if e <= target:
            if i == 0:
                return t, "<="
            t0, e0 = points[i - 1]
            if e <= 0 or target <= 0:
                return t, ""
            f = (math.log(target) - math.log(e0)) / (math.log(e) - math.log(e0))
            return math.exp(math.log(t0) + f * (math.log(t) - math.log(t0))), ""
    return None, ">"


def _curves(result: dict):
    """(method, reference key, its rows in the order of its points, main):
    one curve per method and reference it is measured against (its own first)."""
    for method in result["chart"].methods:
        for i, against in enumerate(method.references):
            rows = [r for r in result["rows"] if r["method"] == method.key and r["reference"] == against]
            if rows:
                yield method, against, rows, i == 0


def equal_error(result: dict) -> list[dict]:
    """For each curve measured against the same reference as the 2020
    report's default, the time it needs to reach that default's error."""
    chart = result["chart"]
    if not chart.report:
        return []
    method, point = chart.report
    against = next(m.references[0] for m in chart.methods if m.key == method)
    report = next((r for r in result["rows"] if r["method"] == method and r["point"] == point
                   and r["reference"] == against), None)
    if report is None:
        return []
    table = []
    for m, curve_reference, rows, _ in _curves(result):
        if curve_reference != against:
            continue
        entry = {"report": report, "method": m.key, "label": m.label}
        for metric, _ in METRICS:
            seconds, how = time_to_reach([(r["time_s"], r[metric]) for r in rows], report[metric])
            entry[metric] = (seconds, how, report["time_s"] / seconds if seconds else None)
        table.append(entry)
    return table


def error_at(points: list[tuple[float, float]], seconds: float) -> float | None:
    """A curve's error at `seconds`, interpolated on log-log axes; None
    outside the times it was measured at."""
    points = sorted(points)
    for (t0, e0), (t1, e1) in zip(points, points[1:]):
        if t0 <= seconds <= t1 and min(e0, e1) > 0:
            f = (math.log(seconds) - math.log(t0)) / (math.log(t1) - math.log(t0)) if t1 > t0 else 0.0
            return math.exp(math.log(e0) + f * (math.log(e1) - math.log(e0)))
    return None


def equal_time(result: dict) -> tuple[float, list[tuple[str, float]]] | None:
    """The longest time every curve compared with the 2020 report's default reaches,
    and each one's RMSE there: where a method stalls at a bias (the frames'
    aliasing) or keeps converging shows at equal time, not at equal error."""
    table = equal_error(result)
    if not table:
        return None
    curves = [(m, rows) for m, against, rows, _ in _curves(result)
              if against == table[0]["report"]["reference"] and m.key in {e["method"] for e in table}]
    seconds = min(max(r["time_s"] for r in rows) for _, rows in curves)
    at = [(m.label.split(":")[0], error_at([(r["time_s"], r["rmse"]) for r in rows], seconds)) for m, rows in curves]
    return seconds, [(label, e) for label, e in at if e is not None]


def _reach_text(seconds: float | None, how: str, speedup: float | None) -> str:
    if seconds is None:
        return "not reached"
    return f"{how}{seconds:.3g} s ({speedup:.2g}x)"


def headline(result: dict) -> str:
    chart = result["chart"]
    if chart.depth:
        s = result["saving"]
        rows = {(r["method"], r["point"]): r for r in result["rows"]}
        cut = rows.get((chart.methods[0].key, f"depth {s['depth']}"))
        off = rows.get((chart.methods[1].key, f"depth {s['depth']}"))
        errors = (f"; RMSE at depth {s['depth']}: {cut['rmse']:.3g} with the cutoff, {off['rmse']:.3g} without"
                  if cut and off else "")
        return (f"the cutoff {s['cutoff']:g} saves {s['saved_percent']:.0f}% of the time at depth {s['depth']} "
                f"({s['time_with_s']:.3g} s against {s['time_without_s']:.3g} s; the 2020 report claimed a third)"
                f"{errors}")
    table = equal_error(result)
    if not table:
        return ""
    report = table[0]["report"]
    name = next(m.label for m in chart.methods if m.key == report["method"]).split(":")[0]
    others = [f"{e['label'].split(':')[0]} {_reach_text(*e['rmse'])}" for e in table
              if e["method"] != report["method"]]
    line = (f"the 2020 report's default, {name.removesuffix(' (2020 report)')} {report['point']}, has RMSE "
            f"{report['rmse']:.3g} in {report['time_s']:.3g} s; time to the same RMSE: " + ", ".join(others))
    same_time = equal_time(result)
    if same_time and len(same_time[1]) > 1:
        seconds, errors = same_time
        line += f"; RMSE in {seconds:.3g} s: " + ", ".join(f"{label} {e:.3g}" for label, e in errors)
    return line


# Errors below this are rounding: a float32 image equal to its reference.
EXACT = 1e-9


def _plot_errors(ax, result: dict, metric: str, axis_label: str) -> None:
    chart, rows = result["chart"], result["rows"]
    positive = [r[metric] for r in rows if r[metric] > EXACT]
    floor = min(positive) / 3 if positive else 1e-6
    colours = {}
    if len(positive) < len(rows):
        ax.text(0.01, 0.01, "\u25bc error 0: the reference's own image", transform=ax.transAxes, fontsize=7,
                color="#555")
    for method, against, mine, main in _curves(result):
        index = [m.key for m in chart.methods].index(method.key)
        label = method.label + (f"\n  vs {chart.references[against].what}" if len(chart.references) > 1 else "")
        times = [r["time_s"] for r in mine]
        errors = [r[metric] if r[metric] > EXACT else floor for r in mine]
        line, = ax.plot(times, errors, marker=MARKERS[index % len(MARKERS)], markersize=5, label=label,
                        linestyle="-" if main else "--", color=colours.get(method.key))
        colours[method.key] = line.get_color()
        exact = [(t, e) for t, e, r in zip(times, errors, mine) if r[metric] <= EXACT]
        if exact:
            ax.plot(*zip(*exact), linestyle="none", marker="v", markersize=9, color=line.get_color())
        for t, e, r in zip(times, errors, mine):
            ax.annotate(_short(r["point"]), (t, e), textcoords="offset points", xytext=(4, 3), fontsize=6.5,
                        color=line.get_color())
    ax.set_xscale("log")
    ax.set_yscale("log")
    for axis in (ax.xaxis, ax.yaxis):
        # Labels at 1, 2 and 5 times each power of ten: a curve may span less than a decade.
        axis.set_major_locator(ticker.LogLocator(subs=(1.0, 2.0, 5.0)))
        axis.set_major_formatter(ticker.FuncFormatter(lambda v, _: f"{v:g}"))
        axis.set_minor_formatter(ticker.NullFormatter())
    ax.set_xlabel(TIME_AXIS)
    ax.set_ylabel(axis_label)
    ax.grid(True, which="both", linewidth=0.3, alpha=0.6)


def _plot_depth_times(ax, result: dict) -> None:
    chart = result["chart"]
    for i, method in enumerate(chart.methods):
        mine = [r for r in result["rows"] if r["method"] == method.key]
        depths = [r["settings"]["max_depth"] for r in mine]
        ax.plot(depths, [r["time_s"] * 1000 for r in mine], marker=MARKERS[i], markersize=5, label=method.label)
    ax.set_xlabel("max_depth (reflection rays after the primary)")
    ax.set_ylabel("render time (ms, wall clock, all cores)")
    ax.set_ylim(bottom=0)
    ax.grid(True, linewidth=0.3, alpha=0.6)
    s = result["saving"]
    ax.set_title(f"cutoff saves {s['saved_percent']:.0f}% at depth {s['depth']} ({s['pairs']} interleaved pairs)",
                 fontsize=9)


def plot(result: dict, machine: dict, budget, path: Path) -> None:
    """The chart's PNG: error against time, RMSE and FLIP (and time against depth)."""
    chart = result["chart"]
    panels = 3 if chart.depth else 2
    fig, axes = plt.subplots(1, panels, figsize=(6.2 * panels, 5.2))
    for ax, (metric, label) in zip(axes, METRICS):
        _plot_errors(ax, result, metric, label)
    if chart.depth:
        _plot_depth_times(axes[2], result)
    axes[0].legend(fontsize=7, loc="best")
    fig.suptitle(f"{chart.effect}: {chart.scene.label}, {budget.width}x{budget.height}")
    chart_index.save_figure(fig, machine, path, "; time: median of up to 5 renders (about 1 s)")


def _fmt(value: float) -> str:
    return "0 (exact)" if value == 0 else f"{value:.4g}"


def _write_csv(result: dict, machine: dict, path: Path) -> None:
    with path.open("w", newline="") as f:
        writer = csv.DictWriter(f, CSV_FIELDS)
        writer.writeheader()
        for row in result["rows"]:
            writer.writerow({**{k: row[k] for k in CSV_FIELDS if k in row},
                             "time_s": f"{row['time_s']:.6f}", "rmse": f"{row['rmse']:.6g}",
                             "flip": f"{row['flip']:.6g}", "settings": json.dumps(row["settings"]),
                             **{k: machine[k] for k in ("cpu", "cores", "commit", "date")}})


def _markdown(result: dict, machine: dict, budget, line: str) -> str:
    chart = result["chart"]
    slug = chart.slug
    out = [f"# {chart.effect}: {chart.scene.label}, {budget.width}x{budget.height}", "",
           f"![{chart.effect}: error against render time]({slug}.png)", "",
           f"Scene: {chart.scene_note}.", "",
           f"Machine: {chart_index.machine_line(machine)}. Time: median wall time of `Scene.render` on every core "
           f"(tile 32), short renders repeated until about a second is spent (at most 5 renders). Error: RMSE "
           f"of the linear image and mean HDR-FLIP against a converged reference (the References table says "
           f"which one each curve is measured against).", "",
           f"Settings: {json.dumps(chart.base)}, {DEFAULTS}, except as each point says (the CSV has every "
           f"point's settings).", ""]
    if line:
        out += [f"**Headline**: {line}.", ""]
    out += [f"- {note}" for note in chart.notes] + [""]
    if chart.report:
        out += ["## Time to the 2020 report's default error", "",
                "| method | to the same RMSE (speed-up) | to the same FLIP (speed-up) |", "| --- | --- | --- |"]
        for e in equal_error(result):
            out.append(f"| {e['label']} | {_reach_text(*e['rmse'])} | {_reach_text(*e['flip'])} |")
        others = sorted({m.label for m, against, _, _ in _curves(result)} - {e["label"] for e in equal_error(result)})
        out += ["", "`<=`: already at the cheapest point measured, which is better. Only the curves measured "
                "against the same reference as the 2020 report's default are compared"
                + (f"; left out: {'; '.join(others)}" if others else "") + ".", ""]
    adaptive = any(m.adaptive for m in chart.methods)
    out += ["## Points", "", "| method | point | time (s) | renders timed | RMSE | FLIP |"
            + (" mean spp |" if adaptive else "") + " reference |",
            "| --- | --- | ---: | ---: | ---: | ---: |" + (" ---: |" if adaptive else "") + " --- |"]
    for r in result["rows"]:
        out.append(f"| {r['label']} | {r['point']} | {r['time_s']:.4g} | {r['renders_timed']} | {_fmt(r['rmse'])} | "
                   f"{_fmt(r['flip'])} |" + (f" {r['mean_spp']} |" if adaptive else "") + f" {r['reference']} |")
    out += ["", "## References", "", "| reference | what | render time (s) |", "| --- | --- | ---: |"]
    for r in result["references"]:
        out.append(f"| {r['reference']} | {r['what']} | {r['seconds']:.1f} |")
    if result["checks"]:
        out += ["", "## Do the methods converge to the same image?", "",
                "| converged render | against | RMSE | FLIP | what it says |", "| --- | --- | ---: | ---: | --- |"]
        for c in result["checks"]:
            out.append(f"| {c['what']} | {c['reference']} | {_fmt(c['rmse'])} | {_fmt(c['flip'])} | {c['note']} |")
    if chart.depth:
        s = result["saving"]
        out += ["", "## Time the cutoff saves", "",
                f"At max_depth {s['depth']}, min_contribution {s['cutoff']:g} against 0: median of {s['pairs']} "
                f"interleaved pairs, {s['time_with_s']:.4g} s against {s['time_without_s']:.4g} s: "
                f"**{s['saved_percent']:.1f}% saved** (the 2020 report claimed a third)."]
    return "\n".join(out) + "\n"


def write_chart(result: dict, machine: dict, budget, out: Path) -> str:
    """<slug>.png, .csv and .md in `out`; returns the headline."""
    slug = result["chart"].slug
    line = headline(result)
    plot(result, machine, budget, out / f"{slug}.png")
    _write_csv(result, machine, out / f"{slug}.csv")
    (out / f"{slug}.md").write_text(_markdown(result, machine, budget, line))
    return line


def _key_figures(result: dict):
    """The chart's table on the Charts page: time to the 2020 report's error for
    each method, or for the depth charts time and error at each depth."""
    chart = result["chart"]
    if chart.depth:
        by_depth: dict[int, dict[str, dict]] = {}
        for r in result["rows"]:
            by_depth.setdefault(r["settings"]["max_depth"], {})[r["method"]] = r
        cut, off = (m.key for m in chart.methods)
        return chart_index.table(
            ["max_depth", "time with the cutoff (s)", "RMSE with the cutoff", "time without (s)", "RMSE without"],
            [[d, f"{rows[cut]['time_s']:.3g}", _fmt(rows[cut]["rmse"]), f"{rows[off]['time_s']:.3g}",
              _fmt(rows[off]["rmse"])] for d, rows in sorted(by_depth.items()) if cut in rows and off in rows])
    table = equal_error(result)
    if not table:
        return chart_index.table([], [])
    report = table[0]["report"]
    seconds, errors = equal_time(result)
    at = dict(errors)
    return chart_index.table(
        ["method", f"time to RMSE {report['rmse']:.3g} (speed-up)", f"time to FLIP {report['flip']:.3g} (speed-up)",
         f"RMSE in {seconds:.3g} s"],
        [[e["label"], _reach_text(*e["rmse"]), _reach_text(*e["flip"]),
          f"{at[e['label'].split(':')[0]]:.3g}" if e["label"].split(":")[0] in at else "-"] for e in table])


def section(results: list[dict], machine: dict, budget, quick: bool) -> charts_pb2.ChartSection:
    """The speed-against-accuracy section of the chart index."""
    summary = ("For each sampled effect, the error of each method against a converged reference (many samples) "
               "versus its render time, log-log, as RMSE and as mean HDR-FLIP; then what max_depth and the "
               "min_contribution cutoff trade. The tables give the time each method needs to reach the error of "
               "the 2020 report's default (speed-up against it), and each one's error at the longest time all of them "
               "were measured at, where a method that stalls at a bias shows. "
               f"Images {budget.width}x{budget.height}; run {machine['run_minutes']} min; "
               "made by renderer/bench/speed_accuracy.py."
               + (" Quick mode: tiny images, few points: a test of the script, not a measurement." if quick else ""))
    charts = [charts_pb2.Chart(slug=r["chart"].slug,
                               title=f"{r['chart'].effect}: {r['chart'].scene.label}",
                               headline=r["headline"][:1].upper() + r["headline"][1:],
                               table=_key_figures(r)) for r in results]
    return charts_pb2.ChartSection(key="speed_accuracy", title="Speed against accuracy", summary=summary,
                                   machine=chart_index.machine_line(machine), charts=charts)
