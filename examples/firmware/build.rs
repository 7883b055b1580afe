//! Puts the target's memory map (`memory/<arch>.x`) on the linker search path as `memory.x`
//! (cortex-m-rt's and riscv-rt's `link.x` include it), and adds defmt's linker script for the
//! `defmt` feature.

use std::{env, fs, path::PathBuf};

fn main() {
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    let arch = env::var("CARGO_CFG_TARGET_ARCH").expect("cargo sets CARGO_CFG_TARGET_ARCH");
    let map: &[u8] = match arch.as_str() {
        "arm" => include_bytes!("memory/thumbv7em.x"),
        "riscv32" => include_bytes!("memory/riscv32.x"),
        other => panic!(
            "hsid-firmware has board support for arm (thumbv7em-none-eabihf) and riscv32 \
             (riscv32imafc-unknown-none-elf), not {other}: build with --target one of those"
        ),
    };
    fs::write(out.join("memory.x"), map).expect("write memory.x");
    println!("cargo:rustc-link-search={}", out.display());
    // defmt's linker script (its interned-string section) when the `defmt` feature is on.
    if env::var_os("CARGO_FEATURE_DEFMT").is_some() {
        println!("cargo:rustc-link-arg=-Tdefmt.x");
    }
    println!("cargo:rerun-if-changed=memory");
    println!("cargo:rerun-if-changed=build.rs");
}
