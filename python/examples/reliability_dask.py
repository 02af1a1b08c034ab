"""The same reliability analysis locally (rayon, every core) and on a Dask
LocalCluster of worker processes; prints both wall times and checks that the
results are equal bit for bit (docs/reliability.md section 4).

    .venv/bin/python python/examples/reliability_dask.py [WORKERS] [METHOD] [SAMPLES]
"""

import sys
import time
from typing import Optional, Tuple

from dask.distributed import Client, LocalCluster

import deploywatch

MECH = "data/mechanisms/seed001_T01.toml"
VARY = [
    "coulomb_friction:joint=1:lognormal(2.63,0.05)",
    "coulomb_friction:joint=2:lognormal(1.7,0.05)",
    "coulomb_friction:joint=3:lognormal(0.001,0.05)",
]


def main() -> None:
    workers = int(sys.argv[1]) if len(sys.argv) > 1 else 2
    method = sys.argv[2] if len(sys.argv) > 2 else "subset"
    samples = int(sys.argv[3]) if len(sys.argv) > 3 else None

    def run(executor: Optional[deploywatch.Executor]) -> Tuple[deploywatch.Reliability, float]:
        t = time.perf_counter()
        r = deploywatch.reliability(
            MECH, vary=VARY, fail=["not_latched"], method=method, samples=samples, seed=0,
            executor=executor,
        )
        return r, time.perf_counter() - t

    local, t_local = run(None)
    # dask.distributed's constructors carry no annotations.
    with LocalCluster(  # type: ignore[no-untyped-call]
        n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster, Client(cluster) as client:  # type: ignore[no-untyped-call]
        remote, t_dask = run(client)
    print(
        f"{method}: p_fail = {local.p_fail:.4e}, c.o.v. {local.cov:.3f}, "
        f"{local.simulations} deployments; local {t_local:.2f} s, "
        f"Dask LocalCluster of {workers} processes {t_dask:.2f} s (cluster start not counted); "
        f"equal bit for bit: {local == remote}"
    )
    sys.exit(0 if local == remote else 1)


if __name__ == "__main__":
    main()
