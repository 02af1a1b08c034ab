//! Puts the experiment's `memory.x` where `cortex-m-rt`'s `link.x` looks for
//! it, as firmware-example does with the workspace's.

use std::path::PathBuf;
use std::{env, fs};

fn main() {
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    let src =
        PathBuf::from(env::var_os("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR"))
            .join("memory.x");
    fs::copy(&src, out.join("memory.x"))
        .unwrap_or_else(|e| panic!("cannot copy {}: {e}", src.display()));
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed={}", src.display());
    println!("cargo:rerun-if-changed=build.rs");
}
