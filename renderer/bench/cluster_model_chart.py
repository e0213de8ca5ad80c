"""The scaling_cluster_model chart (scaling.py draws it with the others, or
alone with --only cluster_model): a 3840x2160 dragon modelled on 1 to 64
workers of 8 threads (cluster_model.py) from Dask's and the renderer's costs
measured here (dask_costs.py, tile_costs.py), with the service's plan and
dealing now and as they were before (issue 18)."""

from __future__ import annotations

import contextlib
import dataclasses
from pathlib import Path

import matplotlib.pyplot as plt
from rt import charts_pb2

import chart_index
import cluster_costs_file
import cluster_model
import dask_costs
import tile_costs
from app.services import tile_plan

# The jobs the cluster model projects: the viewer's default (one sample, an
# interactive job) and a final render (the README's anti-aliasing example, 16
# samples, as a batch job).
MODEL_JOBS = (("1 spp, interactive", 1, True), ("16 spp, batch", 16, False))
MODEL_SIZE = (3840, 2160)
# The plans and dealings drawn: (label, TASK_RAYS_PER_THREAD of the earlier
# plan or None for the service's plan now, the dealing, line style).
PLANS = (("2 tiles a thread, Dask's dealing", 0, "dask", "--"),
         ("limit of 8K rays a thread, Dask's dealing", 8 * 1024, "dask", "-."),
         ("limit of 8K rays, 2 tiles a worker", 8 * 1024, "service", ":"),
         ("now: middle tiles cut, 2 tiles a worker", None, "service", "-"))


