#!/usr/bin/env bash
# Installs what the embedded part of deploywatch needs, and prints what it
# uses:
#   - a Rust toolchain that builds for thumbv7em-none-eabihf (Cortex-M4F):
#     the rustup target when it is already installed; otherwise Debian's
#     rustc-web, cargo-web and rust-web-src (core is then built from source
#     with -Zbuild-std, see scripts/embedded-env.sh). It never downloads a
#     toolchain itself: rustup cannot fetch targets on this project's machines.
#   - binutils-arm-none-eabi (the linker arm-none-eabi-ld, arm-none-eabi-size)
#   - qemu-system-arm (the mps2-an386 board that runs the firmware)
#   - defmt-print (crates.io), which decodes the firmware's defmt log
#
# Idempotent: nothing is installed that is already there; `apt-get update`
# runs once, and only when a package is missing. Runs as root, or with sudo,
# non-interactively.
#
# Usage: scripts/embedded-toolchain.sh [--no-defmt-print]
# Afterwards: `. scripts/embedded-env.sh` gives the build environment.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
target=thumbv7em-none-eabihf
want_defmt_print=1
for arg in "$@"; do
    case "$arg" in
        --no-defmt-print) want_defmt_print=0 ;;
        -h|--help) sed -n '2,17p' "$0"; exit 0 ;;
        *) echo "embedded-toolchain: unknown argument: $arg" >&2; exit 2 ;;
    esac
done

log() { echo "embedded-toolchain: $*"; }

# defmt-print pinned to the defmt wire format the firmware uses (defmt 1.x).
DEFMT_PRINT_VERSION=1.2.0

have_rustup_target() {
    command -v rustup >/dev/null 2>&1 \
        && rustup target list --installed 2>/dev/null | grep -qx "$target"
}

have_debian_rust() {
    [ -x /usr/bin/rustc ] && [ -x /usr/bin/cargo ] \
        && [ -d "$(/usr/bin/rustc --print sysroot 2>/dev/null)/lib/rustlib/src/rust/library/core" ]
}

packages=()
if have_rustup_target; then
    log "rustup has $target: using it ($(rustc --version))"
elif have_debian_rust; then
    log "using Debian's Rust: $(/usr/bin/rustc --version) with its library source"
else
    log "no $target toolchain: installing Debian's rustc-web, cargo-web, rust-web-src"
    packages+=(rustc-web cargo-web rust-web-src)
fi
command -v arm-none-eabi-ld >/dev/null 2>&1 && command -v arm-none-eabi-size >/dev/null 2>&1 \
    || packages+=(binutils-arm-none-eabi)
command -v qemu-system-arm >/dev/null 2>&1 || packages+=(qemu-system-arm)

if [ ${#packages[@]} -gt 0 ]; then
    sudo=
    if [ "$(id -u)" -ne 0 ]; then
        command -v sudo >/dev/null 2>&1 || { log "need root (or sudo) to install: ${packages[*]}" >&2; exit 1; }
        sudo="sudo -E"
    fi
    export DEBIAN_FRONTEND=noninteractive
    log "apt-get update"
    $sudo apt-get update -qq
    log "apt-get install ${packages[*]}"
    $sudo apt-get install -y -qq --no-install-recommends "${packages[@]}"
else
    log "apt packages already present: nothing to install"
fi

if [ "$want_defmt_print" = 1 ]; then
    if command -v defmt-print >/dev/null 2>&1; then
        log "defmt-print present: $(defmt-print --version 2>/dev/null | head -n 1)"
    else
        # Host tool, built with whichever cargo builds for the host.
        host_cargo=$(command -v cargo || true)
        [ -n "$host_cargo" ] || host_cargo=/usr/bin/cargo
        log "cargo install defmt-print $DEFMT_PRINT_VERSION (with $host_cargo)"
        "$host_cargo" install --locked defmt-print --version "$DEFMT_PRINT_VERSION"
    fi
fi

# shellcheck source=scripts/embedded-env.sh
. "$here/embedded-env.sh"
dw_env_print
