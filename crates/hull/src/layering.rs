//! A guard of the crates' layering (issue 13): no top-level module of `src/` imports one that
//! imports it back, directly or through others; run over this crate, the kernel below it
//! (`crates/nurbs`) and the presentation crate above it (`crates/view`).
//!
//! It reads the sources as text: every `use` path and every `crate::` path in code (comments,
//! strings and `#[cfg(test)]` items left out, since tests may use what sits above them) is
//! resolved to the top-level module it names (`crate::optimize::quiet` to `optimize`,
//! `super::x` by the module it is written in, a root re-export such as `crate::FitOutcome` by
//! `lib.rs`'s `pub use` to the module that defines it). The modules and these edges make a
//! graph; a strongly connected component of more than one module is a cycle, reported as a
//! path `a -> b -> a` with the line that makes each step.
//!
//! The same reading guards both crates' front door: `lib.rs` declares no `pub mod` and no glob
//! re-export, so the public API is its list of `pub use`, one path per item.

use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// One token of Rust source, with its line.
#[derive(Clone, Debug, PartialEq)]
struct Token {
    text: String,
    line: usize,
}

/// The source as identifiers, `::` and single punctuation, without comments, string and
/// character literals (their contents could look like paths) and lifetimes.
fn tokenize(src: &str) -> Vec<Token> {
    let chars: Vec<char> = src.chars().collect();
    let mut tokens = Vec::new();
    let (mut i, mut line) = (0, 1);
    let newlines = |from: usize, to: usize| chars[from..to].iter().filter(|&&c| c == '\n').count();
    while i < chars.len() {
        let c = chars[i];
        let next = chars.get(i + 1).copied();
        if c == '\n' {
            line += 1;
            i += 1;
        } else if c.is_whitespace() {
            i += 1;
        } else if c == '/' && next == Some('/') {
            while i < chars.len() && chars[i] != '\n' {
                i += 1;
            }
        } else if c == '/' && next == Some('*') {
            let (start, mut depth) = (i, 0);
            while i < chars.len() {
                if chars[i] == '/' && chars.get(i + 1) == Some(&'*') {
                    depth += 1;
                    i += 2;
                } else if chars[i] == '*' && chars.get(i + 1) == Some(&'/') {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    i += 1;
                }
            }
            line += newlines(start, i);
        } else if c == '"' || ((c == 'r' || c == 'b') && raw_or_byte_string(&chars, i).is_some()) {
            let start = i;
            i = if c == '"' { quoted_end(&chars, i) } else { raw_or_byte_string(&chars, i).unwrap_or(i + 1) };
            line += newlines(start, i.min(chars.len()));
        } else if c == '\'' {
            // A character literal ('x', '\n', '\u{1F600}') or a lifetime ('a, 'static).
            if next == Some('\\') {
                i += 2;
                while i < chars.len() && chars[i] != '\'' {
                    i += 1;
                }
                i += 1;
            } else if chars.get(i + 2) == Some(&'\'') {
                i += 3;
            } else {
                i += 1;
                while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
                    i += 1;
                }
            }
        } else if c.is_alphanumeric() || c == '_' {
            let start = i;
            while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            tokens.push(Token { text: chars[start..i].iter().collect(), line });
        } else if c == ':' && next == Some(':') {
            tokens.push(Token { text: "::".into(), line });
            i += 2;
        } else {
            tokens.push(Token { text: c.to_string(), line });
            i += 1;
        }
    }
    tokens
}

/// The index past a `"..."` string starting at `i`.
fn quoted_end(chars: &[char], mut i: usize) -> usize {
    i += 1;
    while i < chars.len() && chars[i] != '"' {
        i += if chars[i] == '\\' { 2 } else { 1 };
    }
    i + 1
}

/// The index past a raw or byte string (`r"..."`, `r#"..."#`, `b"..."`, `br#"..."#`)
/// starting at `i`, or `None` when `i` starts no such literal (an identifier such as `r`).
fn raw_or_byte_string(chars: &[char], i: usize) -> Option<usize> {
    if i > 0 && (chars[i - 1].is_alphanumeric() || chars[i - 1] == '_') {
        return None;
    }
    let mut j = i;
    if chars[j] == 'b' {
        j += 1;
        if chars.get(j) == Some(&'"') {
            return Some(quoted_end(chars, j));
        }
    }
    if chars.get(j) != Some(&'r') {
        return None;
    }
    j += 1;
    let hashes = chars[j..].iter().take_while(|&&c| c == '#').count();
    j += hashes;
    if chars.get(j) != Some(&'"') {
        return None;
    }
    j += 1;
    while j < chars.len() {
        if chars[j] == '"' && chars[j + 1..].iter().take(hashes).filter(|&&c| c == '#').count() == hashes {
            return Some(j + 1 + hashes);
        }
        j += 1;
    }
    Some(j)
}

