//! The library's modules form layers and every `crate::` path points down
//! (or within its own layer): parsers → fsio → testdata/model → solvers →
//! simulate → benchmark → updating → diagnosis → report → tasks → batch →
//! commands → main. Also no two modules reach each other, however deep
//! (no import cycle). The rule is stated in `src/lib.rs`; this test keeps
//! it true.
//!
//! The check reads `src/**/*.rs` as text (doc comments included: a doc link
//! to a higher layer is a dependency too) and takes a `crate::a::b` path, or
//! an item of a `use crate::{a::b, c}` group, as an edge to the deepest module
//! that exists (a file `src/a/b.rs` or `src/a/b/mod.rs`).

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Top-level modules of `src/lib.rs`, lowest layer first; modules of one
/// layer may use each other (without a cycle).
const LAYERS: &[&[&str]] = &[
    &["fsio"],
    &["testdata", "model"],
    &["solvers", "identification"],
    &["simulate"],
    &["benchmark"],
    &["updating"],
    &["diagnosis"],
    &["report"],
    &["tasks"],
    &["batch"],
    &["commands"],
];

type Module = Vec<String>;

fn src() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

/// Every module file under `src` but the crate roots, by module path.
fn modules() -> BTreeMap<Module, String> {
    fn walk(dir: &Path, root: &Path, out: &mut BTreeMap<Module, String>) {
        let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .collect();
        entries.sort();
        for p in entries {
            if p.is_dir() {
                walk(&p, root, out);
                continue;
            }
            if p.extension().is_none_or(|e| e != "rs") {
                continue;
            }
            let rel = p.strip_prefix(root).unwrap().with_extension("");
            let mut path: Module = rel
                .components()
                .map(|c| c.as_os_str().to_string_lossy().into_owned())
                .collect();
            if path.last().is_some_and(|l| l == "mod") {
                path.pop();
            }
            if path == ["lib"] || path == ["main"] {
                continue;
            }
            out.insert(path, std::fs::read_to_string(&p).unwrap());
        }
    }
    let mut out = BTreeMap::new();
    walk(&src(), &src(), &mut out);
    out
}

fn is_ident(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '_'
}

/// The paths (as segments) after each `crate::` in `text`, with the items
/// of `crate::{...}` groups as separate paths.
fn crate_paths(text: &str) -> Vec<Vec<String>> {
    let mut out = Vec::new();
    let bytes = text.as_bytes();
    let mut from = 0;
    while let Some(at) = text[from..].find("crate::") {
        let start = from + at;
        from = start + "crate::".len();
        if start > 0 && is_ident(bytes[start - 1] as char) {
            continue; // e.g. `frfup_crate::`
        }
        let rest = &text[from..];
        if let Some(group) = rest.strip_prefix('{') {
            // Items of the group at depth 0, each up to `,` or a nested `{`.
            let mut depth = 0;
            let mut item = String::new();
            for c in group.chars() {
                match c {
                    '{' => depth += 1,
                    '}' if depth == 0 => break,
                    '}' => depth -= 1,
                    ',' if depth == 0 => {
                        out.push(segments(&item));
                        item.clear();
                    }
                    _ if depth == 0 => item.push(c),
                    _ => {}
                }
            }
            out.push(segments(&item));
        } else {
            out.push(segments(rest));
        }
    }
    out
}

/// `a::b::c` (up to the first character of no path) as segments.
fn segments(s: &str) -> Vec<String> {
    let s = s.trim_start();
    let end = s
        .find(|c: char| !(is_ident(c) || c == ':'))
        .unwrap_or(s.len());
    s[..end]
        .split("::")
        .filter(|t| !t.is_empty())
        .map(str::to_string)
        .collect()
}

/// Module → modules it names (not itself, not its ancestors).
fn graph(mods: &BTreeMap<Module, String>) -> BTreeMap<Module, BTreeSet<Module>> {
    let mut g = BTreeMap::new();
    for (m, text) in mods {
        let mut targets = BTreeSet::new();
        for path in crate_paths(text) {
            let Some(t) = (1..=path.len())
                .rev()
                .map(|k| path[..k].to_vec())
                .find(|p| mods.contains_key(p))
            else {
                continue;
            };
            if t != *m && !m.starts_with(&t) {
                targets.insert(t);
            }
        }
        g.insert(m.clone(), targets);
    }
    g
}

fn name(m: &Module) -> String {
    m.join("::")
}

#[test]
fn every_top_level_module_has_a_layer() {
    let lib = std::fs::read_to_string(src().join("lib.rs")).unwrap();
    let declared: BTreeSet<String> = lib
        .lines()
        .filter_map(|l| l.trim().strip_prefix("pub mod "))
        .map(|l| l.trim_end_matches(';').to_string())
        .collect();
    let layered: BTreeSet<String> = LAYERS
        .iter()
        .flat_map(|l| l.iter().map(|s| s.to_string()))
        .collect();
    assert_eq!(
        declared, layered,
        "src/lib.rs's modules and this test's LAYERS differ: place a new module in a layer"
    );
}

