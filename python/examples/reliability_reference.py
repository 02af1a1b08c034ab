"""Crude Monte-Carlo reference through Dask (docs/reliability.md §6): N
deployments of a reliability problem on a LocalCluster of WORKERS worker
processes (one thread each), printing p_fail, its Wilson interval and the
deployments per core-second. Same bits as the CLI's `--method mc` with the
same seed.

    .venv/bin/python python/examples/reliability_reference.py [N] [WORKERS] [CASE]

CASE: `two_modes` (data/mechanisms/reliability_two_modes.toml, the
two-mode case of tests/reliability.rs) or `t01` (seed 001 T01, 5 %
lognormal friction, §4).
"""

import os
import resource
import sys
import time

from dask.distributed import Client, LocalCluster

import deploywatch

CASES = {
    "two_modes": (
        "data/mechanisms/reliability_two_modes.toml",
        [
            "coulomb_friction:joint=1:normal(0.98,0.1)",
            "spring_preload:joint=2:normal(0.55,0.1)",
            "coulomb_friction:joint=2:normal(0.8,1e-6)",
        ],
    ),
    "t01": (
        "data/mechanisms/seed001_T01.toml",
        [
            "coulomb_friction:joint=1:lognormal(2.63,0.05)",
            "coulomb_friction:joint=2:lognormal(1.7,0.05)",
            "coulomb_friction:joint=3:lognormal(0.001,0.05)",
        ],
    ),
}


def main() -> None:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 10_000_000
    workers = int(sys.argv[2]) if len(sys.argv) > 2 else (os.cpu_count() or 1)
    mech, vary = CASES[sys.argv[3] if len(sys.argv) > 3 else "two_modes"]
    env = {"RAYON_NUM_THREADS": "1"}
    # dask.distributed's constructors carry no annotations.
    with LocalCluster(  # type: ignore[no-untyped-call]
        n_workers=workers, threads_per_worker=1, processes=True,
        dashboard_address=None, env=env,
    ) as cluster, Client(cluster) as client:  # type: ignore[no-untyped-call]
        t = time.perf_counter()
        r = deploywatch.reliability(
            mech, vary=vary, fail=["not_latched"], method="mc", samples=n, seed=0,
            executor=client,
        )
        wall = time.perf_counter() - t
        cpu = sum(client.run(lambda: resource.getrusage(resource.RUSAGE_SELF).ru_utime).values())
    lo, hi = r.ci95
    print(
        f"mc: p_fail = {r.p_fail:.4e}, 95 % [{lo:.4e}, {hi:.4e}], c.o.v. {r.cov:.3f}, "
        f"{r.simulations} deployments, {r.failures} failed; {wall:.1f} s wall, "
        f"{cpu:.1f} s of the workers' CPU: {r.simulations / cpu:.0f} deployments per core-second"
    )


if __name__ == "__main__":
    main()
