# shellcheck shell=bash
# Source this file (`. scripts/embedded-env.sh`) for the commands that build
# deploywatch for the Cortex-M4F target (thumbv7em-none-eabihf).
# scripts/embedded-toolchain.sh installs what it needs; this file installs
# nothing, changes no variable the host build reads, and only looks at what
# is there.
#
# It defines:
#   DW_TARGET     thumbv7em-none-eabihf
#   DW_ROUTE      "rustup" or "debian"
#   DW_CARGO      the cargo to run
#   DW_CARGO_ENV  environment for that cargo only (empty on the rustup route)
#   DW_BUILD_STD  extra arguments of `cargo build` (empty on the rustup route)
#   dw_cargo ARGS...  runs DW_CARGO with DW_CARGO_ENV
#   dw_env_print      prints all of it and the tools found
# and returns non-zero (without exiting the caller's shell) when neither route
# is usable. Example: `dw_cargo build --release --target "$DW_TARGET" $DW_BUILD_STD`
#
# Two routes, chosen in this order:
#  1. rustup, when `rustup target list --installed` has the target: its
#     precompiled `core` is used as it is.
#  2. Debian's rustc-web, cargo-web and rust-web-src (packages): Debian ships
#     no precompiled `core` for thumbv7em-none-eabihf, so `core` and
#     `compiler_builtins` are compiled from the shipped library source with
#     cargo's `-Zbuild-std` (`compiler-builtins-mem` provides memcpy & co.,
#     which no C library does on bare metal). `-Z` flags are refused by a
#     stable toolchain unless RUSTC_BOOTSTRAP=1, which is why it is set here,
#     for these cargo commands only: rustc itself builds stable Rust (the
#     project uses no unstable feature, and the rustup route builds the same
#     code without it). RUSTC=/usr/bin/rustc makes cargo use Debian's
#     compiler, whose library source matches it, and not the rustup proxy
#     that is earlier on PATH.

DW_TARGET=thumbv7em-none-eabihf
DW_ROUTE=
DW_CARGO=
DW_CARGO_ENV=
DW_BUILD_STD=

dw_env_detect() {
    if command -v rustup >/dev/null 2>&1 \
        && rustup target list --installed 2>/dev/null | grep -qx "$DW_TARGET"; then
        DW_ROUTE=rustup
        DW_CARGO=$(command -v cargo)
        DW_CARGO_ENV=
        DW_BUILD_STD=
        return 0
    fi
    if [ -x /usr/bin/rustc ] && [ -x /usr/bin/cargo ] \
        && [ -d "$(/usr/bin/rustc --print sysroot 2>/dev/null)/lib/rustlib/src/rust/library/core" ]; then
        DW_ROUTE=debian
        DW_CARGO=/usr/bin/cargo
        # See the top of this file for why RUSTC_BOOTSTRAP.
        DW_CARGO_ENV="RUSTC=/usr/bin/rustc RUSTC_BOOTSTRAP=1"
        DW_BUILD_STD="-Zbuild-std=core,compiler_builtins -Zbuild-std-features=compiler-builtins-mem"
        return 0
    fi
    echo "embedded-env: no toolchain for $DW_TARGET: run scripts/embedded-toolchain.sh" >&2
    return 1
}

dw_cargo() {
    # shellcheck disable=SC2086 # DW_CARGO_ENV is a list of NAME=VALUE words
    env $DW_CARGO_ENV "$DW_CARGO" "$@"
}

dw_env_print() {
    echo "route:       $DW_ROUTE"
    echo "cargo:       $DW_CARGO ($(dw_cargo --version 2>/dev/null))"
    echo "rustc:       $(env $DW_CARGO_ENV sh -c '${RUSTC:-rustc} --version' 2>/dev/null)"
    echo "env:         ${DW_CARGO_ENV:-(none)}"
    echo "build:       ${DW_CARGO_ENV:+$DW_CARGO_ENV }$DW_CARGO build --release --target $DW_TARGET $DW_BUILD_STD"
    local t
    for t in arm-none-eabi-ld arm-none-eabi-size qemu-system-arm defmt-print; do
        printf '%-12s %s\n' "$t:" "$(command -v "$t" || echo 'not found')"
    done
}

dw_env_detect