#[test]
fn imports_point_down_the_layers() {
    let layer = |top: &str| LAYERS.iter().position(|l| l.contains(&top));
    let g = graph(&modules());
    let mut upward = Vec::new();
    for (m, targets) in &g {
        for t in targets {
            if let (Some(a), Some(b)) = (layer(&m[0]), layer(&t[0])) {
                if b > a {
                    upward.push(format!("{} -> {}", name(m), name(t)));
                }
            }
        }
    }
    assert!(
        upward.is_empty(),
        "imports that go up the layers (see src/lib.rs): {upward:#?}"
    );
}

#[test]
fn no_import_cycle() {
    // Tarjan's strongly connected components.
    struct Tarjan<'a> {
        g: &'a BTreeMap<Module, BTreeSet<Module>>,
        index: BTreeMap<&'a Module, (usize, usize)>,
        stack: Vec<&'a Module>,
        on_stack: BTreeSet<&'a Module>,
        cycles: Vec<Vec<String>>,
    }
    impl<'a> Tarjan<'a> {
        fn visit(&mut self, v: &'a Module) {
            let i = self.index.len();
            self.index.insert(v, (i, i));
            self.stack.push(v);
            self.on_stack.insert(v);
            for w in &self.g[v] {
                if !self.index.contains_key(w) {
                    self.visit(w);
                    let low = self.index[v].1.min(self.index[w].1);
                    self.index.get_mut(v).unwrap().1 = low;
                } else if self.on_stack.contains(w) {
                    let low = self.index[v].1.min(self.index[w].0);
                    self.index.get_mut(v).unwrap().1 = low;
                }
            }
            if self.index[v].0 == self.index[v].1 {
                let mut comp = Vec::new();
                while let Some(w) = self.stack.pop() {
                    self.on_stack.remove(w);
                    comp.push(name(w));
                    if w == v {
                        break;
                    }
                }
                if comp.len() > 1 {
                    comp.sort();
                    self.cycles.push(comp);
                }
            }
        }
    }
    let g = graph(&modules());
    let mut t = Tarjan {
        g: &g,
        index: BTreeMap::new(),
        stack: Vec::new(),
        on_stack: BTreeSet::new(),
        cycles: Vec::new(),
    };
    for v in g.keys() {
        if !t.index.contains_key(v) {
            t.visit(v);
        }
    }
    assert!(
        t.cycles.is_empty(),
        "modules that import each other: {:#?}",
        t.cycles
    );
}

/// No hidden global state: no module of either crate changes a
/// process-wide setting that other code reads (faer's global parallelism,
/// rayon's global pool, environment variables) or keeps a mutable static. Kernels take their parallelism as an argument
/// (`solvers::dense` runs on the calling thread).
#[test]
fn no_process_wide_settings() {
    let forbidden = [
        "set_global_parallelism",
        "build_global",
        "static mut",
        "set_var(",
        "remove_var(",
    ];
    let mut files: Vec<(String, String)> = modules()
        .into_iter()
        .map(|(m, text)| (name(&m), text))
        .collect();
    for root in ["lib.rs", "main.rs"] {
        files.push((
            root.into(),
            std::fs::read_to_string(src().join(root)).unwrap(),
        ));
    }
    let parsers = src().join("../parsers/src");
    let mut dirs = vec![parsers.clone()];
    while let Some(d) = dirs.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            let p = e.path();
            if p.is_dir() {
                dirs.push(p);
            } else if p.extension().is_some_and(|x| x == "rs") {
                let name = p.strip_prefix(&parsers).unwrap().display().to_string();
                files.push((
                    format!("parsers/{name}"),
                    std::fs::read_to_string(&p).unwrap(),
                ));
            }
        }
    }
    assert!(
        files.iter().any(|(f, _)| f == "parsers/lib.rs"),
        "the parsers were read"
    );
    let mut found = Vec::new();
    for (file, text) in files {
        for f in forbidden {
            if text.contains(f) {
                found.push(format!("{file}: {f}"));
            }
        }
    }
    assert!(found.is_empty(), "{found:#?}");
}

#[test]
fn the_reader_finds_grouped_and_nested_paths() {
    let paths = crate_paths(
        "use crate::{model::{self, Dof}, fsio};\nlet x = crate::solvers::eigen::lowest_modes(k);",
    );
    assert_eq!(
        paths,
        vec![
            vec!["model".to_string()],
            vec!["fsio".to_string()],
            vec!["solvers".into(), "eigen".into(), "lowest_modes".into()],
        ]
    );
}

/// faer's high-level decompositions take its process-wide parallelism, and
/// its parallel kernels sum in another order than its sequential ones: the
/// bytes written would depend on the machine's cores. Every dense
/// decomposition goes through `solvers::dense`, whose kernels run on the
/// calling thread (the sparse Cholesky of `solvers` passes its own `Par`).
#[test]
fn dense_decompositions_go_through_solvers_dense() {
    let implicit = [
        ".partial_piv_lu(",
        ".full_piv_lu(",
        ".eigen()",
        ".eigenvalues()",
        ".self_adjoint_eigen(",
        ".llt(",
        ".ldlt(",
        ".thin_svd()",
        ".svd()",
        ".qr()",
        ".col_piv_qr()",
    ];
    let mut found = Vec::new();
    for (m, text) in modules() {
        if name(&m) == "solvers::dense" {
            continue;
        }
        for f in implicit {
            if text.contains(f) {
                found.push(format!("{}: {f}", name(&m)));
            }
        }
    }
    assert!(found.is_empty(), "{found:#?}");
}
