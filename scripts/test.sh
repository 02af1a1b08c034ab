#!/usr/bin/env bash
# Every test of deploywatch, as CI runs it (.ci/run calls exactly this).
#
#   scripts/test.sh          everything
#   scripts/test.sh --host   host checks only (fmt, clippy, cargo test, the
#                            docs' examples, Python): no embedded toolchain,
#                            no QEMU, no fuzzing
#
# Steps (each prints a header; the first failure stops the run, or its lane):
#  1. cargo fmt --check, clippy -D warnings on every target of the workspace,
#     cargo doc -D warnings (private items too: every intra-doc link resolves;
#     the Python extension crate left out, see the step)
#  2. cargo test --workspace, by cargo-nextest where the machine has it
#     (the test profile is optimised, see Cargo.toml):
#     unit tests, golden trajectories, paper vectors, monitor, identification,
#     the hidden-effect diagnosis suite, black-box CLI tests; then the
#     test-only effect of the demo-effect feature (host-sim/tests/demo_effect.rs)
# Lanes run beside that, each with its own log (target/lane-*.log, printed
# when the lane ends):
#  - from the start, beside steps 1-2 (they need nothing the host build
#    makes): the embedded toolchain and the no_std proof (3), and the
#    fuzzing (5);
#  - after step 2: docs + Python (2a-2b), and the firmware on QEMU (4),
#    which needs the test build's host binary and the toolchain.
#  2a. the docs' examples (scripts/doc-examples.py): the checker's self-test,
#     then every command shown in README.md and docs/*.md run with the
#     binary the tests built (scripts/deploywatch-bin.py) and its shown
#     output compared (synopses checked against --help; slow ones marked in
#     the doc and skipped, with the reason)
#  2a'. the docs' figures (scripts/doc-figures.py): its self-test, then no
#     measured figure in README.md, docs/*.md, the crates' READMEs and
#     manifests, and the comments of the Rust sources, outside
#     docs/measured.md and the compared example outputs;
#     every section of docs/measured.md with its command and date, every
#     link to it resolving (scripts/measured.py check)
#  2a''. the core's public surface (scripts/public-api.py --check): the
#     listing of every public item by path, from rustdoc's JSON, against
#     core/public-api.txt; fails with the diff when they differ, and when an
#     item is reachable by two paths
#  2b. the Python package (python/, a member of the workspace): .venv/ made or
#     updated by scripts/python-env.sh (the extension built once, in
#     release), then pytest, with a real Dask LocalCluster of 2 processes,
#     then mypy --strict on the package and on a program using its stubs
#  3. the embedded toolchain (installed by scripts/embedded-toolchain.sh from
#     Debian packages or an installed rustup target; never downloaded), the
#     no_std proof of the core for thumbv7em-none-eabihf with each feature
#  4. the firmware under QEMU replaying every reference mechanism, checked
#     bit-identical with the host's f32 run of the same core code
#  5. a short run of every fuzz target on its kept corpus
# After the lanes:
#  6. python/tests/test_hil.py, the Python twin of `hil`, on the firmware step
#     4 built and the package step 2b installed (it needs both)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
# A run from scratch gains nothing from incremental compilation; without it
# the workspace's build takes about 5 GB less disk.
export CARGO_INCREMENTAL=0
# pyo3's build script finds Python on the PATH and reruns when the PATH
# changes, and `cargo nextest` runs cargo with another PATH than a plain
# `cargo` has: the lanes' first cargo call compiled pyo3 and the extension
# crate again. Named once, the interpreter is the same for every call.
if [ -z "${PYO3_PYTHON:-}" ] && command -v python3 >/dev/null 2>&1; then
    export PYO3_PYTHON="$(command -v python3)"
fi
# The docs' examples and the firmware's replay run the test build's
# `deploywatch` (scripts/deploywatch-bin.py): asked for with step 2's
# selection, it is found fresh, never compiled again.
export DEPLOYWATCH_BIN_AS_TESTS=1
host_only=false
[ "${1:-}" = "--host" ] && host_only=true

# Each header gives the minutes since the start (CI's budget is per run).
start=$SECONDS
step() { printf '\n=== %s  [%d:%02d]\n' "$*" $(((SECONDS - start) / 60)) $(((SECONDS - start) % 60)); }

# lane NAME FUNCTION: runs FUNCTION in a subshell with `set -e`, its output in
# target/lane-NAME.log.
lanes="$root/target"
mkdir -p "$lanes"
lane() { (set -euo pipefail; "$2") >"$lanes/lane-$1.log" 2>&1; }
# A lane still running when the run stops early is stopped with it, and
# what it started (cargo, a fuzzer) too.
kill_tree() {
    local child
    for child in $(pgrep -P "$1" 2>/dev/null); do kill_tree "$child"; done
    kill "$1" 2>/dev/null || true
}
early_pids=()
trap 'for p in "${early_pids[@]}"; do kill_tree "$p"; done' EXIT

toolchain_and_no_std() {
    step "embedded toolchain"
    bash scripts/embedded-toolchain.sh

    step "no_std: deploywatch-core for thumbv7em-none-eabihf, each feature"
    bash scripts/check-no-std.sh
}

fuzzing() {
    step "fuzzing (short run of every target)"
    bash scripts/fuzz.sh "${FUZZ_SECONDS:-20}"
}

