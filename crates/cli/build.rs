//! Test switches, as in `crates/hull/build.rs`: `HULLSKIN_SKIP_OCCT`, `_MESH` and `_DXF` set
//! to 1 make the export tests that read our files with those tools ignored, not passed.

fn main() {
    for check in ["occt", "mesh", "dxf"] {
        let var = format!("HULLSKIN_SKIP_{}", check.to_ascii_uppercase());
        println!("cargo::rustc-check-cfg=cfg(skip_{check})");
        println!("cargo::rerun-if-env-changed={var}");
        if std::env::var(&var).as_deref() == Ok("1") {
            println!("cargo::rustc-cfg=skip_{check}");
        }
    }
}
