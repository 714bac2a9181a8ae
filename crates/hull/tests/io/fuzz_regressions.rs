//! The fuzz targets' findings, replayed on stable Rust in every `cargo test` (docs/fuzzing.md).
//!
//! - `testdata/fuzz/<target>/` holds every input that made a target crash, hang or run out of
//!   memory, named after what it exercised. Each is run through the very function its target
//!   runs (`fuzz/src/lib.rs`, included below by path) and must return. A file named `err-*`
//!   used to panic inside a reader: it must now be refused with an error that names the
//!   source and a place in it. A file named `ok-*` is valid input whose use (slicing,
//!   digitising, evaluating) used to panic: it must parse.
//! - The committed seeds of `fuzz/seeds/` parse, and the four forms of the seed mesh (ASCII,
//!   binary, gzipped STL, OBJ) read to the same mesh.
//! - `fuzz_smoke`: a few thousand inputs per target, mutated from the seeds by a fixed-seed
//!   ChaCha generator the way libFuzzer mutates (bit flips, inserted dictionary words, cut,
//!   copied and spliced runs), must each give `Ok` or `Err`, never a panic. This is the part
//!   of the fuzzing that CI runs; `cargo fuzz` explores far more.

#[path = "../../../../fuzz/src/lib.rs"]
mod fuzz_targets;

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};

use fuzz_targets::{target, Target, TARGETS};
use hull::{parse_mesh, MeshReadOptions};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn files_in(dir: &Path) -> Vec<PathBuf> {
    let mut out: Vec<PathBuf> = match std::fs::read_dir(dir) {
        Ok(entries) => entries.filter_map(Result::ok).map(|e| e.path()).filter(|p| p.is_file()).collect(),
        Err(_) => Vec::new(),
    };
    out.sort();
    out
}

