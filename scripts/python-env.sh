#!/usr/bin/env bash
# The Python environment of deploywatch: `.venv/` at the repository root
# with pinned maturin, numpy, pytest, dask[distributed], mypy, pandas (the
# `to_pandas()` views) and mujoco (the second
# opinion engine of python/tests/test_second_opinion.py) from PyPI, and the
# `deploywatch` package (python/, PyO3 + maturin) built in release and
# installed. Idempotent: a second run with nothing changed takes a second.
#
#   bash scripts/python-env.sh && .venv/bin/pytest python/tests -q
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"

pins="maturin==1.16.0 numpy==2.4.6 pytest==9.2.0 dask[distributed]==2026.8.0 mypy==2.4.1 mujoco==4.0.0 pandas==3.1.1"
venv=.venv
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
if [ "$(cat "$venv/.deploywatch-pins" 2>/dev/null)" != "$pins" ]; then
    echo "python-env: installing $pins"
    # shellcheck disable=SC2086
    "$venv/bin/pip" install -q $pins
    echo "$pins" > "$venv/.deploywatch-pins"
fi

# Rebuild the extension only when a source it is built from changed.
stamp="$venv/.deploywatch-built"
if [ -f "$stamp" ] && [ -z "$(find python/src python/deploywatch python/Cargo.toml Cargo.lock \
        python/pyproject.toml Cargo.toml host-sim/src host-sim/Cargo.toml core/src core/Cargo.toml \
        -newer "$stamp" -print -quit)" ]; then
    echo "python-env: deploywatch is up to date in $venv"
    exit 0
fi
echo "python-env: building the deploywatch extension (release)"
# The workspace's target directory: the release build of the `deploywatch`
# binary (scripts/doc-examples.py) and this one share their dependencies.
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$root/target}"
wheels="$CARGO_TARGET_DIR/wheels"
rm -f "$wheels"/deploywatch-*.whl
"$venv/bin/maturin" build --release --locked -q -m python/Cargo.toml -i "$venv/bin/python" --out "$wheels"
"$venv/bin/pip" install -q --force-reinstall --no-deps "$wheels"/deploywatch-*.whl
touch "$stamp"
echo "python-env: deploywatch installed in $venv"
