"""Design sweeps: designs per second per core, the serial fraction, the cluster extrapolation.

One run measures, on the same study (a grid over two xacro arguments of rcm_bevel, four
metrics):

* ``t1``: wall time in this process (one core), hence designs per second per core;
* ``t_local``: wall time on W local processes (fork server);
* ``t_dask``: wall time through a distributed.LocalCluster of W one-thread workers;
* the serial fraction s of each parallel route from Amdahl's law, t_W = t1·(s + (1 − s)/W),
  i.e. s = (W·t_W/t1 − 1)/(W − 1);
* the extrapolation to 10^6 and 10^8 designs on N workers: T = n·t_design·(s + (1 − s)/N).

Usage::

    .venv/bin/python benchmarks/bench_design.py [--designs 48] [--workers 2]
"""

from __future__ import annotations

import argparse
import json
import math
import time

from rcm_pin.design import Study, Vary, run

METRICS = ("cone_coverage", "cone_margin", "worst_conditioning", "rcm_drift")


def study(n: int, shift: int = 0) -> Study:
    """A side × side grid; ``shift`` moves the l9 range so that no two runs share a design
    (``rcm_pin.load`` caches renderings: a repeated design would be a cache hit)."""
    side = max(2, math.isqrt(n))
    lo = 0.2 + 0.011 * shift
    return Study(
        "rcm_bevel", (Vary("q2_limit", 0.6, 1.4, side), Vary("l9", lo, lo + 0.1, side)), METRICS
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--designs", type=int, default=48)
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    w = args.workers
    run(study(4, shift=9), workers=1, progress=False)  # imports and first renders
    t = time.perf_counter()
    serial = run(study(args.designs, shift=1), workers=1, progress=False)
    t1 = time.perf_counter() - t
    n = len(serial.frame)
    t = time.perf_counter()
    local = run(study(args.designs, shift=2), workers=w, chunk=max(1, n // (4 * w)), progress=False)
    t_local = time.perf_counter() - t  # includes starting the fork server and its workers
    from distributed import LocalCluster

    with LocalCluster(
        n_workers=w, threads_per_worker=1, host="127.0.0.1", dashboard_address=None
    ) as cluster:
        warm = study(2 * w, shift=8)  # imports and first renders on every worker
        run(warm, scheduler=cluster.scheduler_address, chunk=1, progress=False)
        t = time.perf_counter()
        dask = run(
            study(args.designs, shift=3), scheduler=cluster.scheduler_address,
            chunk=max(1, n // (4 * w)), progress=False,
        )  # fmt: skip
        t_dask = time.perf_counter() - t
    assert len(local.frame) == len(dask.frame) == n
    t_design = t1 / n

    def serial_fraction(tw: float) -> float:
        return (w * tw / t1 - 1.0) / (w - 1) if w > 1 else 1.0

    s_dask = max(serial_fraction(t_dask), 0.0)
    extrapolation = {
        f"{designs:.0e} designs on {workers} workers [h]": designs
        * t_design
        * (s_dask + (1 - s_dask) / workers)
        / 3600
        for designs in (1e6, 1e8)
        for workers in (10, 100, 1000)
    }
    print(
        json.dumps(
            {
                "designs": n,
                "workers": w,
                "seconds_per_design_one_core": t_design,
                "designs_per_second_per_core": 1.0 / t_design,
                "t1_s": t1,
                "t_local_s": t_local,
                "t_dask_s": t_dask,
                "speedup_local": t1 / t_local,
                "speedup_dask": t1 / t_dask,
                "serial_fraction_local": serial_fraction(t_local),
                "serial_fraction_dask": serial_fraction(t_dask),
                "extrapolation": extrapolation,
            },
            indent=2,
        )
    )


if __name__ == "__main__":
    main()
