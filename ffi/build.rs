//! Gives the shared library `libccss.so` a versioned soname on ELF platforms,
//! so that programs linked against it record `libccss.so.<soversion>` and
//! keep working across compatible upgrades (`scripts/install.sh` installs
//! `libccss.so.<version>` with the `libccss.so.<soversion>` and `libccss.so`
//! links).
//!
//! soversion (semver, as cargo-c does it): the major version from 1.0 on;
//! before 1.0, where a minor bump may break the ABI, `0.<minor>`. So 0.2.x
//! has the soname `libccss.so.0.2`.
use std::env;

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    let major = env::var("CARGO_PKG_VERSION_MAJOR").unwrap_or_default();
    let minor = env::var("CARGO_PKG_VERSION_MINOR").unwrap_or_default();
    let soversion = if major == "0" {
        format!("0.{minor}")
    } else {
        major
    };
    let os = env::var("CARGO_CFG_TARGET_OS").unwrap_or_default();
    let elf = matches!(
        os.as_str(),
        "linux" | "freebsd" | "netbsd" | "openbsd" | "dragonfly" | "solaris" | "illumos"
    );
    if elf {
        // Applies to the cdylib only (not to the staticlib or the rlib).
        println!("cargo:rustc-cdylib-link-arg=-Wl,-soname,libccss.so.{soversion}");
    }
}