/// A path named in a file: its segments and line.
#[derive(Clone, Debug, PartialEq)]
struct PathUse {
    segments: Vec<String>,
    line: usize,
}

/// What one file names: its paths (each with the module it is written in), and the
/// `#[cfg(test)] mod name;` declarations whose files are test code.
#[derive(Debug, Default)]
struct FileUses {
    /// (module path of the scope, the path named).
    paths: Vec<(Vec<String>, PathUse)>,
    test_mods: Vec<String>,
    /// `pub use` paths at the file's top level, with their alias (for `lib.rs`'s re-exports).
    reexports: Vec<(String, Vec<String>)>,
}

/// The paths a file at module path `module` names.
fn scan(src: &str, module: &[String]) -> FileUses {
    let tokens = tokenize(src);
    let mut out = FileUses::default();
    // The inline modules we are in: (name, the brace depth inside them).
    let mut scopes: Vec<(String, usize)> = Vec::new();
    let (mut depth, mut i) = (0usize, 0usize);
    let scope = |scopes: &[(String, usize)]| {
        let mut m = module.to_vec();
        m.extend(scopes.iter().map(|(n, _)| n.clone()));
        m
    };
    let text = |k: usize| tokens.get(k).map_or("", |t| t.text.as_str());
    while i < tokens.len() {
        match text(i) {
            "#" if text(i + 1) == "[" || (text(i + 1) == "!" && text(i + 2) == "[") => {
                let open = if text(i + 1) == "!" { i + 2 } else { i + 1 };
                let close = matching(&tokens, open);
                let is_test = (open + 1..close).map(text).collect::<Vec<_>>() == ["cfg", "(", "test", ")"];
                i = close + 1;
                if is_test && text(open - 1) != "!" {
                    // Skip further attributes, then the item: a `mod name;` is a test file.
                    while text(i) == "#" {
                        i = matching(&tokens, i + 1) + 1;
                    }
                    let item = i;
                    i = item_end(&tokens, i);
                    let words: Vec<&str> = (item..i).map(text).collect();
                    if let Some(p) = words.iter().position(|&w| w == "mod") {
                        if words.get(p + 2) == Some(&";") {
                            out.test_mods.push(words[p + 1].to_string());
                        }
                    }
                }
            }
            "mod" if text(i + 2) == "{" => {
                scopes.push((text(i + 1).to_string(), depth + 1));
                depth += 1;
                i += 3;
            }
            "use" => {
                let end = (i..tokens.len()).find(|&k| text(k) == ";").unwrap_or(tokens.len());
                let public = i > 0 && (text(i - 1) == "pub" || text(i - 1) == ")");
                for (alias, segments) in use_tree(&tokens[i + 1..end]) {
                    if public && scopes.is_empty() {
                        out.reexports.push((alias.clone(), segments.clone()));
                    }
                    out.paths.push((scope(&scopes), PathUse { segments, line: tokens[i].line }));
                }
                i = end + 1;
            }
            "crate" if text(i + 1) == "::" => {
                let mut segments = vec!["crate".to_string()];
                let mut k = i + 1;
                while text(k) == "::" && tokens.get(k + 1).is_some_and(|t| is_ident(&t.text)) {
                    segments.push(text(k + 1).to_string());
                    k += 2;
                }
                out.paths.push((scope(&scopes), PathUse { segments, line: tokens[i].line }));
                i = k;
            }
            "{" => {
                depth += 1;
                i += 1;
            }
            "}" => {
                if scopes.last().is_some_and(|&(_, d)| d == depth) {
                    scopes.pop();
                }
                depth = depth.saturating_sub(1);
                i += 1;
            }
            _ => i += 1,
        }
    }
    out
}

fn is_ident(s: &str) -> bool {
    s.chars().next().is_some_and(|c| c.is_alphabetic() || c == '_')
}