fn read(path: &Path) -> Vec<u8> {
    std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Runs `t` on `data`, turning a panic into `Err` with the panic's message.
fn run(t: Target, data: &[u8], source: &str) -> Result<Result<(), String>, String> {
    catch_unwind(AssertUnwindSafe(|| t(data, source))).map_err(|p| {
        p.downcast_ref::<String>()
            .cloned()
            .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
            .unwrap_or_else(|| "a panic".into())
    })
}

/// True if `message` names `source` followed by a place: `source:LINE` (with an optional
/// `:COLUMN`), or `source: ...byte offset N` / `...byte N` for binary formats. The surface
/// JSON reader, which is not given a source name, must give `line L, column C` or the key.
fn names_a_place(message: &str, source: &str, target_name: &str) -> bool {
    if target_name == "surface_json" {
        return message.contains(", line ") || message.contains("\"");
    }
    let Some(rest) = message.find(source).map(|i| &message[i + source.len()..]) else { return false };
    let rest = rest.strip_prefix(':').unwrap_or("");
    rest.starts_with(|c: char| c.is_ascii_digit()) || rest.contains("byte")
}

#[test]
fn every_regression_input_returns_and_former_panics_name_their_place() {
    let dir = root().join("testdata/fuzz");
    let mut failures = Vec::new();
    let mut count = 0;
    for sub in std::fs::read_dir(&dir).map(|d| d.filter_map(Result::ok).map(|e| e.path())).into_iter().flatten() {
        if !sub.is_dir() {
            continue;
        }
        let name = sub.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        let t = target(&name).unwrap_or_else(|| panic!("testdata/fuzz/{name}: no fuzz target of that name"));
        for file in files_in(&sub) {
            count += 1;
            let source = file.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
            match run(t, &read(&file), &source) {
                Err(panic) => failures.push(format!("{name}/{source}: panicked: {panic}")),
                Ok(result) if source.starts_with("err-") => match result {
                    Ok(()) => failures.push(format!("{name}/{source}: read without error, expected a refusal")),
                    Err(m) if !names_a_place(&m, &source, &name) => {
                        failures.push(format!("{name}/{source}: the error does not name the source and a place: {m}"))
                    }
                    Err(_) => {}
                },
                Ok(Err(m)) if source.starts_with("ok-") => {
                    failures.push(format!("{name}/{source}: expected to parse: {m}"))
                }
                Ok(_) => {}
            }
        }
    }
    assert!(count > 0, "no regression inputs found in {}", dir.display());
    assert!(failures.is_empty(), "{} of {count} regression inputs fail:\n{}", failures.len(), failures.join("\n"));
}

/// The inputs each target starts from: the committed seeds (`fuzz/seeds/`), small inputs of
/// `testdata/` (as `fuzz/seed_corpora.py` picks them), and the target's regression inputs.
fn seeds(name: &str) -> Vec<Vec<u8>> {
    let r = root();
    let td = |n: &str| r.join("testdata").join(n);
    let seed_dir = |n: &str| files_in(&r.join("fuzz/seeds").join(n));
    let offsets = vec![
        td("sections_example.csv"),
        td("offsets_example.csv"),
        td("series60_cb060_offsets.csv"),
        td("wigley_offsets.csv"),
        td("freeship_curves_example.txt"),
        td("freeship_wigley_offsets.txt"),
        td("raw/series60/cb0p6.csv"),
        td("raw/cargo116/principals.json"),
        td("peers/cargo116_wl.csv"),
    ];
    let mut paths: Vec<PathBuf> = match name {
        "read_json_table" => [seed_dir("json_table"), vec![td("raw/cargo116/offsets_table.json")]].concat(),
        "mesh_stl" => seed_dir("mesh").into_iter().filter(|p| p.extension().is_some_and(|e| e == "stl")).collect(),
        "mesh_obj" => seed_dir("mesh").into_iter().filter(|p| p.extension().is_some_and(|e| e == "obj")).collect(),
        "mesh_vrml" => seed_dir("mesh").into_iter().filter(|p| p.extension().is_some_and(|e| e == "wrl")).collect(),
        "mesh_parse_slice" => seed_dir("mesh"),
        "drawing_dxf" | "drawing_svg" | "drawing_digitize" => {
            let ext = match name {
                "drawing_dxf" => "dxf",
                "drawing_svg" => "svg",
                _ => "",
            };
            [seed_dir("drawing"), files_in(&td("digitize"))]
                .concat()
                .into_iter()
                .filter(|p| p.extension().is_some_and(|e| e == ext || (ext.is_empty() && e != "md")))
                .collect()
        }
        "surface_json" => seed_dir("surface_json"),
        "read_iges" | "read_step" => {
            let ext = if name == "read_iges" { "igs" } else { "stp" };
            seed_dir("cad").into_iter().filter(|p| p.extension().is_some_and(|e| e == ext)).collect()
        }
        "read_detect" => [offsets, seed_dir("json_table")].concat(),
        _ => offsets,
    };
    paths.extend(files_in(&td("fuzz").join(name)));
    paths.iter().map(|p| read(p)).collect()
}

#[test]
fn the_committed_seeds_parse() {
    for (name, dir, ext) in [
        ("mesh_parse_slice", "mesh", ""),
        ("read_json_table", "json_table", ""),
        ("drawing_digitize", "drawing", ""),
        ("surface_json", "surface_json", ""),
        ("read_iges", "cad", "igs"),
        ("read_step", "cad", "stp"),
    ] {
        let t = target(name).expect("a target of the list");
        let files: Vec<PathBuf> = files_in(&root().join("fuzz/seeds").join(dir))
            .into_iter()
            .filter(|p| ext.is_empty() || p.extension().is_some_and(|e| e == ext))
            .collect();
        assert!(!files.is_empty(), "fuzz/seeds/{dir} has no {name} seed");
        for f in files {
            let source = f.display().to_string();
            let result = run(t, &read(&f), &source).unwrap_or_else(|p| panic!("{source}: panicked: {p}"));
            assert_eq!(result, Ok(()), "{source}");
        }
    }
}

#[test]
fn the_seed_mesh_reads_the_same_from_each_of_its_five_forms() {
    let dir = root().join("fuzz/seeds/mesh");
    let mesh = |n: &str| {
        parse_mesh(&read(&dir.join(n)), n, None, &MeshReadOptions::default()).unwrap_or_else(|e| panic!("{n}: {e}"))
    };
    let ascii = mesh("wigley_ascii.stl");
    assert!(ascii.triangles.len() >= 20 && ascii.degenerate == 0, "{} triangles", ascii.triangles.len());
    let edges = ascii.edge_counts();
    assert_eq!((edges.open, edges.non_manifold), (0, 0), "the seed hull is closed and manifold");
    let gz = mesh("wigley_ascii.stl.gz");
    assert_eq!((&gz.vertices, &gz.triangles), (&ascii.vertices, &ascii.triangles), "gzip changes nothing");
    // The OBJ numbers its vertices in its own order: compare the triangles' corners.
    let corners = |m: &hull::TriMesh| (0..m.triangles.len()).map(|t| m.corners(t)).collect::<Vec<_>>();
    assert_eq!(corners(&mesh("wigley.obj")), corners(&ascii));
    assert_eq!(corners(&mesh("wigley.wrl")), corners(&ascii));
    let binary = mesh("wigley_binary.stl");
    assert_eq!(binary.triangles, ascii.triangles);
    for (b, a) in corners(&binary).iter().flatten().zip(corners(&ascii).iter().flatten()) {
        // Binary STL stores f32: a relative rounding of at most 2^-24 (6e-8) of |c| <= 10 m.
        assert!(b.distance(*a) <= 1e-6, "{b:?} vs {a:?}");
    }
}

/// The words of a libFuzzer dictionary (`fuzz/dicts/*.dict`), unescaped.
fn dictionary(file: &str) -> Vec<Vec<u8>> {
    let text = String::from_utf8(read(&root().join("fuzz/dicts").join(file))).expect("UTF-8 dictionary");
    let mut words = Vec::new();
    for line in text.lines().filter(|l| l.starts_with('"')) {
        let body = line.trim_end().trim_matches('"').as_bytes();
        let mut word = Vec::new();
        let mut i = 0;
        while i < body.len() {
            match (body[i], body.get(i + 1)) {
                (b'\\', Some(b'x')) => {
                    let hex = std::str::from_utf8(&body[i + 2..i + 4]).expect("ASCII escape");
                    word.push(u8::from_str_radix(hex, 16).expect("hex escape"));
                    i += 4;
                }
                (b'\\', Some(&c)) => {
                    word.push(c);
                    i += 2;
                }
                (c, _) => {
                    word.push(c);
                    i += 1;
                }
            }
        }
        words.push(word);
    }
    assert!(!words.is_empty(), "{file}: no words");
    words
}

fn dictionary_of(name: &str) -> &'static str {
    match name {
        "read_json_table" => "json.dict",
        "surface_json" => "surface.dict",
        "read_iges" => "iges.dict",
        "read_step" => "step.dict",
        "mesh_stl" | "mesh_parse_slice" => "stl.dict",
        "mesh_obj" => "obj.dict",
        "mesh_vrml" => "vrml.dict",
        "drawing_dxf" | "drawing_digitize" => "dxf.dict",
        "drawing_svg" => "svg.dict",
        _ => "csv.dict",
    }
}

