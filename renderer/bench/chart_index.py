"""docs/charts/index.json (an rt.ChartIndex) and the README.md made from it.

Each chart script of `make charts` puts its section into the index, replacing
the one it wrote before, so that the scripts can run alone; the README then
lists every section's charts with their headlines. The viewer's Charts page
reads the same index.
"""

from __future__ import annotations

import re
from pathlib import Path

from google.protobuf import json_format
from rt import charts_pb2

INDEX = "index.json"
# Sections in the order a reader wants them, whichever script ran last.
ORDER = ("speed_accuracy", "stability", "scaling")


def table(columns: list[str], rows: list[list[object]]) -> charts_pb2.ChartTable:
    return charts_pb2.ChartTable(columns=columns,
                                 rows=[charts_pb2.ChartRow(cells=[str(c) for c in row]) for row in rows])


def machine_line(machine: dict) -> str:
    return (f"{machine['cpu']}, {machine['cores']} cores; {machine['date']}; commit {machine['commit']}; "
            f"load average at start {machine['load_average']}")


def machine_from_line(line: str) -> dict:
    """The machine a section's `machine` line names (the inverse of
    machine_line), so that a chart redrawn from its CSV keeps the foot it had."""
    match = re.fullmatch(r"(?P<cpu>.*), (?P<cores>\d+) cores; (?P<date>[^;]*); commit (?P<commit>[^;]*); "
                         r"load average at start (?P<load_average>.*)", line)
    if not match:
        raise ValueError(f"chart_index: not a machine line: {line!r}")
    return match.groupdict()


def save_figure(fig, machine: dict, path: Path, note: str = "") -> None:
    """Writes a chart's PNG with the machine line (and `note`) along its foot,
    as every chart carries where its numbers come from."""
    import matplotlib.pyplot as plt

    fig.text(0.5, 0.005, machine_line(machine) + note, ha="center", fontsize=7, color="#555")
    fig.tight_layout(rect=(0, 0.03, 1, 1))
    fig.savefig(path, dpi=110)
    plt.close(fig)


def read_index(out: Path) -> charts_pb2.ChartIndex:
    index = charts_pb2.ChartIndex()
    if (out / INDEX).exists():
        json_format.Parse((out / INDEX).read_text(), index)
    return index


def put_section(out: Path, section: charts_pb2.ChartSection) -> None:
    """Writes `section` into out/index.json (in place of its earlier run) and
    rewrites out/README.md from the whole index."""
    index = read_index(out)
    sections = [s for s in index.sections if s.key != section.key] + [section]
    sections.sort(key=lambda s: ORDER.index(s.key) if s.key in ORDER else len(ORDER))
    index = charts_pb2.ChartIndex(sections=sections)
    out.mkdir(parents=True, exist_ok=True)
    (out / INDEX).write_text(json_format.MessageToJson(index, indent=1) + "\n")
    (out / "README.md").write_text(readme(index))


def markdown_table(t: charts_pb2.ChartTable) -> list[str]:
    def row(cells) -> str:
        return "| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |"
    return [row(t.columns), row(["---"] * len(t.columns)), *(row(r.cells) for r in t.rows)]


def readme(index: charts_pb2.ChartIndex) -> str:
    lines = ["# Charts", "",
             "Measured by `make charts` (on a quiet machine: times are wall clock on every core); the viewer shows "
             "the same at /charts. Each chart has a PNG, a CSV with every point and a Markdown page beside it. "
             "The methods marked \"2020 report\" are those of the ray tracer rt started from "
             "([origin.md](../origin.md)).", ""]
    lines += [f"- [{s.title}](#{s.key.replace('_', '-')})" for s in index.sections] + [""]
    for s in index.sections:
        lines += [f'<a id="{s.key.replace("_", "-")}"></a>', "", f"## {s.title}", "", s.summary, "",
                  f"Machine: {s.machine}.", ""]
        for c in s.charts:
            lines += [f"### [{c.title}]({c.slug}.md)", "", f"![{c.title}]({c.slug}.png)", ""]
            if c.headline:
                lines += [f"**{c.headline}**", ""]
            if c.table.columns:
                lines += markdown_table(c.table) + [""]
            lines += [f"[CSV]({c.slug}.csv) · [every point]({c.slug}.md)", ""]
    return "\n".join(lines)
