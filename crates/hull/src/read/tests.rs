use super::records::delimiter_of;
use super::*;

fn texts(recs: &[Record<'_>]) -> Vec<(usize, Vec<String>)> {
    recs.iter().map(|r| (r.line, r.fields.iter().map(|f| f.text.to_string()).collect())).collect()
}

fn err_of<T: std::fmt::Debug>(r: Result<T, HullError>) -> String {
    r.err().map(|e| e.to_string()).unwrap_or_else(|| "no error".into())
}

#[test]
fn line_ends_bom_comments_and_blank_lines() {
    let text = "\u{FEFF}a, b ,c\r\n\r\n# comment\n  \n, ,\r4,5\n";
    let recs = records(text, "t").expect("valid text");
    assert_eq!(texts(&recs), vec![(1, vec!["a".into(), "b".into(), "c".into()]), (6, vec!["4".into(), "5".into()])]);
}

#[test]
fn line_numbers_count_every_line_whatever_the_line_ends() {
    for nl in ["\n", "\r\n", "\r"] {
        let text = ["x", "", "y", "", "", "z"].join(nl) + nl;
        let lines: Vec<usize> = records(&text, "t").expect("valid").iter().map(|r| r.line).collect();
        assert_eq!(lines, vec![1, 3, 6], "line end {nl:?}");
    }
}

#[test]
fn quoted_fields() {
    let recs = records("\"a,b\", \"say \"\"hi\"\"\" ,\"\"\n", "t").expect("valid");
    assert_eq!(texts(&recs), vec![(1, vec!["a,b".into(), "say \"hi\"".into(), "".into()])]);
    assert_eq!(
        err_of(records("a,\"open\n", "q.csv")),
        "q.csv:1:2: quoted field has no closing quote (expected a closing \" on the same line)"
    );
    assert!(err_of(records("x\na,\"b\"c,d\n", "q.csv")).starts_with("q.csv:2:2: text \"c\" follows the closing quote"));
}

#[test]
fn trailing_empty_fields_are_kept_but_not_significant() {
    let recs = records("1,,3,,\n", "t").expect("valid");
    assert_eq!(texts(&recs), vec![(1, vec!["1".into(), "".into(), "3".into(), "".into(), "".into()])]);
    assert_eq!(recs[0].fields[2].column, 3);
    assert_eq!(recs[0].significant_len(), 3);
}

#[test]
fn other_separators_are_named() {
    assert_eq!(
        err_of(records("# c\nsection,x,y,z\na;1;2;3\n", "s.csv")),
        "s.csv:3: fields are separated by semicolons (expected commas, as on the file's first data line: one \
         delimiter for the whole file)"
    );
    assert!(err_of(records("a,b\nc\td\n", "s.csv")).contains("separated by tabs"));
    assert_eq!(
        err_of(records("\n# c\na;b\nc;d\ne,1,2\n", "s.csv")),
        "s.csv:5: fields are separated by commas (expected semicolons as on line 3, the file's first data \
         line: one delimiter for the whole file)"
    );
    assert!(err_of(records("a\tb\nc,d,e\n", "s.csv")).contains("expected tabs as on line 1"));
}

#[test]
fn semicolon_and_tab_files_take_decimal_commas() {
    let want =
        vec![(1, vec!["s".to_string(), "x".into(), "y".into()]), (2, vec!["a".into(), "1.5".into(), "-0.25".into()])];
    // A European spreadsheet's CSV, with CRLF and a BOM.
    assert_eq!(texts(&records("\u{FEFF}s;x;y\r\na;1,5;-0,25\r\n", "t").expect("valid")), want);
    // Tabs (a spreadsheet's text export); the tab is the delimiter, not a blank to trim.
    assert_eq!(texts(&records("s\tx\ty\na\t1,5\t-0,25\n", "t").expect("valid")), want);
    assert_eq!(texts(&records("s\tx\ty\na\t1.5 \t -0.25\n", "t").expect("valid")), want);
    // A quoted cell, exponents, a label that is no number, and grouped thousands left alone
    // (the reader then says that "1.000,5" is not a number).
    let recs = records("s;x\na;\"2,45\";1,5E-3;B,C;1.000,5;1,2,3\n", "t").expect("valid");
    assert_eq!(texts(&recs)[1].1, vec!["a", "2.45", "1.5E-3", "B,C", "1.000,5", "1,2,3"]);
    // Only a `;` or tab file converts: in a comma file `1,5` is two fields.
    assert_eq!(texts(&records("a,1,5\n", "t").expect("valid"))[0].1, vec!["a", "1", "5"]);
    // The first data line sets the delimiter, even a line of decimal commas only; a comma
    // file aligned with tabs, or with a `;` in a label, stays a comma file.
    assert_eq!(delimiter_of("z\\x;0;2,5;5"), ';');
    assert_eq!(delimiter_of("0,5;1,5;2,5"), ';');
    assert_eq!(delimiter_of("z\\x\t0\t2,5\t5"), '\t');
    assert_eq!(delimiter_of("0,\t1.5,\t2"), ',');
    assert_eq!(delimiter_of("\"a;b\",1,2,3"), ',');
    assert_eq!(delimiter_of("section,x,y,z"), ',');
}

#[test]
fn long_fields_are_shortened_in_messages() {
    let long = "9".repeat(10_000) + "x";
    let e = err_of(parse_number(&long, || Location::new("n.csv", 1, 1), || "a number".into()));
    assert!(e.len() < 200, "{e}");
    assert!(e.contains(&format!("\"{}... (10001 characters)\" is not a number", "9".repeat(64))), "{e}");
    assert_eq!(shown("é".repeat(64).as_str()), "é".repeat(64));
}

#[test]
fn binary_input_is_recognised() {
    assert_eq!(
        err_of(decode(b"ab\ncd\0", "b.bin")),
        "b.bin:2: binary file, NUL byte at byte offset 5 (expected a CSV text)"
    );
    assert_eq!(
        err_of(decode(b"a\nb\nc\xff", "b.bin")),
        "b.bin:3: binary file, invalid UTF-8 at byte offset 5 (expected a CSV text)"
    );
    assert!(err_of(decode(b"\xff\xfes\0e\0", "u.csv")).contains("UTF-16"));
    // Without a byte-order mark, little- and big-endian, told by the NUL of every other byte.
    assert_eq!(err_of(decode(b"s\0e\0c\0\n\0", "u.csv")), err_of(decode(b"\xff\xfes\0", "u.csv")));
    assert!(err_of(decode(b"\0s\0e\0c\0\n", "u.csv")).contains("UTF-16"));
    assert!(err_of(decode(b"ab\0\0", "b.bin")).contains("NUL byte"));
    assert!(err_of(records("a\0", "s")).contains("binary file"));
    assert_eq!(decode(b"ok", "s").ok(), Some("ok"));
}

#[test]
fn numbers() {
    let at = || Location::new("n.csv", 3, 2);
    let what = || "the x coordinate in metres".to_string();
    for (t, v) in [("1", 1.0), ("-2.5", -2.5), ("+.5", 0.5), ("1e3", 1000.0), ("7.", 7.0), ("-0", 0.0)] {
        assert_eq!(parse_number(t, at, what).ok(), Some(v), "{t}");
    }
    for t in ["nan", "NaN", "inf", "-Infinity", "1e999"] {
        assert_eq!(
            err_of(parse_number(t, at, what)),
            format!("n.csv:3:2: \"{t}\" is not a finite number (expected the x coordinate in metres)")
        );
    }
    assert_eq!(
        err_of(parse_number("abc", at, what)),
        "n.csv:3:2: \"abc\" is not a number (expected the x coordinate in metres)"
    );
    assert_eq!(
        err_of(parse_number("1,5", at, what)),
        "n.csv:3:2: \"1,5\" has a decimal comma (expected the x coordinate in metres, written with a decimal point)"
    );
    assert_eq!(err_of(parse_number("", at, what)), "n.csv:3:2: empty field (expected the x coordinate in metres)");
    assert!(err_of(parse_number("0x10", at, what)).contains("is not a number"));
}

#[test]
fn format_detection() {
    assert_eq!(detect_format("\u{FEFF}# c\n Section , X,y,z\n"), InputFormat::SectionsCsv);
    assert_eq!(detect_format("z\\x,0,1\n0,1,2\n"), InputFormat::OffsetTable);
    assert_eq!(detect_format(""), InputFormat::OffsetTable);
    assert_eq!(detect_format(",,\n\n# section,x,y,z\nsection,x,y,z\n"), InputFormat::SectionsCsv);
    // A header naming x, y and z columns (and a label column) is a long CSV.
    assert_eq!(detect_format("sections,x,y,z\n"), InputFormat::LongCsv);
    assert_eq!(detect_format("x,z,y\n1,2,3\n"), InputFormat::LongCsv);
    assert_eq!(detect_format(",0,0.5,1,SAR\n0,0,0,0,0\nMaxBm,1,1,1\n"), InputFormat::Series60Table);
    assert_eq!(detect_format("{\"a\": 1}"), InputFormat::JsonTable);
    assert_eq!(detect_format("  1.0  2.0  3.0\n"), InputFormat::PointCloud);
    assert_eq!(detect_format("station 3 x = 1\n0 0\n1 1\n"), InputFormat::PointCloud);
    assert_eq!(detect_format("0\n1 2 3\n"), InputFormat::FreeshipCurves);
    assert_eq!(detect_format("Station 12.000\n  12.0 0.0 1.0\n"), InputFormat::FreeshipOffsets);
    assert_eq!(detect_format("section\tx\ty\tz\n"), InputFormat::SectionsCsv);
    assert_eq!(detect_format("section;x;y;z\n"), InputFormat::SectionsCsv);
    assert_eq!(detect_format("z\\x\t0\t2,5\n0\t1,5\t2\n"), InputFormat::OffsetTable);
}

fn testdata(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../testdata").join(name)
}

#[test]
fn read_offsets_sniffs_both_example_files() {
    let s = read_offsets(&testdata("sections_example.csv"), Units::Metre).expect("sections example");
    assert_eq!((s.sections.len(), s.num_points()), (3, 12));
    assert!(s.source.ends_with("sections_example.csv"));
    let t = read_offsets(&testdata("offsets_example.csv"), Units::Foot).expect("offsets example");
    assert_eq!((t.sections.len(), t.num_points(), t.units), (4, 19, Units::Foot));
}

#[test]
fn an_offset_table_rewritten_as_a_sections_csv_reads_back_the_same() {
    let table = read_offsets(&testdata("offsets_example.csv"), Units::Metre).expect("offsets example");
    let mut text = String::from("section,x,y,z\n");
    for s in &table.sections {
        for p in &s.points {
            // `{}` prints the shortest decimal that parses back to the same f64.
            text.push_str(&format!("{},{},{},{}\n", s.label, p.x, p.y, p.z));
        }
    }
    let csv = parse_offsets(&text, "rewritten.csv", Units::Metre).expect("rewritten");
    assert_eq!(csv.sections.len(), table.sections.len());
    for (a, b) in csv.sections.iter().zip(&table.sections) {
        assert_eq!((&a.label, &a.points), (&b.label, &b.points));
    }
}

#[test]
fn min_points_drops_short_sections_of_the_new_formats_only() {
    let cloud = "0 0 0\n0 1 1\n0 2 2\n5 0 0\n5 1 1\n";
    let options = ReadOptions { min_points: 3, ..ReadOptions::default() };
    let o = parse_offsets_with(cloud, "c.dat", &options).expect("valid");
    assert_eq!(o.offsets.sections.len(), 1);
    assert!(o.notes.iter().any(|n| n == "sections with fewer than 3 points left out: x5 (2)"), "{:?}", o.notes);
    let csv = "section,x,y,z\na,0,0,0\na,0,1,1\na,0,2,2\nb,5,0,0\nb,5,1,1\n";
    let o = parse_offsets_with(csv, "s.csv", &options).expect("valid");
    assert_eq!(o.offsets.sections.len(), 2, "a sections CSV keeps them for validate to report");
}

#[test]
fn read_offsets_reports_a_missing_file_with_its_path() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("missing.csv");
    let e = err_of(read_offsets(&path, Units::Metre));
    assert!(e.starts_with(&format!("{}: ", path.display())), "{e}");
}

