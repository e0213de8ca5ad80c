"""The cluster model's measured inputs (dask_costs.DaskCosts and each modelled
job's tile_costs.RenderCosts) and the machine they were measured on, to and
from a JSON file beside the chart, so that the model can be run again on the
costs of one measurement (scaling.py --only cluster_model --reuse-costs): a
change to the plan or the dealing is then judged on the same costs, and a look
at it does not take the cores for minutes."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np

from dask_costs import DaskCosts, Spread
from tile_costs import RenderCosts


def _spread(value: dict) -> Spread:
    return Spread(**value)


def _plain(value):
    """JSON's form of a measurement: Spreads as dicts, arrays as lists."""
    if isinstance(value, Spread):
        return dataclasses.asdict(value)
    if isinstance(value, np.ndarray):
        return np.round(value, 4).tolist()  # the cost map: relative costs, 4 places are plenty
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    return value


def save(path: Path, dask: DaskCosts, renders: list[RenderCosts], machine: dict) -> None:
    def fields(obj) -> dict:
        return {f.name: _plain(getattr(obj, f.name)) for f in dataclasses.fields(obj)}

    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps({"machine": machine, "dask": fields(dask), "renders": [fields(r) for r in renders]},
                               indent=1) + "\n")


def load(path: Path) -> tuple[DaskCosts, list[RenderCosts], dict]:
    data = json.loads(path.read_text())
    d = data["dask"]
    by_workers = lambda values: {int(n): _spread(v) for n, v in values.items()}  # noqa: E731
    dask = DaskCosts(**{**d, "scheduler_s": by_workers(d["scheduler_s"]), "wall_s": by_workers(d["wall_s"]),
                        "worker_s": by_workers(d["worker_s"]),
                        **{k: _spread(d[k]) for k in ("server_s", "server_small_s", "server_large_s", "latency_s")}})
    renders = [RenderCosts(**{**r, "cost_map": np.asarray(r["cost_map"]),
                              **{k: _spread(r[k]) for k in ("pixel_s", "render_s", "tile_s")}})
               for r in data["renders"]]
    return dask, renders, data["machine"]
