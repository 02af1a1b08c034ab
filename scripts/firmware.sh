#!/usr/bin/env bash
# Builds the example firmware (firmware-example/) and replays recorded runs
# through it on QEMU's Cortex-M4 board, checking that the MCU's output is
# byte-identical with the host simulator's f32 run of the same monitor.
#
# Usage:
#   scripts/firmware.sh build                 firmware ELF + host tool, prints the sizes
#   scripts/firmware.sh size                  flash / RAM of the ELF against the budget
#   scripts/firmware.sh run IN.bin OUT.bin MECHANISM
#                                             run the firmware on QEMU: sample frames
#                                             IN.bin -> status frames OUT.bin
#   scripts/firmware.sh replay RUN.csv MECH.toml [DIR]
#                                             encode the run, the host's f32 monitor
#                                             run, the QEMU run, byte comparison (files
#                                             in DIR, default target/replay/<run>)
#   scripts/firmware.sh test                  replay bundled runs (CI)
#
# The toolchain comes from scripts/embedded-toolchain.sh (run it first);
# scripts/embedded-env.sh picks the rustup or the Debian route.
# Environment: QEMU_TIMEOUT (seconds, default 300).
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
fw="$root/firmware-example"
elf="$fw/target/thumbv7em-none-eabihf/release/deploywatch-firmware-example"
host_tool=  # set by build_host_tool
# The on-board budget (memory.x declares the same regions, so the link fails
# beyond them; this check reports the margin).
FLASH_BUDGET=$((64 * 1024))
RAM_BUDGET=$((16 * 1024))

die() { echo "firmware.sh: $*" >&2; exit 1; }

# shellcheck source=scripts/embedded-env.sh
. "$root/scripts/embedded-env.sh" || die "no embedded toolchain: run scripts/embedded-toolchain.sh"

build_firmware() {
    # cargo reads firmware-example/.cargo/config.toml only when run from there.
    # shellcheck disable=SC2086 # DW_BUILD_STD is a list of arguments
    (cd "$fw" && dw_cargo build --release $DW_BUILD_STD)
}

build_host_tool() {
    # A host program, built by the host's cargo.
    (cd "$fw/host" && cargo build --quiet)
    # With build.target = "host-tuple" the binary lands under the host triple.
    local triple
    triple=$(rustc -vV | sed -n 's/^host: //p')
    host_tool="$fw/target/host/$triple/debug/deploywatch-replay"
}

size_report() {
    [ -f "$elf" ] || die "no firmware ELF: run scripts/firmware.sh build"
    # Berkeley format: text (flash code + constants), data (flash and RAM),
    # bss (RAM). The stack takes the rest of RAM.
    local text data bss
    read -r text data bss _ < <(arm-none-eabi-size "$elf" | sed -n 2p)
    local flash=$((text + data)) ram=$((data + bss))
    echo "firmware: $elf"
    printf '  flash %6d B of %6d B (%3d %%)\n' "$flash" "$FLASH_BUDGET" $((100 * flash / FLASH_BUDGET))
    printf '  RAM   %6d B of %6d B (%3d %%), static data only; the stack uses the rest\n' \
        "$ram" "$RAM_BUDGET" $((100 * ram / RAM_BUDGET))
    [ "$flash" -le "$FLASH_BUDGET" ] && [ "$ram" -le "$RAM_BUDGET" ] || die "over the budget"
}

