"""An error raised inside a Dask worker process arrives in the caller as the
package's exception, with the worker's message and cause (a real
LocalCluster of 2 worker processes, the session's `dask_client`).

    bash scripts/python-env.sh && .venv/bin/pytest python/tests/test_dask_errors.py -q
"""

import time

import numpy as np
import pytest

import deploywatch
from deploywatch import DeploywatchError, InputError, SimulationError

MECH = "data/mechanisms/reliability_one_panel.toml"
NEGATIVE = ["panel_inertia:joint=1:normal(0.16,0.2)"]


def test_a_simulation_error_on_a_worker(root, dask_client):
    rows = np.array([[0.16], [0.15], [-0.1], [0.17]])
    with pytest.raises(SimulationError) as here:
        deploywatch.simulate_batch(root / MECH, NEGATIVE, rows)
    future = dask_client.submit(deploywatch.simulate_batch, root / MECH, NEGATIVE, rows)
    with pytest.raises(SimulationError) as there:
        future.result()
    # The same class, message and cause as the same call here.
    assert str(there.value) == str(here.value)
    assert str(there.value).startswith("the deployment at panel_inertia:joint=1 = -0.1 failed")
    assert there.value.causes == here.value.causes != ()
    assert isinstance(there.value.__cause__, DeploywatchError)
    assert str(there.value.__cause__) == str(here.value.__cause__)


def test_an_input_error_on_a_worker(root, dask_client):
    future = dask_client.submit(deploywatch.simulate_batch, root / MECH, NEGATIVE, [[0.1, 0.2]])
    with pytest.raises(InputError, match=r"^params: expected a 2-D array .* got shape \(1, 2\)$") as e:
        future.result()
    assert isinstance(e.value, ValueError)


def test_reliability_on_the_cluster_raises_the_workers_error(root, dask_client):
    # The deployments run on the workers; the first that cannot be simulated
    # stops the analysis with the worker's SimulationError.
    with pytest.raises(SimulationError, match=r"^the deployment at panel_inertia:joint=1 = -[0-9.e-]+ failed: ") as e:
        deploywatch.reliability(root / MECH, vary=NEGATIVE, samples=1000, executor=dask_client)
    (why,) = e.value.causes
    assert why.startswith("panel_inertia at joint 1 would be -") and "expected > 0" in why, why


def second_client(address):
    """A second client of the session's scheduler. A connection made while
    the scheduler still cancels the tasks of the test before (an analysis
    stopped at its first failure) can read a message of that traffic as
    its handshake's reply (``assert len(msg) == 1`` inside
    ``Client._ensure_connected``): that race of dask.distributed is not
    what these tests check, so the connection is tried again."""
    from dask import distributed

    for _ in range(3):
        try:
            return distributed.Client(address)
        except AssertionError:
            time.sleep(0.5)
    return distributed.Client(address)


def test_a_closed_client_is_an_input_error(root, dask_client):
    """A ``dask.distributed.Client`` closed before the call: an
    ``InputError`` naming ``executor``, saying the client is closed and
    what to pass instead, before any task is sent (not Dask's
    ``ClosedClientError`` from inside the analysis). The cluster itself is
    left running."""
    client = second_client(dask_client.scheduler.address)
    client.close()
    assert client.status == "closed"
    with pytest.raises(InputError) as e:
        deploywatch.reliability(root / MECH, vary=["coulomb_friction:joint=1:normal(1.1,0.1)"], samples=1000,
                                executor=client)
    msg = str(e.value)
    assert msg.startswith("executor: the dask.distributed.Client is closed (status 'closed')"), msg
    assert "executor=None" in msg and "client.close()" in msg, msg
    assert dask_client.status == "running"


def test_a_client_closed_during_the_analysis_is_an_input_error(root, dask_client, monkeypatch):
    """A client closed between two batches (here: right after the first):
    the same ``InputError``, not Dask's error from inside the analysis."""
    client = second_client(dask_client.scheduler.address)
    batches = []
    make = deploywatch._api._evaluator

    def closing_after_the_first_batch(*args, **kwargs):
        evaluate = make(*args, **kwargs)

        def first_then_close(xs):
            out = evaluate(xs)
            batches.append(len(out))
            client.close()
            return out

        return first_then_close

    monkeypatch.setattr(deploywatch._api, "_evaluator", closing_after_the_first_batch)
    try:
        with pytest.raises(InputError, match=r"^executor: the dask\.distributed\.Client is closed"):
            deploywatch.reliability(root / MECH, vary=["coulomb_friction:joint=1:normal(1.1,0.1)"],
                                    method="subset", samples=1000, executor=client)
    finally:
        client.close()
    assert len(batches) == 1, "the first batch ran on the client, the second was refused"