/// One to four libFuzzer-like mutations of `input`.
fn mutate(rng: &mut ChaCha8Rng, input: &[u8], others: &[Vec<u8>], words: &[Vec<u8>]) -> Vec<u8> {
    let mut v = input.to_vec();
    for _ in 0..rng.random_range(1..=4) {
        let n = v.len();
        let at = rng.random_range(0..=n);
        match rng.random_range(0..8) {
            0 if n > 0 => {
                let i = rng.random_range(0..n);
                v[i] ^= 1 << rng.random_range(0..8);
            }
            1 => v.insert(at, rng.random()),
            2 if n > 0 => {
                let i = rng.random_range(0..n);
                let len = rng.random_range(1..=(n - i).min(64));
                v.drain(i..i + len);
            }
            3 => {
                let w = &words[rng.random_range(0..words.len())];
                v.splice(at..at, w.iter().copied());
            }
            4 if n > 0 => {
                // Copy a run elsewhere (repeats rows, keywords, numbers).
                let i = rng.random_range(0..n);
                let run: Vec<u8> = v[i..(i + rng.random_range(1..=64)).min(n)].to_vec();
                v.splice(at..at, run);
            }
            5 => v.truncate(at),
            6 if !others.is_empty() => {
                // Splice: our head, another seed's tail.
                let o = &others[rng.random_range(0..others.len())];
                let from = rng.random_range(0..=o.len());
                v.truncate(at);
                v.extend_from_slice(&o[from..]);
            }
            _ => {
                // A digit or sign changed: numbers out of range, negative counts.
                let digits = b"0123456789-.eE+";
                if n > 0 {
                    let i = rng.random_range(0..n);
                    v[i] = digits[rng.random_range(0..digits.len())];
                }
            }
        }
    }
    v
}

