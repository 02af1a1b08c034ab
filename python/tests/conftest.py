"""Shared fixtures: the repository, the `deploywatch` CLI to compare with, a
Dask LocalCluster of 2 worker processes (started once for the session)."""

import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def root():
    return ROOT


@pytest.fixture(scope="session")
def cli():
    """The CLI binary: $DEPLOYWATCH_BIN, else debug/deploywatch of
    $CARGO_TARGET_DIR (default target/; built by `cargo test` in
    scripts/test.sh), else built here."""
    env = os.environ.get("DEPLOYWATCH_BIN")
    if env:
        return env
    target = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    exe = target / "debug" / "deploywatch"
    if not exe.exists():
        subprocess.run(
            ["cargo", "build", "-q", "-p", "deploywatch-sim", "--bin", "deploywatch"],
            cwd=ROOT,
            check=True,
        )
    return str(exe)


@pytest.fixture(scope="session")
def dask_client():
    """A client of a real Dask LocalCluster of 2 worker processes, one thread
    each (the workers import the installed `deploywatch`)."""
    from dask import distributed

    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster, distributed.Client(cluster) as client:
        yield client
