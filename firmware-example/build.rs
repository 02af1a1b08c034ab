//! Puts each binary's memory map where `cortex-m-rt`'s `link.x` looks for
//! `memory.x`: the workspace's `memory.x` (60 KiB of flash) for the replay
//! firmwares of 2 and 3 joints, `memory-6.x` (60 KiB, 32 KiB of RAM) for
//! that of 6, `memory-uart.x` (64 KiB) for the serial-link firmware of 3 joints,
//! `memory-uart-6.x` (64 KiB, 32 KiB of RAM) for that of 6, each
//! in its own folder on that binary's link search path.

use std::path::{Path, PathBuf};
use std::{env, fs};

/// Copies `src` to `dir/memory.x` and links `bin` with it.
fn memory_for(bin: &str, src: &Path, dir: &Path) {
    fs::create_dir_all(dir).unwrap_or_else(|e| panic!("cannot create {}: {e}", dir.display()));
    fs::copy(src, dir.join("memory.x"))
        .unwrap_or_else(|e| panic!("cannot copy {}: {e}", src.display()));
    // The folder first, then cortex-m-rt's link.x, which INCLUDEs memory.x:
    // GNU ld reads a script when it meets its -T, with the -L paths given
    // before it.
    println!("cargo:rustc-link-arg-bin={bin}=-L{}", dir.display());
    println!("cargo:rustc-link-arg-bin={bin}=-Tlink.x");
    println!("cargo:rerun-if-changed={}", src.display());
}

fn main() {
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    let here =
        PathBuf::from(env::var_os("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR"));
    memory_for(
        "deploywatch-firmware-example",
        &here.join("../memory.x"),
        &out.join("replay"),
    );
    memory_for(
        "deploywatch-firmware-example-2",
        &here.join("../memory.x"),
        &out.join("replay-2"),
    );
    memory_for(
        "deploywatch-firmware-example-6",
        &here.join("memory-6.x"),
        &out.join("replay-6"),
    );
    memory_for(
        "deploywatch-firmware-uart",
        &here.join("memory-uart.x"),
        &out.join("uart"),
    );
    memory_for(
        "deploywatch-firmware-uart-6",
        &here.join("memory-uart-6.x"),
        &out.join("uart-6"),
    );
    println!("cargo:rerun-if-changed=build.rs");
}
