//! Test switches: each `HULLSKIN_SKIP_<CHECK>=1` becomes the cfg `skip_<check>`, on which the
//! tests that need an outside program (Open CASCADE, trimesh, ezdxf, Chromium, the Khronos glTF
//! validator) are `#[cfg_attr(skip_<check>, ignore = ...)]`: a skipped check is reported by
//! `cargo test` as ignored, never as passed. Nothing else depends on these variables.

fn main() {
    for check in ["occt", "mesh", "dxf", "browser", "gltf_validator"] {
        let var = format!("HULLSKIN_SKIP_{}", check.to_ascii_uppercase());
        println!("cargo::rustc-check-cfg=cfg(skip_{check})");
        println!("cargo::rerun-if-env-changed={var}");
        if std::env::var(&var).as_deref() == Ok("1") {
            println!("cargo::rustc-cfg=skip_{check}");
        }
    }
}
