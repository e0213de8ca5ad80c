#!/usr/bin/env python3
"""Speed against accuracy: error against a converged reference versus render time.

For each sampled effect (soft shadows, anti-aliasing, motion blur) on the
Cornell box and on the dragon, one curve per method: the 2020 report's method
(docs/origin.md) beside ours, each at a rising number of samples. Error is the
RMSE of the linear image and the mean HDR-FLIP (NVIDIA's perceptual metric,
`flip-evaluator`); time is the wall time of rtcore's Scene.render on every
core. Then how max_depth and the min_contribution cutoff trade time for error,
and how much time the cutoff saves at the default depth.

Each chart is a PNG with a CSV and a Markdown table beside it (the machine and
settings recorded), and the chart index (docs/charts/index.json and README.md) lists them all with
the headline numbers.
References (many samples) are cached in --cache, keyed by scene files,
camera, settings and the rtcore build, so that reruns only time the test points.
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import statistics
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import accuracy_report  # noqa: E402
import accuracy_scenes  # noqa: E402
import chart_index  # noqa: E402
from accuracy_measure import Renderer, SceneSpec, machine_info, mean_flip, rmse  # noqa: E402


@dataclass
class Method:
    key: str
    label: str                     # the legend's
    references: tuple[str, ...]    # the chart's references its error is measured against; the first is its own
    points: list[tuple[str, dict]]  # (what the point is, its settings beyond the chart's base)
    adaptive: bool = False


@dataclass
class Reference:
    what: str
    fields: dict


@dataclass
class Check:
    """A converged render of another method (or another reference) against a
    reference: what is left is bias (or, as `note` says, a different filter)."""
    what: str
    fields: dict
    reference: str
    note: str


@dataclass
class Chart:
    slug: str
    effect: str
    scene: SceneSpec
    scene_note: str
    base: dict
    references: dict[str, Reference]
    methods: list[Method]
    checks: list[Check] = field(default_factory=list)
    report: tuple[str, str] | None = None  # (method, point): the 2020 report's default, for the equal-error headline
    notes: list[str] = field(default_factory=list)
    depth: bool = False                  # the depth/cutoff chart


@dataclass(frozen=True)
class Budget:
    width: int
    height: int
    light_samples: tuple[int, ...]         # sphere and cone, at 1 spp
    pixel_spp: tuple[int, ...]             # cone over pixel samples; box and Gaussian jitter; time-sampled
    denoise_spp: tuple[int, ...]           # the same, denoised (OIDN): from fewer samples
    adaptive_thresholds: tuple[float, ...]
    adaptive_cap: int
    grid_k: tuple[int, ...]
    frames: tuple[int, ...]
    depths: tuple[int, ...]
    ref_light_samples: int                 # cone at 1 spp
    ref_spp: int                           # Gaussian/box references (spread shadows: x 2 shadow rays)
    ref_frames: int
    check_grid_k: int
    check_frames: tuple[int, int]          # frames x spp, both near converged
    saving_pairs: int                      # interleaved renders with and without the cutoff
    repeats: bool


# About 12 minutes on 2 cores once the references are cached (rendering them
# the first time takes about as long again).
NORMAL = Budget(width=320, height=240, light_samples=(1, 2, 4, 8, 16, 32, 64, 128, 256),
                pixel_spp=(4, 8, 16, 32, 64, 128, 256), denoise_spp=(1, 2, 4, 8, 16, 32, 64), adaptive_thresholds=(0.2, 0.1, 0.05, 0.02, 0.01),
                adaptive_cap=256, grid_k=(2, 3, 4, 6, 8, 12), frames=(2, 4, 8, 16, 32, 64, 128),
                depths=(0, 1, 2, 3, 4, 5, 6, 8, 16), ref_light_samples=4096, ref_spp=2048, ref_frames=1024,
                check_grid_k=32, check_frames=(32, 32), saving_pairs=9, repeats=True)
# Seconds: to test the script. Keeps the 2020 report's defaults (16 shadow rays, 2x2, 16 frames) among the points.
QUICK = Budget(width=64, height=48, light_samples=(1, 4, 16), pixel_spp=(4, 16), denoise_spp=(1, 4),
               adaptive_thresholds=(0.2, 0.05),
               adaptive_cap=64, grid_k=(2, 4), frames=(2, 16), depths=(0, 1, 5), ref_light_samples=1024,
               ref_spp=256, ref_frames=256, check_grid_k=16, check_frames=(16, 16), saving_pairs=3, repeats=False)

DEFAULT_DEPTH, DEFAULT_CUTOFF = 5, 0.001
# Denoised points: Scene.render denoises the whole image, so their times include the denoiser's.
DENOISE = {"denoise": "OIDN"}


def soft_shadow_chart(slug: str, scene: SceneSpec, note: str, b: Budget) -> Chart:
    cap = b.adaptive_cap
    return Chart(
        slug, "Soft shadows", scene, note, {"width": b.width, "height": b.height},
        references={
            "centre": Reference(f"cone, {b.ref_light_samples} shadow rays at 1 spp (the pixel centre)",
                                {"light_samples": b.ref_light_samples}),
            "filtered": Reference(f"cone, {b.ref_spp} spp (Gaussian filter) x 2 shadow rays",
                                  {"samples_per_pixel": b.ref_spp, "light_samples": 2}),
        },
        methods=[
            Method("sphere", "whole sphere (2020 report): N rays at 1 spp", ("centre",),
                   [(f"N={n}", {"light_sampling": "SPHERE", "light_samples": n}) for n in b.light_samples]),
            Method("cone", "cone: N rays at 1 spp", ("centre",),
                   [(f"N={n}", {"light_samples": n}) for n in b.light_samples]),
            Method("cone_pixel", "cone over pixel samples: N spp x 1 ray", ("filtered",),
                   [(f"N={n}", {"samples_per_pixel": n, "light_samples": 1}) for n in b.pixel_spp]),
            Method("adaptive", f"adaptive: <= {cap} spp x 1 ray", ("filtered",),
                   [(f"t={t:g}", {"samples_per_pixel": cap, "light_samples": 1, "adaptive_threshold": t})
                    for t in b.adaptive_thresholds], adaptive=True),
            Method("cone_denoised", "cone, denoised (OIDN): N rays at 1 spp", ("centre",),
                   [(f"N={n}", {"light_samples": n, **DENOISE}) for n in b.light_samples if n <= 64]),
            Method("cone_pixel_denoised", "cone over pixel samples, denoised (OIDN): N spp x 1 ray",
                   ("filtered", "centre"),
                   [(f"N={n}", {"samples_per_pixel": n, "light_samples": 1, **DENOISE}) for n in b.denoise_spp]),
        ],
        checks=[Check(f"sphere, {b.ref_light_samples} shadow rays at 1 spp",
                      {"light_sampling": "SPHERE", "light_samples": b.ref_light_samples}, "centre",
                      "sphere and cone sampling should converge to the same image")],
        report=("sphere", "N=16"),
        notes=["Every sampler here is stratified (Owen-scrambled Sobol'); there is no setting for independent "
               "samples, so no unstratified curve. `cone` takes its N rays from one camera sample through the "
               "pixel centre (N points of one stratified set over the light); `cone over pixel samples` takes "
               "one ray from each of N camera samples spread over the Gaussian filter, so the N rays are "
               "stratified over the light and the pixel together and the image is anti-aliased as well: it "
               "converges to the filtered reference, not to the pixel-centre one.",
               "Adaptive: the threshold t is the relative standard error at which a pixel stops (after the "
               "minimum of 16 / t^0.3 samples, a power of two); `mean spp` is counted on every 4th pixel."])


def aa_chart(slug: str, scene: SceneSpec, note: str, b: Budget) -> Chart:
    cap = b.adaptive_cap
    k = b.check_grid_k
    return Chart(
        slug, "Anti-aliasing", scene, note, {"width": b.width, "height": b.height},
        references={
            "box": Reference(f"box filter, {b.ref_spp} spp", {"pixel_filter": "BOX", "samples_per_pixel": b.ref_spp}),
            "gaussian": Reference(f"Gaussian filter, {b.ref_spp} spp", {"samples_per_pixel": b.ref_spp}),
        },
        methods=[
            Method("grid", "grid (2020 report): k x k sub-pixel centres", ("box",),
                   [(f"{n}x{n}", {"pixel_filter": "GRID", "samples_per_pixel": n * n}) for n in b.grid_k]),
            Method("box", "box filter: N stratified spp", ("box",),
                   [(f"N={n}", {"pixel_filter": "BOX", "samples_per_pixel": n}) for n in b.pixel_spp]),
            Method("gaussian", "Gaussian filter (default): N spp", ("gaussian",),
                   [(f"N={n}", {"samples_per_pixel": n}) for n in b.pixel_spp]),
            Method("adaptive", f"adaptive, box filter: <= {cap} spp", ("box",),
                   [(f"t={t:g}", {"pixel_filter": "BOX", "samples_per_pixel": cap, "adaptive_threshold": t})
                    for t in b.adaptive_thresholds], adaptive=True),
            Method("box_denoised", "box filter, denoised (OIDN): N stratified spp", ("box",),
                   [(f"N={n}", {"pixel_filter": "BOX", "samples_per_pixel": n, **DENOISE}) for n in b.denoise_spp]),
        ],
        checks=[Check(f"grid {k}x{k}", {"pixel_filter": "GRID", "samples_per_pixel": k * k}, "box",
                      "the grid's sub-pixel centres and the box filter's stratified samples should "
                      "converge to the same box-filtered image")],
        report=("grid", "2x2"),
        notes=["The grid and box curves converge to the same box-filtered image; the Gaussian filter "
               "(the default) converges to a softer one, so it has its own reference: its error measures its "
               "noise, not how sharp it is."])


def motion_chart(slug: str, scene: SceneSpec, note: str, b: Budget) -> Chart:
    frames, spp = b.check_frames
    return Chart(
        slug, "Motion blur", scene, note, {"width": b.width, "height": b.height},
        references={
            "frames": Reference(f"frames, {b.ref_frames} at 1 spp",
                                {"motion_blur": "FRAMES", "motion_frames": b.ref_frames}),
            "time": Reference(f"time-sampled, {b.ref_spp} spp (Gaussian filter)", {"samples_per_pixel": b.ref_spp}),
        },
        methods=[
            Method("frames", "frames (2020 report): K renders at 1 spp", ("time", "frames"),
                   [(f"K={k}", {"motion_blur": "FRAMES", "motion_frames": k}) for k in b.frames]),
            Method("time", "time-sampled: N spp", ("time",),
                   [(f"N={n}", {"samples_per_pixel": n}) for n in b.pixel_spp]),
            Method("time_denoised", "time-sampled, denoised (OIDN): N spp", ("time",),
                   [(f"N={n}", {"samples_per_pixel": n, **DENOISE}) for n in b.denoise_spp]),
        ],
        checks=[Check(f"frames, {frames} x {spp} spp (Gaussian filter)",
                      {"motion_blur": "FRAMES", "motion_frames": frames, "samples_per_pixel": spp}, "time",
                      f"with the same pixel filter, frames and time samples should converge to the same blur; "
                      f"left: {frames} frames' steps and {spp} film positions (every frame takes the same ones)"),
                Check(f"frames reference ({b.ref_frames} at 1 spp)",
                      {"motion_blur": "FRAMES", "motion_frames": b.ref_frames}, "time",
                      "not a bias of the blur: pixel centres against the Gaussian filter (aliasing)")],
        report=("frames", "K=16"),
        notes=["Frames at 1 spp sample each pixel at its centre, so they converge to an aliased blur; "
               "time samples are spread over the Gaussian filter as well as over the shutter interval, and "
               "converge to the blurred, anti-aliased image (the reference `time`). The frames are measured "
               "against both: against `time` (solid), where the aliasing their limit keeps is a floor, and "
               "against their own limit, `frames` (dashed), which shows how fast the frames alone converge."])


def depth_chart(slug: str, scene: SceneSpec, note: str, b: Budget) -> Chart:
    return Chart(
        slug, "Recursion depth and cutoff", scene, note, {"width": b.width, "height": b.height},
        references={"deep": Reference("max_depth 64, min_contribution 0", {"max_depth": 64, "min_contribution": 0})},
        methods=[Method(f"cutoff_{cutoff:g}", f"min_contribution {cutoff:g}" + (" (default)" if cutoff else " (off)"),
                        ("deep",), [(f"depth {d}", {"max_depth": d, "min_contribution": cutoff}) for d in b.depths])
                 for cutoff in (DEFAULT_CUTOFF, 0.0)],
        notes=["1 spp through the pixel centres and a point light: the image has no noise, and its error is "
               "the bias of stopping the reflection rays early. An error of 0 (the reference's own image) is "
               "drawn at the bottom of the axis with a downward triangle."],
        depth=True)


def plan(scenes: Path, work: Path, dragon: str, b: Budget) -> list[Chart]:
    source = scenes / dragon
    lit, light = accuracy_scenes.sphere_lit_glb(source, work / "dragon_sphere_light")
    moving, motion = accuracy_scenes.moving_glb(source, work / "dragon_motion")
    spheres = accuracy_scenes.cornell_with_spheres(scenes, work / "cornell_spheres")
    name = source.stem
    return [
        soft_shadow_chart("soft_shadows_cornell", SceneSpec("cornell_sphere_light.obj",
                                                             scenes / "cornell_sphere_light.obj"),
                          "the Cornell box lit by a spherical light (radius 0.1)", b),
        soft_shadow_chart("soft_shadows_dragon", SceneSpec(f"{name}.glb, spherical light", lit),
                          f"{dragon} with its point light made a spherical light of radius {light['radius']} "
                          f"(a copy with a sidecar)", b),
        aa_chart("antialiasing_cornell", SceneSpec("cornell.obj", scenes / "cornell.obj"),
                 "the Cornell box with a point light: the only noise is at edges", b),
        aa_chart("antialiasing_dragon", SceneSpec(f"{name}.glb", source),
                 f"{dragon} with its point light", b),
        motion_chart("motion_cornell", SceneSpec("cornell_motion.obj, camera look_shift",
                                                 scenes / "cornell_motion.obj", "look_shift"),
                     "the short box slides and turns and the camera's look-at point shifts by 0.15 "
                     "(as in the 2020 report)", b),
        motion_chart("motion_dragon", SceneSpec(f"{name}.glb, moving", moving),
                     f"{dragon} turning {motion['turn_degrees']:g} degrees about +Y and sliding "
                     f"{motion['translation'][0]} along +X "
                     f"(an rt.NodeMotion in a sidecar), point light", b),
        depth_chart("depth_cornell", SceneSpec("cornell.obj, camera mirror", scenes / "cornell.obj", "mirror"),
                    "the Cornell box seen in its mirror (Kr 0.9; the other surfaces reflect nothing)", b),
        depth_chart("depth_cornell_spheres", SceneSpec("cornell.obj + 2 reflective spheres, camera mirror",
                                                       spheres, "mirror"),
                    "the Cornell box with a mirror ball (Kr 0.85) and a glossy ball (Kr 0.3) added by a sidecar, "
                    "seen in its mirror: reflections of reflections", b),
        depth_chart("depth_dragon", SceneSpec(f"{name}.glb", source),
                    f"{dragon}: every surface reflects a little (Kr 0.02 on the dragon, 0.0016 on the ground, "
                    "from glTF roughness)", b),
    ]


def run_chart(renderer: Renderer, chart: Chart, b: Budget) -> dict:
    print(f"\n{chart.slug}: {chart.effect}, {chart.scene.label}, {b.width}x{b.height}", flush=True)
    references, ref_rows = {}, []
    for key, ref in chart.references.items():
        image, seconds, cached = renderer.reference(chart.scene, {**chart.base, **ref.fields})
        references[key] = image
        ref_rows.append({"reference": key, "what": ref.what, "settings": {**chart.base, **ref.fields},
                         "seconds": seconds, "cached": cached})
        print(f"  reference {key:9} {seconds:8.2f} s{' (cached)' if cached else ''}", flush=True)

    rows = []
    for method in chart.methods:
        for label, fields in method.points:
            settings = {**chart.base, **fields}
            image, seconds, timed = renderer.timed(chart.scene, settings)
            spp = round(renderer.mean_samples(chart.scene, settings), 1) if method.adaptive else ""
            for against in method.references:
                reference = references[against]
                rows.append({"chart": chart.slug, "scene": chart.scene.label, "method": method.key,
                             "label": method.label, "point": label, "time_s": seconds, "renders_timed": timed,
                             "rmse": rmse(reference, image), "flip": mean_flip(reference, image),
                             "reference": against, "mean_spp": spp, "settings": settings})
                print(f"  {method.key:10} {label:10} {seconds:8.3f} s  RMSE {rows[-1]['rmse']:.5f}  "
                      f"FLIP {rows[-1]['flip']:.5f}  vs {against}" + (f"  {spp} spp" if spp else ""), flush=True)

    checks = []
    for check in chart.checks:
        image, seconds, cached = renderer.reference(chart.scene, {**chart.base, **check.fields})
        reference = references[check.reference]
        checks.append({"what": check.what, "reference": check.reference, "rmse": rmse(reference, image),
                       "flip": mean_flip(reference, image), "note": check.note, "seconds": seconds})
        print(f"  check {check.what}: RMSE {checks[-1]['rmse']:.5f}  FLIP {checks[-1]['flip']:.5f}", flush=True)

    result = {"chart": chart, "rows": rows, "references": ref_rows, "checks": checks}
    if chart.depth:
        result["saving"] = cutoff_saving(renderer, chart, b)
    return result


def cutoff_saving(renderer: Renderer, chart: Chart, b: Budget) -> dict:
    """Render time with the default cutoff against none, at the default depth:
    interleaved pairs, so that a change of load between them hits both alike."""
    with_cutoff = {**chart.base, "max_depth": DEFAULT_DEPTH, "min_contribution": DEFAULT_CUTOFF}
    without = {**chart.base, "max_depth": DEFAULT_DEPTH, "min_contribution": 0}
    times = {"with": [], "without": []}
    for _ in range(b.saving_pairs):
        times["with"].append(renderer.render(chart.scene, with_cutoff)[1])
        times["without"].append(renderer.render(chart.scene, without)[1])
    t_with, t_without = statistics.median(times["with"]), statistics.median(times["without"])
    saving = {"depth": DEFAULT_DEPTH, "cutoff": DEFAULT_CUTOFF, "pairs": b.saving_pairs,
              "time_with_s": t_with, "time_without_s": t_without, "saved_percent": 100 * (1 - t_with / t_without)}
    print(f"  cutoff {DEFAULT_CUTOFF:g} at depth {DEFAULT_DEPTH}: {t_with:.4f} s against {t_without:.4f} s "
          f"without: {saving['saved_percent']:.1f}% saved", flush=True)
    return saving


CHART_KINDS = {"soft_shadows": soft_shadow_chart, "antialiasing": aa_chart, "motion": motion_chart}


def replot(out: Path, only: str) -> int:
    """Redraws the PNGs of the sampling charts in `out` from their committed
    CSVs, with the legends and titles of the charts as defined here: nothing
    is rendered. The depth charts are left alone (their third panel needs the
    cutoff's time saving, which their CSV does not keep)."""
    section = next((s for s in chart_index.read_index(out).sections if s.key == "speed_accuracy"), None)
    redrawn = 0
    for path in sorted(out.glob("*.csv")):
        kind = next((k for k in CHART_KINDS if path.stem.startswith(k + "_")), None)
        if kind is None or only not in path.stem:
            continue
        with path.open() as f:
            rows = list(csv.DictReader(f))
        if not rows or rows[0]["chart"] != path.stem:
            continue
        base = json.loads(rows[0]["settings"])
        budget = QUICK if base["width"] == QUICK.width else NORMAL
        chart = CHART_KINDS[kind](path.stem, SceneSpec(rows[0]["scene"], Path(rows[0]["scene"])), "", budget)
        labels = {m.key: m.label for m in chart.methods}
        result = {"chart": chart, "rows": [
            {**r, "label": labels[r["method"]], "time_s": float(r["time_s"]), "rmse": float(r["rmse"]),
             "flip": float(r["flip"]), "settings": json.loads(r["settings"])} for r in rows]}
        machine = chart_index.machine_from_line(section.machine) if section else {"load_average": "?"}
        machine.update({k: rows[0][k] for k in ("cpu", "cores", "commit", "date")})
        accuracy_report.plot(result, machine, budget, out / f"{path.stem}.png")
        print(f"redrew {path.stem}.png from {path.name}")
        redrawn += 1
    return redrawn


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenes", type=Path, default=Path("build/scenes"), help="the sample scenes (make samples)")
    parser.add_argument("--out", type=Path, help="where the charts and tables go (default docs/charts; "
                        "with --quick, quick/ in the cache folder)")
    parser.add_argument("--cache", type=Path, default=Path("build/charts"),
                        help="references and the scene variants (kept between runs)")
    parser.add_argument("--dragon", default="dragon_3.glb", help="which of the sample dragons")
    parser.add_argument("--quick", action="store_true",
                        help=f"{QUICK.width}x{QUICK.height}, 2-3 points per curve, no repeats: to test the script")
    parser.add_argument("--only", default="", help="only the charts whose name contains this")
    parser.add_argument("--replot", action="store_true",
                        help="only redraw the sampling charts' PNGs in --out (default docs/charts) from their "
                        "CSVs, rendering nothing")
    args = parser.parse_args()
    if args.replot:
        return 0 if replot(args.out or Path("docs/charts"), args.only) else 1
    if not (args.scenes / "cornell.obj").exists():
        sys.exit(f"speed_accuracy: no sample scenes in {args.scenes}: run `make samples`")
    budget = QUICK if args.quick else NORMAL
    args.out = args.out or (args.cache / "quick" if args.quick else Path("docs/charts"))
    start = time.perf_counter()
    machine = machine_info()
    print(f"{machine['cpu']}, {machine['cores']} cores, load average {machine['load_average']}, "
          f"commit {machine['commit']}", flush=True)
    if os.getloadavg()[0] > 1.0 and not args.quick:
        print("speed_accuracy: warning: something else is busy on this machine (load average above 1): "
              "the times will be skewed", flush=True)

    renderer = Renderer(args.cache / "references", repeats=budget.repeats)
    charts = [c for c in plan(args.scenes, args.cache / "scenes", args.dragon, budget) if args.only in c.slug]
    args.out.mkdir(parents=True, exist_ok=True)
    results = []
    for chart in charts:
        result = run_chart(renderer, chart, budget)
        result["headline"] = accuracy_report.write_chart(result, machine, budget, args.out)
        results.append(result)
    machine["run_minutes"] = round((time.perf_counter() - start) / 60, 1)
    chart_index.put_section(args.out, accuracy_report.section(results, machine, budget, quick=args.quick))
    print(f"\n{len(results)} charts in {args.out} ({machine['run_minutes']} min)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