/// The index of the bracket closing the one at `open`.
fn matching(tokens: &[Token], open: usize) -> usize {
    let mut depth = 0i32;
    for (k, t) in tokens.iter().enumerate().skip(open) {
        match t.text.as_str() {
            "(" | "[" | "{" => depth += 1,
            ")" | "]" | "}" => {
                depth -= 1;
                if depth == 0 {
                    return k;
                }
            }
            _ => {}
        }
    }
    tokens.len() - 1
}

/// The index past the item starting at `i`: its `;` at depth 0, or its closing brace.
fn item_end(tokens: &[Token], mut i: usize) -> usize {
    while i < tokens.len() {
        match tokens[i].text.as_str() {
            ";" => return i + 1,
            "{" => return matching(tokens, i) + 1,
            "(" | "[" => i = matching(tokens, i) + 1,
            _ => i += 1,
        }
    }
    i
}

/// The paths of a use tree (`a::{b, c::{self, d as e}}`), each with the name it binds.
fn use_tree(tokens: &[Token]) -> Vec<(String, Vec<String>)> {
    fn walk(tokens: &[Token], prefix: &[String], out: &mut Vec<(String, Vec<String>)>) {
        // Split at top-level commas.
        let mut parts: Vec<&[Token]> = Vec::new();
        let (mut depth, mut start) = (0, 0);
        for (k, t) in tokens.iter().enumerate() {
            match t.text.as_str() {
                "{" => depth += 1,
                "}" => depth -= 1,
                "," if depth == 0 => {
                    parts.push(&tokens[start..k]);
                    start = k + 1;
                }
                _ => {}
            }
        }
        parts.push(&tokens[start..]);
        for part in parts.into_iter().filter(|p| !p.is_empty()) {
            let mut path = prefix.to_vec();
            let mut k = 0;
            let mut alias = None;
            while k < part.len() {
                match part[k].text.as_str() {
                    "::" => k += 1,
                    "{" => {
                        let close = matching(part, k);
                        walk(&part[k + 1..close], &path, out);
                        break;
                    }
                    "as" => {
                        alias = part.get(k + 1).map(|t| t.text.clone());
                        k += 2;
                    }
                    "*" => k += 1,
                    "self" if !path.is_empty() => k += 1,
                    word => {
                        path.push(word.to_string());
                        k += 1;
                    }
                }
                if k == part.len() && !path.is_empty() {
                    let name = alias.clone().unwrap_or_else(|| path.last().cloned().unwrap_or_default());
                    out.push((name, path.clone()));
                }
            }
        }
    }
    let mut out = Vec::new();
    walk(tokens, &[], &mut out);
    out
}

/// An edge of the module graph with the place that makes it.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Evidence {
    pub file: String,
    pub line: usize,
    pub path: String,
}

/// Top-level module -> the modules it imports, each with the first place that does.
pub(crate) type Graph = BTreeMap<String, BTreeMap<String, Evidence>>;

/// The import graph of the crate whose `lib.rs` is `src/lib.rs`.
fn crate_graph(src: &Path) -> Graph {
    let lib = std::fs::read_to_string(src.join("lib.rs")).expect("lib.rs reads");
    let root = scan(&lib, &[]);
    let modules: BTreeSet<String> = top_level_modules(&lib);
    // Root re-exports: the name at the crate root -> the module it comes from.
    let reexports: BTreeMap<String, String> = root
        .reexports
        .iter()
        .filter_map(|(alias, segs)| {
            let first = if segs[0] == "crate" || segs[0] == "self" { segs.get(1)? } else { &segs[0] };
            modules.contains(first).then(|| (alias.clone(), first.clone()))
        })
        .collect();
    let mut graph: Graph = modules.iter().map(|m| (m.clone(), BTreeMap::new())).collect();
    let mut files = Vec::new();
    collect_files(src, &mut files);
    // Files declared `#[cfg(test)] mod name;` (and everything below them) are test code.
    let mut test_files: BTreeSet<PathBuf> = BTreeSet::new();
    let mut scans = Vec::new();
    for file in &files {
        let rel = file.strip_prefix(src).expect("under src");
        let module = module_path(rel);
        if module.is_empty() {
            continue;
        }
        let text = std::fs::read_to_string(file).expect("source reads");
        let uses = scan(&text, &module);
        let dir = if matches!(rel.file_name().and_then(|n| n.to_str()), Some("mod.rs")) {
            file.parent().expect("dir").to_path_buf()
        } else {
            file.with_extension("")
        };
        for m in &uses.test_mods {
            test_files.insert(dir.join(format!("{m}.rs")));
            test_files.insert(dir.join(m));
        }
        scans.push((file.clone(), rel.to_path_buf(), module, uses));
    }
    for (file, rel, module, uses) in scans {
        if test_files.iter().any(|t| file.starts_with(t)) {
            continue;
        }
        let from = &module[0];
        for (scope, used) in uses.paths {
            let Some(to) = resolve(&scope, &used.segments, &modules, &reexports) else { continue };
            if &to != from {
                graph.get_mut(from).expect("module").entry(to).or_insert_with(|| Evidence {
                    file: rel.display().to_string(),
                    line: used.line,
                    path: used.segments.join("::"),
                });
            }
        }
    }
    graph
}

