"""The package as a package: what it exports, its version, the docstrings
`help()` shows, the stubs and `py.typed` installed with it.

    bash scripts/python-env.sh && .venv/bin/pytest python/tests/test_package.py -q
"""

import importlib.metadata
import pathlib
import pydoc
import re

import deploywatch

FUNCTIONS = ["simulate", "simulate_batch", "reliability", "parameters"]


def test_all_names_every_public_name_and_nothing_else():
    public = {n for n in dir(deploywatch) if not n.startswith("_")}
    assert public == set(deploywatch.__all__)
    for leaked in ("json", "np", "numpy", "os", "math"):
        assert leaked not in public
    for name in deploywatch.__all__:
        assert hasattr(deploywatch, name), name


def test_version_is_the_installed_distributions():
    v = deploywatch.__version__
    assert re.fullmatch(r"\d+\.\d+\.\d+", v)
    assert v == importlib.metadata.version("deploywatch")


def test_help_shows_the_docstrings():
    for name in FUNCTIONS:
        text = pydoc.render_doc(getattr(deploywatch, name), renderer=pydoc.plaintext)
        assert "Raises" in text or "order" in text, name
        assert f"{name}(" in text
    text = pydoc.render_doc(deploywatch.reliability, renderer=pydoc.plaintext)
    assert "executor" in text and "Ctrl-C" in text and "-> 'Reliability'" in text
    module = pydoc.render_doc(deploywatch, renderer=pydoc.plaintext)
    assert "DeploywatchError" in module and "simulate_batch" in module
    for cls in (deploywatch.Reliability, deploywatch.Batch, deploywatch.Trajectory, deploywatch.InputError):
        assert cls.__doc__ and len(cls.__doc__) > 40, cls
    # The extension's functions carry their docs and signatures too.
    native = deploywatch._native
    for name in FUNCTIONS:
        assert getattr(native, name).__doc__, name
        assert getattr(native, name).__text_signature__, name


def test_the_stubs_and_marker_are_installed():
    here = pathlib.Path(deploywatch.__file__).parent
    assert (here / "py.typed").is_file()
    stub = (here / "_native.pyi").read_text()
    for name in FUNCTIONS:
        assert f"def {name}(" in stub, name


def test_the_typed_usage_program_runs(root):
    # python/tests/typed/usage.py is what `mypy --strict` checks in
    # scripts/test.sh; here it runs.
    import runpy

    runpy.run_path(str(root / "python/tests/typed/usage.py"), run_name="__main__")


def test_results_pickle(root):
    # What a Dask task returns crosses processes by pickle.
    import pickle

    import numpy as np

    mech = root / "data/mechanisms/reliability_one_panel.toml"
    vary = ["coulomb_friction:joint=1:normal(1.1,0.1)"]
    run = deploywatch.simulate(mech)
    back = pickle.loads(pickle.dumps(run))
    assert np.array_equal(back.phi_deg, run.phi_deg) and back.end_s == run.end_s
    batch = deploywatch.simulate_batch(mech, vary, [[1.0], [1.6]])
    assert np.array_equal(pickle.loads(pickle.dumps(batch)).g, batch.g)
    r = deploywatch.reliability(mech, vary=vary, samples=1000, seed=2)
    assert pickle.loads(pickle.dumps(r)) == r