# qemu_exec IN OUT MECHANISM: runs the firmware on IN, writes OUT and returns
# QEMU's exit status (the firmware's); the defmt log goes to stdout, decoded
# by defmt-print when it is installed.
qemu_exec() {
    local in out mech=$3
    in=$(realpath "$1")
    out=$(realpath -m "$2")
    [ -f "$in" ] || die "no input file $1"
    case "$in$out$mech" in
        *[[:space:]]*) die "arguments with spaces cannot be semihosting arguments: $in $out $mech" ;;
    esac
    # -semihosting-config takes commas doubled inside a value.
    local args="arg=deploywatch-firmware-example,arg=${in//,/,,},arg=${out//,/,,},arg=${mech//,/,,}"
    # -icount shift=0: one instruction is 1 ns of virtual time, which the
    # firmware's instruction count of Monitor::update relies on.
    local qemu=(qemu-system-arm -cpu cortex-m4 -machine mps2-an386 -nographic -icount shift=0
        -semihosting-config "enable=on,target=native,$args" -kernel "$elf")
    local status=0
    if command -v defmt-print >/dev/null 2>&1; then
        set +e
        timeout "${QEMU_TIMEOUT:-300}" "${qemu[@]}" | defmt-print -e "$elf"
        local st=("${PIPESTATUS[@]}")
        set -e
        status=${st[0]}
    else
        local log="${out%.*}.defmt"
        timeout "${QEMU_TIMEOUT:-300}" "${qemu[@]}" >"$log" || status=$?
        echo "(defmt-print not installed: raw log in $log; decode with defmt-print -e $elf < $log)"
    fi
    return "$status"
}

qemu_run() {
    local status=0
    qemu_exec "$@" || status=$?
    [ "$status" -eq 0 ] || die "the firmware failed on $1 (QEMU exit $status; 124 is the timeout)"
}

# replay RUN.csv MECH.toml [DIR]
replay() {
    local csv=$1 mech=$2 dir=${3:-} name
    [ -f "$csv" ] || die "no run file $csv"
    [ -f "$mech" ] || die "no mechanism file $mech"
    if [ -z "$dir" ]; then
        dir="$root/target/replay/$(basename "$(dirname "$csv")")-$(basename "${csv%.*}")"
    fi
    mkdir -p "$dir"
    name=$("$host_tool" mechanism "$csv")
    "$host_tool" encode "$csv" "$dir/input.bin"
    "$host_tool" host "$mech" "$csv" "$dir/host.bin"
    qemu_run "$dir/input.bin" "$dir/qemu.bin" "$name"
    "$host_tool" compare "$dir/host.bin" "$dir/qemu.bin"
    "$host_tool" decode "$dir/qemu.bin" >"$dir/qemu.jsonl"
    echo "replay of $csv: the QEMU output is byte-identical with the host's f32 run ($dir)"
}

cmd=${1:-}
case "$cmd" in
    build)
        build_firmware
        build_host_tool
        size_report
        ;;
    size)
        size_report
        ;;
    run)
        [ $# -eq 4 ] || die "usage: scripts/firmware.sh run IN.bin OUT.bin MECHANISM"
        build_firmware
        qemu_run "$2" "$3" "$4"
        ;;
    replay)
        [ $# -ge 3 ] && [ $# -le 4 ] || die "usage: scripts/firmware.sh replay RUN.csv MECH.toml [DIR]"
        build_firmware
        build_host_tool
        replay "$2" "$3" "${4:-}"
        ;;
    test)
        build_firmware
        build_host_tool
        size_report
        # The replay loop and the built-in mechanisms, on the host.
        (cd "$fw/host" && cargo test --quiet)
        # A nominal run, and measured-like runs (noise, quantisation,
        # friction) of both seed 001 mechanisms.
        replay "$root/data/reference/seed001_T01_nominal.csv" "$root/data/mechanisms/seed001_T01.toml"
        for set in a_seed001_eft c_seed001_friction_harness; do
            for t in T01 T02; do
                replay "$root/data/examples/$set/seed001_$t.csv" "$root/data/mechanisms/seed001_$t.toml"
            done
        done
        # A damaged input must fail the firmware with exit 1, not hang or
        # write a partial file as if all were well.
        bad="$root/target/replay/truncated"
        mkdir -p "$bad"
        input="$root/target/replay/reference-seed001_T01_nominal/input.bin"
        head -c "$(($(stat -c %s "$input") - 2))" "$input" >"$bad/input.bin"
        status=0
        qemu_exec "$bad/input.bin" "$bad/qemu.bin" seed001-T01 || status=$?
        [ "$status" -eq 1 ] || die "a truncated input gave QEMU exit $status, expected 1"
        echo "truncated input: the firmware reports it and exits 1, as it should"
        ;;
    *)
        sed -n '2,20p' "$0" >&2
        exit 2
        ;;
esac
