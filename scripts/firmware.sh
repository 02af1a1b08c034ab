#!/usr/bin/env bash
# Builds the example firmware (firmware-example/) and replays recorded runs
# through it on QEMU's Cortex-M4 board, checking that the MCU's output is
# byte-identical with the host's f32 run of the same code.
#
# Usage:
#   scripts/firmware.sh build                 firmware ELF + host tool, prints the sizes
#   scripts/firmware.sh size                  flash / RAM of the ELF against the budget
#   scripts/firmware.sh run IN.bin OUT.bin    run the firmware on QEMU: IN.bin -> OUT.bin
#   scripts/firmware.sh replay RUN.csv [DIR]  encode, host run, QEMU run, compare
#                                             (files in DIR, default target/replay/<run>)
#   scripts/firmware.sh test                  replay the bundled reference runs (CI)
#
# The toolchain comes from scripts/embedded-toolchain.sh (run it first);
# scripts/embedded-env.sh picks the rustup or the Debian route.
# Environment: QEMU_TIMEOUT (seconds, default 300).
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
fw="$root/firmware-example"
elf="$fw/target/thumbv7em-none-eabihf/release/deploywatch-firmware-example"
host_tool="$fw/target/host/release/deploywatch-replay"
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
    (cd "$fw" && "$DW_CARGO" build --release --locked $DW_BUILD_STD)
}

build_host_tool() {
    # A host program: neither the Debian route's RUSTC nor -Zbuild-std.
    (cd "$fw/host" && env -u RUSTC -u RUSTC_BOOTSTRAP cargo build --release --locked --quiet)
    # With build.target = "host-tuple" the binary lands under the host triple.
    local triple
    triple=$(env -u RUSTC rustc -vV | sed -n 's/^host: //p')
    host_tool="$fw/target/host/$triple/release/deploywatch-replay"
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

# qemu_run IN OUT: runs the firmware on IN, writes OUT; the defmt log goes to
# stdout, decoded by defmt-print when it is installed.
qemu_run() {
    local in out
    in=$(realpath "$1")
    out=$(realpath -m "$2")
    [ -f "$in" ] || die "no input file $1"
    case "$in$out" in
        *[[:space:]]*) die "paths with spaces cannot be semihosting arguments: $in $out" ;;
    esac
    # -semihosting-config takes commas doubled inside a value.
    local args="arg=deploywatch-firmware-example,arg=${in//,/,,},arg=${out//,/,,}"
    local qemu=(qemu-system-arm -cpu cortex-m4 -machine mps2-an386 -nographic
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
    [ "$status" -eq 0 ] || die "the firmware failed on $1 (QEMU exit $status; 124 is the timeout)"
}

replay() {
    local csv=$1 dir=${2:-}
    [ -f "$csv" ] || die "no run file $csv"
    if [ -z "$dir" ]; then
        dir="$root/target/replay/$(basename "${csv%.*}")"
    fi
    mkdir -p "$dir"
    "$host_tool" encode "$csv" "$dir/input.bin"
    "$host_tool" run "$dir/input.bin" "$dir/host.bin"
    qemu_run "$dir/input.bin" "$dir/qemu.bin"
    "$host_tool" compare "$dir/host.bin" "$dir/qemu.bin"
    "$host_tool" decode "$dir/qemu.bin" >"$dir/qemu.csv"
    echo "replay of $csv: QEMU output byte-identical with the host's ($dir)"
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
        [ $# -eq 3 ] || die "usage: scripts/firmware.sh run IN.bin OUT.bin"
        build_firmware
        qemu_run "$2" "$3"
        ;;
    replay)
        [ $# -ge 2 ] && [ $# -le 3 ] || die "usage: scripts/firmware.sh replay RUN.csv [DIR]"
        build_firmware
        build_host_tool
        replay "$2" "${3:-}"
        ;;
    test)
        build_firmware
        build_host_tool
        size_report
        for run in "$root"/data/reference/seed001_T01_nominal.csv \
                   "$root"/data/reference/seed001_T02_eft.csv; do
            replay "$run"
        done
        ;;
    *)
        sed -n '2,17p' "$0" >&2
        exit 2
        ;;
esac
