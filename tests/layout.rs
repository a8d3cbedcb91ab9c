//! The crate's layout rules, checked on every file of `src/` (see
//! ARCHITECTURE.md, "Layers"): no module imports from a layer above its
//! own, and the imports between modules (a folder's `mod.rs` and its
//! children included) have no cycle.
//!
//! Imports are read from the code outside test modules: `use` paths and
//! every `crate::`, `super::` and `self::` path, and a `mod.rs`'s paths
//! through its own children.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The layers, lowest first; a module may import from its own and lower ones.
const LAYERS: &[&[&str]] = &[
    &["error", "params"],
    &["kernel"],
    &["input", "mesh"],
    &["skeleton", "measure", "io"],
    &["build", "overlap"],
    &["pipeline"],
    &["batch"],
    &["cli"],
    &["python"],
];

fn layer(top: &str) -> Option<usize> {
    LAYERS.iter().position(|l| l.contains(&top))
}

/// Every module of `src/` (but the binary) by its path (`build::tube`), with
/// its file.
fn modules(src: &Path) -> BTreeMap<String, PathBuf> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        for e in std::fs::read_dir(dir).expect("src is readable") {
            let p = e.expect("entry").path();
            if p.is_dir() {
                if p.file_name().is_some_and(|n| n != "bin") {
                    walk(&p, out);
                }
            } else if p.extension().is_some_and(|x| x == "rs") {
                out.push(p);
            }
        }
    }
    let mut files = Vec::new();
    walk(src, &mut files);
    files
        .into_iter()
        .map(|p| {
            let rel = p.strip_prefix(src).expect("under src").with_extension("");
            let mut parts: Vec<String> = rel
                .components()
                .map(|c| c.as_os_str().to_string_lossy().into_owned())
                .collect();
            if parts.last().is_some_and(|l| l == "mod" || l == "lib") {
                parts.pop();
            }
            (parts.join("::"), p)
        })
        .collect()
}

/// The code of a file outside its test module, comments and test-only items'
/// first lines dropped.
fn code_of(text: &str) -> String {
    let test_module = [
        "#[cfg(test)]\nmod tests",
        "#[cfg(test)]\npub(crate) mod tests",
    ]
    .iter()
    .filter_map(|m| text.find(m))
    .min();
    let text = test_module.map_or(text, |i| &text[..i]);
    let mut out = String::new();
    let mut skip_next = false;
    for line in text.lines() {
        let t = line.trim_start();
        if skip_next {
            skip_next = false;
            continue;
        }
        if t.starts_with("//") {
            continue;
        }
        if t.starts_with("#[cfg(test)]") || t.starts_with("#[cfg(any(test") {
            skip_next = true;
            continue;
        }
        out.push_str(line);
        out.push('\n');
    }
    out
}

fn is_ident(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '_'
}

/// The `::`-joined identifier path starting at byte `i` of `s`.
fn path_at(s: &str, i: usize) -> String {
    let bytes = s.as_bytes();
    let mut j = i;
    loop {
        while j < bytes.len() && is_ident(bytes[j] as char) {
            j += 1;
        }
        if s[j..].starts_with("::") && s[j + 2..].starts_with(|c: char| is_ident(c)) {
            j += 2;
        } else {
            break;
        }
    }
    s[i..j].to_owned()
}

/// The paths a `use` tree names, braces expanded.
fn expand_use(tree: &str) -> Vec<String> {
    let tree = tree.trim();
    let Some(open) = tree.find('{') else {
        let plain = tree.split(" as ").next().unwrap_or(tree).trim();
        return vec![plain.to_owned()];
    };
    let prefix = &tree[..open];
    let close = tree.rfind('}').filter(|&c| c > open).unwrap_or(tree.len());
    let inner = &tree[open + 1..close];
    let (mut items, mut depth, mut cur) = (Vec::new(), 0, String::new());
    for c in inner.chars() {
        match c {
            '{' => depth += 1,
            '}' => depth -= 1,
            ',' if depth == 0 => {
                items.push(std::mem::take(&mut cur));
                continue;
            }
            _ => {}
        }
        cur.push(c);
    }
    items.push(cur);
    items
        .iter()
        .filter(|i| !i.trim().is_empty())
        .flat_map(|i| expand_use(&format!("{prefix}{}", i.trim())))
        .collect()
}