def _earlier_tile_size(width: int, height: int, threads: int, pixel_rays: float) -> int:
    """tile_plan.full_tile_size as it was before the middle tiles were cut
    (6f9ebcf): enough tiles whatever the limit, one grid."""
    enough, limit, _ = tile_plan._tile_counts(width, height, threads, pixel_rays)  # noqa: SLF001
    counts = [-(-width // s) * -(-height // s) for s in tile_plan.TILE_SIZES]
    for i, size in enumerate(tile_plan.TILE_SIZES):
        if counts[i] < enough:
            continue
        smallest = i + 1 == len(tile_plan.TILE_SIZES)
        if size * size * pixel_rays <= tile_plan.TILE_RAYS or smallest or counts[i + 1] > limit:
            return size
    return tile_plan.TILE_SIZES[-1]


@contextlib.contextmanager
def earlier_plan(task_rays_per_thread: int | None):
    """tile_plan as it was with that scheduler limit (0: none, before issue
    18; 8K: before the middle tiles were cut); None: as it is."""
    if task_rays_per_thread is None:
        yield
        return
    saved = tile_plan.TASK_RAYS_PER_THREAD, tile_plan.full_tiles
    tile_plan.TASK_RAYS_PER_THREAD = task_rays_per_thread
    tile_plan.full_tiles = lambda w, h, threads, rays=1.0: tile_plan._grid(  # noqa: SLF001
        w, h, _earlier_tile_size(w, h, threads, rays))
    try:
        yield
    finally:
        tile_plan.TASK_RAYS_PER_THREAD, tile_plan.full_tiles = saved


COSTS_FILE = "scaling_cluster_model_costs.json"  # beside the chart: what it was modelled from


def measure(scenes: Path, quick: bool, out: Path, machine: dict, reuse: bool = False
            ) -> tuple[dask_costs.DaskCosts, list[tile_costs.RenderCosts], dict]:
    """Dask's costs on a real scheduler and the dragon's render costs for each
    modelled job (quick: few tasks, small images read as if full size), and
    the machine they were measured on; written to COSTS_FILE in `out`, or,
    with `reuse`, read from there."""
    if reuse:
        return cluster_costs_file.load(out / COSTS_FILE)
    dask = dask_costs.measure((1,), tasks=100, repeats=1, large=128) if quick else dask_costs.measure()
    scene = scenes / ("dragon_3.glb" if quick else "dragon_1.glb")
    renders = [tile_costs.measure(scene, *MODEL_SIZE, samples=samples, repeats=1 if quick else 3,
                                  scale=(16 if samples == 1 else 32) if quick else (1 if samples == 1 else 4))
               for _, samples, _ in MODEL_JOBS]
    cluster_costs_file.save(out / COSTS_FILE, dask, renders, machine)
    return dask, renders, machine


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
    lines = [f"Dask scheduler CPU per task (jobs of {dask.tasks} no-op tasks dealt as the service has them "
             f"dealt, median (range)): {sched}.",
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


def model_rows(dask: dask_costs.DaskCosts, renders: list[tile_costs.RenderCosts]
               ) -> dict[tuple[str, str], list[cluster_model.Row]]:
    """(job, plan) -> the modelled rows at each cluster size."""
    found = {}
    for (label, _, interactive), render in zip(MODEL_JOBS, renders):
        costs = model_costs(dask, render, interactive)
        for plan, rays, dealing, _ in PLANS:
            with earlier_plan(rays):
                found[label, plan] = cluster_model.scaling(dataclasses.replace(costs, dealing=dealing))
    return found


def _draw(found: dict, machine: dict, out: Path, scene: str) -> None:
    width, height = MODEL_SIZE
    fig, axes = plt.subplots(1, 2, figsize=(13, 5.5))
    counts = list(cluster_model.WORKER_COUNTS)
    axes[0].plot(counts, counts, linestyle=":", color="#999", label="ideal")
    axes[1].plot(counts, [100] * len(counts), linestyle=":", color="#999", label="ideal")
    axes[1].axhline(80, color="#d62728", linewidth=0.6, alpha=0.6)
    for (label, _, _), color in zip(MODEL_JOBS, ("#1f77b4", "#2ca02c")):
        for plan, _, _, style in PLANS:
            rows = found[label, plan]
            for ax, values in ((axes[0], [r.speedup for r in rows]), (axes[1], [100 * r.efficiency for r in rows])):
                ax.plot(counts, values, linestyle=style, marker="o", markersize=3.5, color=color,
                        label=f"{label}: {plan}")
    for ax, what in ((axes[0], "speed-up against one worker"), (axes[1], "efficiency (%)")):
        ax.set_xscale("log", base=2)
        ax.set_xlabel("workers of 8 threads")
        ax.set_ylabel(what)
        ax.grid(True, which="both", linewidth=0.3, alpha=0.6)
    axes[0].legend(fontsize=6.5)
    axes[0].set_yscale("log", base=2)
    axes[1].set_ylim(0, 110)
    axes[0].set_title(f"{scene}, {width}x{height}: modelled from Dask's and the renderer's costs measured here",
                      fontsize=8)
    axes[1].set_title("the plan (scheduler limit, middle tiles cut) and Dask's dealing, before and now", fontsize=8)
    fig.suptitle("Cluster scale on paper: a 4K dragon on 1 to 64 Dask workers")
    chart_index.save_figure(fig, machine, out / "scaling_cluster_model.png")


def _headline(found: dict, renders: list[tile_costs.RenderCosts]) -> str:
    width, height = MODEL_SIZE
    final, default = MODEL_JOBS[1][0], MODEL_JOBS[0][0]

    def at(label: str, plan_index: int, workers: int) -> cluster_model.Row:
        return next(r for r in found[label, PLANS[plan_index][0]] if r.modelled.workers == workers)

    start, dealt, now, wide = at(final, 1, 32), at(final, 2, 32), at(final, 3, 32), at(final, 3, 64)
    d_start, d_now = at(default, 1, 32), at(default, 3, 32)
    return (f"At 32 workers of 8 threads a {width}x{height} {renders[1].scene} at {final} was modelled at "
            f"{100 * start.efficiency:.0f}% efficiency ({start.modelled.tiles} tiles of "
            f"{start.modelled.tile_side}, dealt by count, all at once); {100 * dealt.efficiency:.0f}% with two "
            f"tiles a worker; {100 * now.efficiency:.0f}% with the middle tiles cut in four and run last "
            f"({now.modelled.tiles} tiles, {now.modelled.bound}-bound); at 64 workers {100 * wide.efficiency:.0f}% "
            f"(the scheduler hands out about {wide.modelled.tiles} tiles in the time the threads render them); "
            f"at {default} {100 * d_start.efficiency:.0f}% before and {100 * d_now.efficiency:.0f}% now at 32 "
            f"workers ({d_now.modelled.bound}-bound: "
            f"{renders[0].pixel_s.median * width * height / 256 * 1e3:.0f} ms of rendering per thread)")


def chart(dask: dask_costs.DaskCosts, renders: list[tile_costs.RenderCosts], machine: dict,
          out: Path) -> tuple[charts_pb2.Chart, str]:
    """The chart (PNG into `out`, its table and headline) and its page's text."""
    found = model_rows(dask, renders)
    _draw(found, machine, out, renders[0].scene)
    rows = [[label, plan, *cells] for (label, plan), found_rows in found.items()
            for cells in cluster_model.table_rows(found_rows)]
    table = chart_index.table(["job", "plan", *cluster_model.TABLE_COLUMNS], rows)
    result = charts_pb2.Chart(slug="scaling_cluster_model", title="Cluster scale on paper: a 4K dragon on 1 to 64 "
                              "Dask workers", headline=_headline(found, renders), table=table)
    text = (" " + (cluster_model.__doc__ or "").split("\n\n", 1)[0].replace("\n", " ") + " Measured inputs: "
            + measured_inputs_text(dask, renders)
            + " The earlier plans are tile_plan.py's grid of one tile size with no scheduler limit (before issue 18)"
            " and with a limit of 8K rays a thread (6f9ebcf); Dask's dealing is distributed's default, the"
            f" service's is tile_slots.py's. The measured costs are in {COSTS_FILE}: `scaling.py --only"
            " cluster_model --reuse-costs` models them again (a change of plan judged on the same costs).")
    return result, text


# The cluster model's page: its inputs are CPU times, not the section's wall clock.
SUMMARY = ("Modelled by renderer/bench/cluster_model.py from costs measured by dask_costs.py and "
           "tile_costs.py in CPU seconds of each process (steadier than wall time on shared cores), "
           "medians of 3 runs with their ranges.")