/// Mutated inputs per target: the mesh and drawing targets slice or digitise each input they
/// read, which costs more in a debug build.
fn smoke_cases(name: &str) -> usize {
    match name {
        "mesh_parse_slice" | "drawing_digitize" | "surface_json" => 1000,
        _ => 2000,
    }
}

/// `FUZZ_SMOKE_ONLY=<target>` runs one target; `FUZZ_SMOKE_TRACE=<file>` writes each input to
/// the file before running it, so that after an abort (out of memory) or a hang the file holds
/// the input to blame.
#[test]
fn fuzz_smoke() {
    let only = std::env::var("FUZZ_SMOKE_ONLY").ok();
    let trace = std::env::var_os("FUZZ_SMOKE_TRACE").map(PathBuf::from);
    let mut failures = Vec::new();
    for &(name, t) in TARGETS {
        if only.as_deref().is_some_and(|o| o != name) {
            continue;
        }
        let seeds = seeds(name);
        assert!(!seeds.is_empty(), "{name}: no seeds");
        let words = dictionary(dictionary_of(name));
        // One generator per target, seeded by its name: adding a target leaves the others'
        // inputs as they were.
        let seed =
            name.bytes().fold(0xcbf2_9ce4_8422_2325_u64, |h, b| (h ^ u64::from(b)).wrapping_mul(0x100_0000_01b3));
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let (mut ok, mut err) = (0, 0);
        for case in 0..smoke_cases(name) {
            let base = &seeds[rng.random_range(0..seeds.len())];
            let input = mutate(&mut rng, base, &seeds, &words);
            if let Some(trace) = &trace {
                std::fs::write(trace, &input).unwrap_or_else(|e| panic!("{}: {e}", trace.display()));
            }
            match run(t, &input, "smoke") {
                Ok(Ok(())) => ok += 1,
                Ok(Err(_)) => err += 1,
                Err(panic) => {
                    let shown = String::from_utf8_lossy(&input[..input.len().min(400)]).into_owned();
                    failures.push(format!("{name} case {case}: panicked: {panic}\ninput: {shown:?}"));
                }
            }
        }
        // The mutations must leave some inputs readable, or only the first checks are fuzzed.
        assert!(ok > 0 && err > 0, "{name}: {ok} inputs read, {err} refused: the mutations miss one side");
    }
    assert!(failures.is_empty(), "{} panics:\n{}", failures.len(), failures.join("\n\n"));
}