/// Every module path `code` (of module `me`) refers to, not resolved yet.
fn referenced(code: &str, me: &[&str], children: &BTreeSet<String>) -> Vec<Vec<String>> {
    let mut paths: Vec<String> = Vec::new();
    // `use` items start a line (after a visibility); they may span lines.
    let mut offset = 0;
    for line in code.split_inclusive('\n') {
        let t = line.trim_start();
        let t = t
            .strip_prefix("pub ")
            .or_else(|| t.strip_prefix("pub(crate) "))
            .or_else(|| t.strip_prefix("pub(super) "))
            .unwrap_or(t);
        if let Some(tree) = t.strip_prefix("use ") {
            let at = offset + (line.len() - tree.len());
            if let Some(end) = code[at..].find(';') {
                paths.extend(expand_use(&code[at..at + end]));
            }
        }
        offset += line.len();
    }
    for (i, _) in code.match_indices("::") {
        let start = code[..i]
            .char_indices()
            .rev()
            .find(|&(_, c)| !is_ident(c) && c != ':')
            .map_or(0, |(k, c)| k + c.len_utf8());
        if code[..start].ends_with("::") {
            continue;
        }
        let path = path_at(code, start);
        let head = path.split("::").next().unwrap_or("");
        if ["crate", "super", "self"].contains(&head) || children.contains(head) {
            paths.push(path);
        }
    }
    paths
        .into_iter()
        .map(|p| {
            let segs: Vec<&str> = p.split("::").collect();
            let mut out: Vec<String> = me.iter().map(|s| s.to_string()).collect();
            let mut k = 0;
            match segs.first().copied() {
                Some("crate") => {
                    out.clear();
                    k = 1;
                }
                Some("self") => k = 1,
                Some("super") => {
                    while segs.get(k) == Some(&"super") {
                        out.pop();
                        k += 1;
                    }
                }
                _ => {}
            }
            out.extend(segs[k..].iter().map(|s| s.to_string()));
            out
        })
        .collect()
}

/// The import edges between the modules of `src/`.
fn edges(src: &Path) -> BTreeMap<String, BTreeSet<String>> {
    let mods = modules(src);
    let resolve = |segs: &[String]| {
        (1..=segs.len())
            .rev()
            .map(|k| segs[..k].join("::"))
            .find(|m| mods.contains_key(m))
    };
    let mut out: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (m, file) in &mods {
        let me: Vec<&str> = if m.is_empty() {
            Vec::new()
        } else {
            m.split("::").collect()
        };
        let children: BTreeSet<String> = mods
            .keys()
            .filter_map(|k| {
                let rest = if m.is_empty() {
                    Some(k.as_str())
                } else {
                    k.strip_prefix(&format!("{m}::"))
                };
                rest.filter(|r| !r.is_empty() && !r.contains("::"))
                    .map(str::to_owned)
            })
            .collect();
        let code = code_of(&std::fs::read_to_string(file).expect("readable source"));
        for segs in referenced(&code, &me, &children) {
            if let Some(t) = resolve(&segs)
                && &t != m
                && !t.is_empty()
            {
                out.entry(m.clone()).or_default().insert(t);
            }
        }
    }
    out
}

fn src() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("src")
}

#[test]
fn no_module_imports_from_a_layer_above_its_own() {
    let mut upward = Vec::new();
    for (a, targets) in edges(&src()) {
        let top_a = a.split("::").next().unwrap_or("").to_owned();
        for b in targets {
            let top_b = b.split("::").next().unwrap_or("");
            if let (Some(la), Some(lb)) = (layer(&top_a), layer(top_b))
                && la < lb
            {
                upward.push(format!("{a} -> {b}"));
            }
        }
    }
    assert!(upward.is_empty(), "upward imports:\n{}", upward.join("\n"));
}

#[test]
fn the_imports_between_modules_have_no_cycle() {
    let edges = edges(&src());
    // Depth-first search for a back edge.
    fn visit(
        m: &str,
        edges: &BTreeMap<String, BTreeSet<String>>,
        state: &mut BTreeMap<String, u8>,
        stack: &mut Vec<String>,
    ) -> Option<Vec<String>> {
        state.insert(m.to_owned(), 1);
        stack.push(m.to_owned());
        for t in edges.get(m).into_iter().flatten() {
            match state.get(t).copied().unwrap_or(0) {
                1 => {
                    let at = stack.iter().position(|s| s == t).unwrap_or(0);
                    let mut cycle = stack[at..].to_vec();
                    cycle.push(t.clone());
                    return Some(cycle);
                }
                0 => {
                    if let Some(c) = visit(t, edges, state, stack) {
                        return Some(c);
                    }
                }
                _ => {}
            }
        }
        stack.pop();
        state.insert(m.to_owned(), 2);
        None
    }
    let mut state = BTreeMap::new();
    for m in edges.keys() {
        if state.get(m).copied().unwrap_or(0) == 0
            && let Some(cycle) = visit(m, &edges, &mut state, &mut Vec::new())
        {
            panic!("an import cycle: {}", cycle.join(" -> "));
        }
    }
}

#[test]
fn the_reader_finds_the_imports_it_should() {
    let e = edges(&src());
    let has = |a: &str, b: &str| e.get(a).is_some_and(|t| t.contains(b));
    // A `use` with braces, a `super::` path, a full `crate::` path in code.
    assert!(has("build::tube::pieces", "build::coverage"));
    assert!(has("build::tube::band", "build::tube"));
    assert!(has("overlap::boundary", "overlap::patches"));
    assert!(has("skeleton", "kernel::parallel"));
    // Nothing is read from a test module.
    assert!(!has("overlap::cut", "overlap"));
}