if ! $host_only; then
    step "lanes started beside the host checks: embedded toolchain + no_std, fuzzing (logs in target/lane-*.log)"
    lane toolchain toolchain_and_no_std & toolchain_pid=$!
    lane fuzz fuzzing & fuzz_pid=$!
    early_pids=("$toolchain_pid" "$fuzz_pid")
fi

step "format"
cargo fmt --all -- --check

step "clippy (all targets, -D warnings)"
cargo clippy --workspace --all-targets --locked -- -D warnings

step "cargo doc (-D warnings, private items: every intra-doc link resolves)"
# deploywatch-py is left out: its Rust side is not an API (the package's
# reference is docs/python.md), and rustdoc stops with an internal compiler
# error on numpy 0.23's `ToPyArray` when it documents any crate using it.
RUSTDOCFLAGS="-D warnings" cargo doc --no-deps --workspace --exclude deploywatch-py --locked --document-private-items

step "cargo test --workspace"
# cargo-nextest (on every machine of this kind; `cargo test` where it is
# missing) runs every test of every binary side by side, as many at a time
# as there are cores: `cargo test` runs the binaries one after the other,
# and a binary whose one long test runs alone leaves the other core idle.
# Each test runs in its own process; nextest does not run doc tests, the
# second command does. The examples (measurements for docs/measured.md)
# are not built here: clippy above checks every one of them.
if cargo nextest --version >/dev/null 2>&1; then
    cargo nextest run --workspace --locked --no-fail-fast --final-status-level slow --lib --bins --tests
else
    cargo test --workspace --locked --lib --bins --tests
fi
cargo test --workspace --locked --doc
# The test-only named effect (feature demo-effect): one variant and its arms
# in host-sim/src/model/effect/, simulated and diagnosed by name.
# Asked with the workspace's selection, so that the dependencies' features
# are those of the build above and only deploywatch-sim is compiled again
# (with `-p deploywatch-sim` alone, cargo resolved them anew and compiled
# a score of dependencies a second time).
cargo test --locked --workspace --features deploywatch-sim/demo-effect --test demo_effect

# After cargo test, two more lanes run side by side, each on its own log:
# the docs and Python (mostly one process at a time: the shown commands,
# pytest) and the firmware on QEMU (it needs the toolchain lane's QEMU and
# the test build's host binary). Each lane stops at its first failure; the
# run fails if any does, and prints each lane's log when it ends.
docs_and_python() {
    step "docs: every shown command run, its output compared"
    python3 scripts/doc-examples.py --self-test
    python3 scripts/doc-examples.py --check

    step "docs: no measured figure outside docs/measured.md"
    python3 scripts/doc-figures.py --self-test
    python3 scripts/doc-figures.py --check
    python3 scripts/measured.py check

    step "core: the public surface against core/public-api.txt"
    python3 scripts/public-api.py --check

    step "python package: build, pytest (Dask LocalCluster)"
    bash scripts/python-env.sh
    # pytest exits 5 when it collects no test: a failure here, like any other.
    # test_hil.py needs the serial-link firmware the other lane builds: it
    # runs whole after the lanes (step 6), never racing that build.
    .venv/bin/pytest python/tests -q --ignore=python/tests/test_hil.py || { rc=$?; [ "$rc" = 5 ] && echo "pytest collected no test"; return "$rc"; }
    # The types: the package's own sources, then a program using the installed
    # package (its py.typed and stubs; run from a folder without the sources).
    .venv/bin/mypy --strict --cache-dir target/mypy python/deploywatch python/examples
    (cd python/tests/typed && "$root/.venv/bin/mypy" --strict --cache-dir "$root/target/mypy" usage.py)
}

firmware() {
    step "firmware on QEMU: replay and bit-exact comparison"
    # The Python twin of `hil` runs after the lanes (step 6): the docs lane
    # may still be making .venv.
    # Its host tests (replay, hil) ran in step 2's cargo test.
    DW_HIL_PYTHON=0 DW_HOST_TESTS=0 bash scripts/firmware.sh test
}

if $host_only; then
    docs_and_python
    echo "host checks passed (--host: embedded, QEMU and fuzz steps skipped)"
    exit 0
fi

failed=()
# finish NAME PID: waits for lane NAME, prints its log, notes a failure.
finish() {
    local status
    if wait "$2"; then status=passed; else status=FAILED; failed+=("$1"); fi
    printf '\n----- lane %s: %s -----\n' "$1" "$status"
    cat "$lanes/lane-$1.log"
}
finish toolchain "$toolchain_pid"
step "two lanes: docs + Python, and firmware on QEMU (logs in target/lane-*.log)"
lane docs docs_and_python & docs_pid=$!
firmware_pid=
if [ ${#failed[@]} -eq 0 ]; then
    lane firmware firmware & firmware_pid=$!
fi
finish docs "$docs_pid"
[ -z "$firmware_pid" ] || finish firmware "$firmware_pid"
finish fuzz "$fuzz_pid"
early_pids=()
[ ${#failed[@]} -eq 0 ] || { echo; echo "FAILED lane(s): ${failed[*]}"; exit 1; }

step "Python twin of hil: the serial-link firmware under QEMU from deploywatch.hil"
DW_HIL_ELF="${DW_FIRMWARE_TARGET_DIR:-$root/firmware-example/target}/thumbv7em-none-eabihf/release/deploywatch-firmware-uart" \
    .venv/bin/pytest python/tests/test_hil.py -q

echo
echo "all checks passed in $(((SECONDS - start) / 60)) min $(((SECONDS - start) % 60)) s"
