//! Test switches, as in `crates/hull/build.rs`: `HULLSKIN_SKIP_DXF=1` and
//! `HULLSKIN_SKIP_BROWSER=1` become the cfgs `skip_dxf` and `skip_browser`, on which the tests
//! that need ezdxf or Chromium are `#[cfg_attr(skip_<check>, ignore = ...)]` (reported by
//! `cargo test` as ignored, never as passed).

fn main() {
    for (cfg, var) in [("skip_dxf", "HULLSKIN_SKIP_DXF"), ("skip_browser", "HULLSKIN_SKIP_BROWSER")] {
        let on = std::env::var(var).as_deref() == Ok("1");
        println!("cargo::rustc-check-cfg=cfg({cfg})\ncargo::rerun-if-env-changed={var}");
        if on {
            println!("cargo::rustc-cfg={cfg}");
        }
    }
}
