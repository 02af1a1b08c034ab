#!/usr/bin/env bash
# Fuzzes deploywatch's input decoders with libFuzzer (cargo fuzz): each
# target for SECONDS (default 30, the CI setting), one after the other, and
# fails if any of them crashes (a panic, an overflow, a failed oracle, a
# timeout or an out-of-memory). docs/robustness.md has the targets and the
# log of longer runs.
#
#   scripts/fuzz.sh [SECONDS] [TARGET ...]     run (all targets by default)
#   scripts/fuzz.sh --keep [SECONDS] [TARGET ...]
#                                              run, then merge the inputs that
#                                              reach new edges into fuzz/corpus/
#   scripts/fuzz.sh --cmin [TARGET ...]        minimise fuzz/corpus/<target>/
#                                              (with the seeds) to a set that
#                                              covers every edge
#
# Inputs: fuzz/corpus/<target>/ (kept in the repository, minimised) and
# fuzz/seeds/<target>/ (written by fuzz/seeds.py). What a run discovers goes
# to fuzz/target/work/<target>/ (not kept) unless --keep. A crash is saved
# under fuzz/artifacts/<target>/; replay it with
#   (cd fuzz && RUSTC_BOOTSTRAP=1 cargo fuzz run --codegen-units 16 TARGET artifacts/TARGET/crash-...)
# and turn it into a regression test before fixing it.
#
# Each target's line of results (runs, executions per second, coverage) is
# printed at the end and appended to fuzz/target/fuzz-log.tsv.
set -euo pipefail

ROOT="$(cd "$(dirname "$0")/.." && pwd)"
FUZZ="$ROOT/fuzz"
ALL_TARGETS=(run_csv mechanism_toml frame_decode monitor_update)
CARGO_FUZZ_VERSION=0.13.2

mode=run
case "${1:-}" in
--keep) mode=keep; shift ;;
--cmin) mode=cmin; shift ;;
esac
seconds=30
if [[ $mode != cmin && $# -gt 0 && $1 =~ ^[0-9]+$ ]]; then
    seconds=$1
    shift
fi
targets=("$@")
if [[ ${#targets[@]} -eq 0 ]]; then
    targets=("${ALL_TARGETS[@]}")
fi
for t in "${targets[@]}"; do
    if [[ ! -f $FUZZ/fuzz_targets/$t.rs ]]; then
        echo "fuzz.sh: unknown target '$t'; expected one of: ${ALL_TARGETS[*]}" >&2
        exit 2
    fi
done

if ! cargo fuzz --version >/dev/null 2>&1; then
    echo "fuzz.sh: installing cargo-fuzz $CARGO_FUZZ_VERSION from crates.io" >&2
    cargo install cargo-fuzz --locked --version "$CARGO_FUZZ_VERSION"
fi

# libFuzzer instrumentation needs unstable rustc flags (-Zsanitizer=address,
# -Cpasses=sancov-module, ...), which only a nightly compiler accepts. The
# machines here have the stable toolchain alone, so RUSTC_BOOTSTRAP=1 lets
# the stable compiler accept them, for this fuzz workspace only (it has its
# own target directory): the host and firmware builds stay on stable Rust.
export RUSTC_BOOTSTRAP=1

cd "$FUZZ"
# One build of every target first, so that the time budget is fuzzing time.
# Release with debug assertions (cargo fuzz's default): an overflow crashes.
# 16 codegen units instead of cargo fuzz's 1 in release: the build of
# deploywatch-sim with the sanitizer's instrumentation then uses both cores
# and takes about half as long, for somewhat fewer executions per second
# (cargo fuzz's own advice for faster builds). Every `cargo fuzz run` below
# passes the same options, or it would build again.
build=(--codegen-units 16)
cargo fuzz build "${build[@]}"

# The kept corpus is small on purpose: a set of inputs that covers every
# edge reached so far (-use_counters=0: hit counts are not features), not
# every input that ever reached a new count. A run rediscovers the depth in
# seconds; the repository keeps kilobytes, not megabytes.
if [[ $mode == cmin ]]; then
    for t in "${targets[@]}"; do
        mkdir -p "corpus/$t"
        before=$(find "corpus/$t" -type f | wc -l)
        fresh="target/cmin/$t"
        rm -rf "$fresh"
        mkdir -p "$fresh"
        cargo fuzz run "${build[@]}" "$t" "$fresh" "corpus/$t" "seeds/$t" -- \
            -set_cover_merge=1 -use_counters=0 >"target/cmin/$t.log" 2>&1
        rm -rf "corpus/$t"
        mv "$fresh" "corpus/$t"
        after=$(find "corpus/$t" -type f | wc -l)
        echo "$t: corpus $before -> $after inputs, $(cat "corpus/$t"/* 2>/dev/null | wc -c) bytes"
    done
    exit 0
fi

mkdir -p target
log="$FUZZ/target/fuzz-log.tsv"
[[ -f $log ]] || printf 'date\ttarget\tseconds\truns\texec_per_s\tcov\tresult\n' >"$log"
failed=()
summary=()
for t in "${targets[@]}"; do
    work="target/work/$t"
    mkdir -p "$work" "corpus/$t" "seeds/$t" "artifacts/$t"
    dict=()
    [[ -f dicts/$t.dict ]] && dict=("-dict=dicts/$t.dict")
    out="target/work/$t.log"
    echo "== $t: ${seconds} s" >&2
    set +e
    # -timeout: an input that takes 10 s is a hang, a crash; the corpora
    # after the work directory are read, not written.
    cargo fuzz run "${build[@]}" "$t" "$work" "corpus/$t" "seeds/$t" -- \
        -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
        -print_final_stats=1 "${dict[@]}" >"$out" 2>&1
    rc=$?
    set -e
    runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$out" | tail -1)
    eps=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$out" | tail -1)
    cov=$(grep -oE 'cov: [0-9]+' "$out" | tail -1 | cut -d' ' -f2)
    if [[ $rc -eq 0 ]]; then
        result=ok
    else
        result="CRASH (exit $rc)"
        failed+=("$t")
        grep -E 'panicked at|ERROR: libFuzzer|SUMMARY|Test unit written' "$out" | head -5 >&2 || true
    fi
    printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$(date -u +%FT%TZ)" "$t" "$seconds" "${runs:-?}" "${eps:-?}" "${cov:-?}" "$result" >>"$log"
    summary+=("$(printf '%-15s %5s s %12s runs %8s exec/s  cov %6s  %s' "$t" "$seconds" "${runs:-?}" "${eps:-?}" "${cov:-?}" "$result")")
    if [[ $mode == keep && $rc -eq 0 ]]; then
        # Keep only the inputs that reach edges the kept corpus does not.
        cargo fuzz run "${build[@]}" "$t" "corpus/$t" "$work" -- -merge=1 -use_counters=0 >/dev/null 2>&1
    fi
done

printf '%s\n' "${summary[@]}"
if [[ ${#failed[@]} -gt 0 ]]; then
    echo "fuzz.sh: crash in ${failed[*]}: see fuzz/artifacts/ and fuzz/target/work/<target>.log" >&2
    exit 1
fi