/// The modules `lib.rs` declares (`mod x;`, `pub mod x;`; not `#[cfg(test)]` ones).
fn top_level_modules(lib: &str) -> BTreeSet<String> {
    let tokens = tokenize(lib);
    let test_mods = scan(lib, &[]).test_mods;
    tokens
        .windows(3)
        .filter(|w| w[0].text == "mod" && w[2].text == ";")
        .map(|w| w[1].text.clone())
        .filter(|m| !test_mods.contains(m))
        .collect()
}

fn collect_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir).expect("dir reads").flatten().map(|e| e.path()).collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            collect_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// `optimize/weights/gauge.rs` -> `[optimize, weights, gauge]`; `lib.rs` -> `[]`.
fn module_path(rel: &Path) -> Vec<String> {
    let mut parts: Vec<String> = rel.iter().map(|p| p.to_string_lossy().into_owned()).collect();
    let last = parts.pop().unwrap_or_default();
    let stem = last.trim_end_matches(".rs");
    if stem != "mod" && stem != "lib" {
        parts.push(stem.to_string());
    }
    parts
}

/// The top-level module a path written in module `scope` names, if any.
fn resolve(
    scope: &[String],
    segments: &[String],
    modules: &BTreeSet<String>,
    reexports: &BTreeMap<String, String>,
) -> Option<String> {
    let mut abs: Vec<String> = match segments.first()?.as_str() {
        "crate" => Vec::new(),
        "self" => scope.to_vec(),
        "super" => {
            let ups = segments.iter().take_while(|s| *s == "super").count();
            let mut m = scope.to_vec();
            m.truncate(m.len().checked_sub(ups)?);
            m.extend(segments[ups..].iter().cloned());
            return top_of(&m, modules, reexports);
        }
        _ => return None,
    };
    abs.extend(segments[1..].iter().cloned());
    top_of(&abs, modules, reexports)
}

fn top_of(abs: &[String], modules: &BTreeSet<String>, reexports: &BTreeMap<String, String>) -> Option<String> {
    let first = abs.first()?;
    if modules.contains(first) {
        Some(first.clone())
    } else {
        reexports.get(first).cloned()
    }
}

/// Every cycle of the graph, one per strongly connected component of two modules or more,
/// written `a -> b -> a` with the place of each step.
pub(crate) fn cycles(graph: &Graph) -> Vec<String> {
    let mut reports = Vec::new();
    for component in components(graph) {
        if component.len() < 2 {
            continue;
        }
        // The shortest cycle through the component's first module.
        let start = &component[0];
        let inside: BTreeSet<&String> = component.iter().collect();
        let mut previous: BTreeMap<&String, &String> = BTreeMap::new();
        let mut queue = std::collections::VecDeque::from([start]);
        let mut closing = None;
        while let Some(m) = queue.pop_front() {
            for to in graph[m].keys().filter(|t| inside.contains(t)) {
                if to == start {
                    closing = Some(m);
                    break;
                }
                if !previous.contains_key(to) {
                    previous.insert(to, m);
                    queue.push_back(to);
                }
            }
            if closing.is_some() {
                break;
            }
        }
        // Back from the module that closes the cycle to the start, then turned round.
        let mut path = vec![start.clone()];
        let mut at = closing.expect("a component of two or more has a cycle");
        while at != start {
            path.push(at.clone());
            at = previous[at];
        }
        path.push(start.clone());
        path.reverse();
        let mut text = format!("cycle among {{{}}}: {}", component.join(", "), path.join(" -> "));
        for step in path.windows(2) {
            let e = &graph[&step[0]][&step[1]];
            let _ = write!(text, "\n    {} -> {}: {}:{} names {}", step[0], step[1], e.file, e.line, e.path);
        }
        reports.push(text);
    }
    reports
}