#[test]
fn read_offsets_reports_a_binary_file() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("hull.png");
    std::fs::write(&path, b"\x89PNG\r\n\x1a\n\0\0\0\rIHDR").expect("write");
    let e = err_of(read_offsets(&path, Units::Metre));
    assert_eq!(e, format!("{}:1: binary file, invalid UTF-8 at byte offset 0 (expected a CSV text)", path.display()));
}

#[cfg(test)]
mod fuzz {
    //! The readers never panic: any input gives `Ok` or `Err`.

    use super::*;
    use proptest::prelude::*;

    fn all_readers(text: &str) {
        for units in Units::ALL {
            let _ = parse_sections_csv(text, "f", units);
            let _ = parse_offset_table(text, "f", units);
            let _ = parse_offsets(text, "f", units);
        }
        for format in InputFormat::ALL {
            let options = ReadOptions {
                format: Some(format),
                dimensions: Some(MainDimensions { lpp: 100.0, beam: 10.0, draft: 5.0 }),
                ..ReadOptions::default()
            };
            let _ = parse_offsets_with(text, "f", &options);
        }
        if let Ok(o) = parse_offsets(text, "f", Units::Metre) {
            let _ = o.validate(4);
            let _ = o.validate(0);
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]

        #[test]
        fn arbitrary_strings_never_panic(text in any::<String>()) {
            all_readers(&text);
        }

        #[test]
        fn arbitrary_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..300)) {
            if let Ok(text) = decode(&bytes, "f") {
                all_readers(text);
            }
            all_readers(&String::from_utf8_lossy(&bytes));
        }

        /// Text of the whitespace formats reaches their deeper paths.
        #[test]
        fn point_text_never_panics(
            head in prop_oneof![Just("0\n"), Just("Station 1.000\n"), Just("station x = 2\n"), Just("")],
            body in "([0-9\\. \\-e]{0,14}(\n|SEGMENT 1\n|2 segments.\n|Waterline 1.0\n|Buttock 0.5\n)){0,12}",
        ) {
            all_readers(&format!("{head}{body}"));
        }

        /// JSON-like text reaches the JSON readers' deeper paths.
        #[test]
        fn json_like_text_never_panics(
            body in "\\{(\"[0-9a-zA-Z站号WL]{0,5}\": ?(\\[[0-9null, .\\-]{0,12}\\]|[0-9.\\-]{0,4}|\\{\\}),? ?){0,6}\\}",
        ) {
            all_readers(&body);
            all_readers(&format!("{{\"structure\": {{\"hull\": {{\"attributes\": {{\"LOA\": 1, \"BOA\": 1, \"Depth\": 1}}, \"halfBreadths\": {body}}}}}}}"));
        }

        /// CSV-like text reaches the deeper paths (numbers, order checks, validation).
        #[test]
        fn csv_like_text_never_panics(
            head in prop_oneof![Just("section,x,y,z\n"), Just("z\\x,0,1,2\n"), Just(",0,0.5,1,SAR\nMaxBm,1,1,1\n"), Just("x,z,y,kind\n"), Just("")],
            body in "([0-9a-z\\.,\"# \\-+e]{0,12}(\n|\r\n|\r)){0,12}",
        ) {
            all_readers(&format!("{head}{body}"));
            all_readers(&format!("\u{FEFF}{head}{body}"));
        }

        /// Well-formed sections CSVs parse, keep every point, and report lines that exist.
        #[test]
        fn generated_sections_csv_round_trips(
            sections in proptest::collection::vec(proptest::collection::vec((-1e3f64..1e3, 0f64..1e3, -1e3f64..1e3), 1..6), 1..6),
        ) {
            let mut text = String::from("section,x,y,z\n");
            for (i, s) in sections.iter().enumerate() {
                for (x, y, z) in s {
                    text.push_str(&format!("s{i},{x},{y},{z}\n"));
                }
            }
            let o = parse_sections_csv(&text, "f", Units::Metre).map_err(|e| TestCaseError::fail(e.to_string()))?;
            prop_assert_eq!(o.sections.len(), sections.len());
            let n_lines = text.lines().count();
            for (s, want) in o.sections.iter().zip(&sections) {
                // `{}` of an f64 prints the shortest text that parses back to the same value.
                let pts: Vec<(f64, f64, f64)> = s.points.iter().map(|p| (p.x, p.y, p.z)).collect();
                prop_assert_eq!(&pts, want);
                prop_assert!(s.lines.iter().all(|&l| (2..=n_lines).contains(&l)));
            }
        }
    }
}
