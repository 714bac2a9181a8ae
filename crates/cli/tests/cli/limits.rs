//! The documented caps end to end (hull's `MAX_*` constants, README "Limits"): inputs and
//! settings above them are refused quickly with the count, the cap and what was expected, exit
//! status 2, and no output written.

use std::fs;

use crate::common::*;

/// Run `args` in a fresh directory; assert a refusal whose message contains `needle`, and that
/// no output directory was made.
fn refused(args: &[&str], setup: impl FnOnce(&std::path::Path), needle: &str) {
    let dir = temp_dir();
    setup(dir.path());
    let o = hullskin(dir.path(), args);
    let (out, err) = text(&o);
    assert_eq!(o.status.code(), Some(2), "stdout {out}\nstderr {err}");
    assert!(err.contains(needle), "{err}");
    assert!(err.contains("see README Limits"), "{err}");
    assert!(!dir.path().join("out").exists(), "nothing written");
}

#[test]
fn an_offsets_file_above_the_size_cap_is_refused() {
    // A sparse 300 MiB file, refused from its length (that the length alone refuses it, before
    // any read, is hull's unit test `large_files_are_refused_before_reading` in limits.rs; a wall
    // time asserted here failed on a loaded machine, 6.7 s against 5).
    refused(
        &["fit", "big.csv", "-o", "out"],
        |d| fs::File::create(d.join("big.csv")).expect("create").set_len(300 << 20).expect("sparse"),
        "big.csv: 314,572,800 bytes exceed the cap of 268,435,456 (expected an offsets file of at most 256 MiB",
    );
}

#[test]
fn control_points_and_optimiser_sizes_above_the_caps_are_refused() {
    refused(
        &["fit", "-o", "out", "--ctrl", "4,100001"],
        |_| {},
        "100,001 control points along v exceed the cap of 100,000",
    );
    refused(
        &["fit", "-o", "out", "--method", "ga", "--iterations", "2000000"],
        |_| {},
        "2,000,000 optimisation iterations exceed the cap of 1,000,000",
    );
}

#[test]
fn a_binary_stl_claiming_billions_of_triangles_is_refused_from_its_header() {
    // 84 bytes claiming 4,000,000,000 triangles (200 GB of records): refused by the size check
    // before any triangle is allocated.
    let dir = temp_dir();
    let mut stl = vec![0u8; 80];
    stl.extend_from_slice(&4_000_000_000u32.to_le_bytes());
    fs::write(dir.path().join("hull.stl"), &stl).expect("write");
    let o = hullskin(dir.path(), &["slice", "hull.stl", "-o", "out.csv"]);
    let (_, err) = text(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("claims 4000000000 triangles"), "{err}");
    assert!(!dir.path().join("out.csv").exists());
}