/// Tarjan's strongly connected components, each sorted, in the order they close.
fn components(graph: &Graph) -> Vec<Vec<String>> {
    struct State<'g> {
        graph: &'g Graph,
        index: BTreeMap<&'g String, usize>,
        low: BTreeMap<&'g String, usize>,
        stack: Vec<&'g String>,
        on_stack: BTreeSet<&'g String>,
        out: Vec<Vec<String>>,
    }
    fn visit<'g>(s: &mut State<'g>, v: &'g String) {
        let n = s.index.len();
        s.index.insert(v, n);
        s.low.insert(v, n);
        s.stack.push(v);
        s.on_stack.insert(v);
        for w in s.graph[v].keys() {
            let Some((w, _)) = s.graph.get_key_value(w) else { continue };
            if !s.index.contains_key(w) {
                visit(s, w);
                let low = s.low[v].min(s.low[w]);
                s.low.insert(v, low);
            } else if s.on_stack.contains(w) {
                let low = s.low[v].min(s.index[w]);
                s.low.insert(v, low);
            }
        }
        if s.low[v] == s.index[v] {
            let mut component = Vec::new();
            while let Some(w) = s.stack.pop() {
                s.on_stack.remove(w);
                component.push(w.clone());
                if w == v {
                    break;
                }
            }
            component.sort();
            s.out.push(component);
        }
    }
    let mut s = State {
        graph,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on_stack: BTreeSet::new(),
        out: Vec::new(),
    };
    for v in graph.keys() {
        if !s.index.contains_key(v) {
            visit(&mut s, v);
        }
    }
    s.out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn graph(edges: &[(&str, &str)]) -> Graph {
        let mut g = Graph::new();
        for &(a, b) in edges {
            g.entry(b.into()).or_default();
            let e = Evidence { file: format!("{a}.rs"), line: 1, path: format!("crate::{b}::X") };
            g.entry(a.into()).or_default().insert(b.into(), e);
        }
        g
    }

    #[test]
    fn a_layered_graph_has_no_cycle() {
        let g = graph(&[("pipeline", "optimize"), ("pipeline", "fit"), ("optimize", "error"), ("fit", "error")]);
        assert!(cycles(&g).is_empty(), "{:?}", cycles(&g));
    }

    #[test]
    fn a_cycle_is_found_and_named_with_its_steps() {
        // pipeline -> optimize -> fit -> pipeline, and limits off to the side.
        let g = graph(&[("pipeline", "optimize"), ("optimize", "fit"), ("fit", "pipeline"), ("limits", "optimize")]);
        let found = cycles(&g);
        assert_eq!(found.len(), 1, "{found:?}");
        assert!(found[0].starts_with("cycle among {fit, optimize, pipeline}: fit -> pipeline -> optimize -> fit"));
        assert!(found[0].contains("pipeline -> optimize: pipeline.rs:1 names crate::optimize::X"), "{}", found[0]);
    }

    #[test]
    fn two_cycles_are_two_reports() {
        let g = graph(&[("a", "b"), ("b", "a"), ("c", "d"), ("d", "c"), ("b", "c")]);
        let found = cycles(&g);
        assert_eq!(found.len(), 2, "{found:?}");
        assert!(found.iter().any(|c| c.contains("a -> b -> a")) && found.iter().any(|c| c.contains("c -> d -> c")));
    }

    #[test]
    fn paths_are_resolved_through_super_re_exports_and_use_trees() {
        let modules: BTreeSet<String> = ["optimize", "pipeline", "error"].map(String::from).into();
        let reexports: BTreeMap<String, String> = [("FitOutcome".to_string(), "pipeline".to_string())].into();
        let src = r#"
            //! Docs naming crate::error::HullError do not count, nor "crate::error" in a string.
            use super::super::error::HullError;
            use crate::{optimize::{self, quiet}, FitOutcome as Outcome};
            use nurbs::NurbsSurface;
            fn f<'a>(x: &'a str) -> char { let _ = crate::error::HullError::NoSurface; 'x' }
            #[cfg(test)]
            mod tests { use crate::pipeline::fit_offsets; }
            mod inner { use super::super::pipeline::FitConfig; }
        "#;
        let scope: Vec<String> = ["optimize", "weights"].map(String::from).into();
        let uses = scan(src, &scope);
        let tops: Vec<(usize, String)> = uses
            .paths
            .iter()
            .filter_map(|(s, p)| Some((p.line, resolve(s, &p.segments, &modules, &reexports)?)))
            .collect();
        let expected = [(3, "error"), (4, "optimize"), (4, "optimize"), (4, "pipeline"), (6, "error"), (9, "optimize")];
        assert_eq!(tops, expected.map(|(l, m)| (l, m.to_string())));
        assert!(uses.test_mods.is_empty());
        let with_test_file = scan("#[cfg(test)]\n#[path = \"x.rs\"]\nmod tests;\nmod real;", &scope);
        assert_eq!(with_test_file.test_mods, ["tests"]);
    }

    /// The import graph of `crates/<name>/src`, checked to have no cycle.
    fn acyclic_graph_of(name: &str) -> Graph {
        let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(name).join("src");
        let graph = crate_graph(&src);
        let found = cycles(&graph);
        assert!(found.is_empty(), "module cycles in crates/{name}/src:\n{}", found.join("\n"));
        graph
    }

    /// The guard itself: `crates/hull/src` has no module cycle.
    #[test]
    fn no_module_imports_one_that_imports_it_back() {
        let graph = acyclic_graph_of("hull");
        assert!(graph.len() > 20, "read {} modules", graph.len());
        assert!(graph["pipeline"].contains_key("error"), "the reader sees pipeline's imports");
    }

    /// The same guard over the presentation crate above (`crates/view/src`), read as text from
    /// here: the crates' own layering (view -> hull) is enforced by Cargo.
    #[test]
    fn no_module_of_the_view_crate_imports_one_that_imports_it_back() {
        let graph = acyclic_graph_of("view");
        assert!(graph.len() >= 6, "read {} modules", graph.len());
        assert!(graph["report_html"].contains_key("render"), "the reader sees report_html's imports");
    }

    /// The same guard over the kernel below (`crates/nurbs/src`), read as text from here.
    #[test]
    fn no_module_of_the_kernel_imports_one_that_imports_it_back() {
        let graph = acyclic_graph_of("nurbs");
        assert!(graph.len() >= 15, "read {} modules", graph.len());
        assert!(graph["cut"].contains_key("surface"), "the reader sees cut's imports");
    }

    /// `pub mod` and glob re-exports (`pub use x::*`) in a `lib.rs`, as `lib.rs:line: code`.
    fn second_paths(lib: &str) -> Vec<String> {
        let tokens = tokenize(lib);
        let mut found = Vec::new();
        for (i, t) in tokens.iter().enumerate() {
            let next = tokens.get(i + 1).map(|n| n.text.as_str());
            if t.text == "pub" && next == Some("mod") {
                found.push(format!("lib.rs:{}: pub mod", t.line));
            }
            if t.text == "pub" && next == Some("use") {
                let end = tokens[i..].iter().position(|t| t.text == ";").map_or(tokens.len(), |e| i + e);
                if tokens[i..end].iter().any(|t| t.text == "*") {
                    found.push(format!("lib.rs:{}: pub use with a glob", t.line));
                }
            }
        }
        found
    }

    #[test]
    fn a_public_module_and_a_glob_re_export_are_found() {
        let lib =
            "//! `pub mod` in a comment.\nmod a;\npub(crate) mod b;\npub mod c;\npub use a::{x, Y};\npub use b::*;\n";
        assert_eq!(second_paths(lib), ["lib.rs:4: pub mod", "lib.rs:6: pub use with a glob"]);
    }

    /// The front door (issue 13): `hull` and `view` keep their modules private and list their
    /// public API as `pub use` in `lib.rs`, so every public item has exactly one path. A
    /// `pub mod` (or a glob re-export) would give items a second path, or hide which are public.
    #[test]
    fn the_public_api_is_the_pub_use_list_of_lib_rs() {
        for name in ["hull", "view"] {
            let lib = Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(name).join("src").join("lib.rs");
            let text = std::fs::read_to_string(&lib).expect("lib.rs reads");
            let found = second_paths(&text);
            assert!(
                found.is_empty(),
                "crates/{name}/src: make the module private and re-export its items:\n{}",
                found.join("\n")
            );
        }
    }
}
