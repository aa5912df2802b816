//! The import graph between a crate's modules, read from its sources, and the
//! cycles in it (`tests/tests/source_tree.rs` asserts there are none).
//!
//! # What counts as an edge
//! For two modules `A` and `B` with the same parent (the crate's top-level
//! modules are siblings under the crate root), `A -> B` when code anywhere in
//! `A`'s subtree names an item defined in `B`'s subtree: through a `use` path,
//! or a `crate::…` / `super::…` / `self::…` path in code. Paths are followed
//! through `use` re-exports (`pub use frame::permute_frame` at the root makes
//! `crate::permute_frame` an item of `frame`) to the module that defines the
//! item. Items a parent defines in its own file (`mod.rs`, `lib.rs`) and its
//! children use make no edge: only siblings are compared.
//!
//! Not counted: comments (doc links included), string literals, and items
//! under `#[cfg(test)]` (test modules may use whatever they test against)
//! or `#[cfg(doc)]` (imports for doc links).
//! The reading is lexical, not a compiler's: paths hidden behind glob imports
//! of a module's own parent, macros, or `#[path]` attributes are not seen.

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::{Path, PathBuf};

/// A module's path from its crate root (`[]` is the root; `["permutation", "sort"]`).
pub type ModPath = Vec<String>;

/// One module read from its file.
#[derive(Debug, Default)]
struct Module {
    file: PathBuf,
    children: BTreeSet<String>,
    /// Names brought into scope by `use`, each with the absolute path it names.
    imports: BTreeMap<String, ModPath>,
    /// Absolute paths of `use …::*` imports.
    globs: Vec<ModPath>,
    /// Names of items defined in the module's own file.
    items: BTreeSet<String>,
    /// Absolute paths named in the file, with the 1-based line they appear on.
    references: Vec<(ModPath, usize)>,
}

/// One edge of the sibling graph, with the first place that makes it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Edge {
    /// The module whose subtree holds the reference.
    pub from: ModPath,
    /// The sibling module whose subtree defines the item.
    pub to: ModPath,
    /// Where: file and 1-based line.
    pub at: String,
}

/// The modules of one crate (one root file: `lib.rs`, `main.rs`, ...).
#[derive(Debug)]
pub struct CrateGraph {
    modules: BTreeMap<ModPath, Module>,
}

impl CrateGraph {
    /// Reads the crate whose root file is `root` (`src/lib.rs`), following
    /// its `mod name;` declarations (those not under `#[cfg(test)]`).
    ///
    /// # Errors
    /// A declared module whose file is missing, or an unreadable file.
    pub fn read(root: &Path) -> Result<Self, String> {
        let mut modules = BTreeMap::new();
        let mut pending = vec![(Vec::<String>::new(), root.to_path_buf())];
        while let Some((path, file)) = pending.pop() {
            let source = fs::read_to_string(&file).map_err(|e| format!("{}: {e}", file.display()))?;
            let module = parse_module(&path, &file, &source);
            let dir = child_dir(&file);
            for child in &module.children {
                let flat = dir.join(format!("{child}.rs"));
                let nested = dir.join(child).join("mod.rs");
                let child_file = if flat.exists() {
                    flat
                } else if nested.exists() {
                    nested
                } else {
                    return Err(format!("{}: module `{child}` has no file", file.display()));
                };
                let mut child_path = path.clone();
                child_path.push(child.clone());
                pending.push((child_path, child_file));
            }
            modules.insert(path, module);
        }
        Ok(Self { modules })
    }

    /// Number of modules read.
    pub fn len(&self) -> usize {
        self.modules.len()
    }

    /// True when the crate has no module (never: the root is one).
    pub fn is_empty(&self) -> bool {
        self.modules.is_empty()
    }

    /// The module that defines what `path` (absolute) names: its longest
    /// prefix that is a module, after following imports and re-exports.
    fn resolve(&self, path: &[String], depth: usize) -> ModPath {
        let mut current: ModPath = Vec::new();
        for (i, segment) in path.iter().enumerate() {
            let Some(module) = self.modules.get(&current) else {
                return current;
            };
            if module.children.contains(segment) {
                current.push(segment.clone());
                continue;
            }
            if depth < 16 {
                if let Some(target) = module.imports.get(segment) {
                    let mut next = target.clone();
                    next.extend_from_slice(&path[i + 1..]);
                    return self.resolve(&next, depth + 1);
                }
                if !module.items.contains(segment) {
                    for glob in &module.globs {
                        let glob_module = self.resolve(glob, depth + 1);
                        if let Some(m) = self.modules.get(&glob_module) {
                            let known = m.children.contains(segment)
                                || m.imports.contains_key(segment)
                                || m.items.contains(segment);
                            if known && glob_module != current {
                                let mut next = glob_module.clone();
                                next.extend_from_slice(&path[i..]);
                                return self.resolve(&next, depth + 1);
                            }
                        }
                    }
                }
            }
            return current;
        }
        current
    }

    /// Every edge between sibling modules (deduplicated, first place kept).
    pub fn edges(&self) -> Vec<Edge> {
        let mut seen = BTreeMap::new();
        for (from_path, module) in &self.modules {
            for (reference, line) in &module.references {
                let to_path = self.resolve(reference, 0);
                let common = from_path.iter().zip(&to_path).take_while(|(a, b)| a == b).count();
                if common < from_path.len() && common < to_path.len() {
                    let from = from_path[..=common].to_vec();
                    let to = to_path[..=common].to_vec();
                    seen.entry((from, to))
                        .or_insert_with(|| format!("{}:{line}", module.file.display()));
                }
            }
        }
        seen.into_iter()
            .map(|((from, to), at)| Edge { from, to, at })
            .collect()
    }

    /// The cycles of the sibling graph: each strongly connected component of
    /// more than one module, as the edges inside it.
    pub fn cycles(&self) -> Vec<Vec<Edge>> {
        let edges = self.edges();
        let nodes: BTreeSet<ModPath> = edges
            .iter()
            .flat_map(|e| [e.from.clone(), e.to.clone()])
            .collect();
        let reaches = |a: &ModPath, b: &ModPath| {
            let mut stack = vec![a.clone()];
            let mut visited = BTreeSet::new();
            while let Some(n) = stack.pop() {
                if &n == b {
                    return true;
                }
                if visited.insert(n.clone()) {
                    stack.extend(edges.iter().filter(|e| e.from == n).map(|e| e.to.clone()));
                }
            }
            false
        };
        let mut components: Vec<BTreeSet<ModPath>> = Vec::new();
        for node in &nodes {
            if components.iter().any(|c| c.contains(node)) {
                continue;
            }
            let component: BTreeSet<ModPath> = nodes
                .iter()
                .filter(|other| *other == node || (reaches(node, other) && reaches(other, node)))
                .map(|other| (*other).clone())
                .collect();
            if component.len() > 1 {
                components.push(component);
            }
        }
        components
            .into_iter()
            .map(|c| {
                edges
                    .iter()
                    .filter(|e| c.contains(&e.from) && c.contains(&e.to))
                    .cloned()
                    .collect()
            })
            .collect()
    }
}

/// The folder a module's children live in: beside `lib.rs`/`main.rs`/`mod.rs`,
/// or in `name/` beside `name.rs`.
fn child_dir(file: &Path) -> PathBuf {
    let dir = file.parent().unwrap_or(Path::new(".")).to_path_buf();
    match file.file_name().and_then(|n| n.to_str()) {
        Some("lib.rs" | "main.rs" | "mod.rs") => dir,
        _ => dir.join(file.file_stem().unwrap_or_default()),
    }
}

fn parse_module(path: &[String], file: &Path, source: &str) -> Module {
    let code = strip_test_items(&strip_comments_and_strings(source));
    let mut module = Module {
        file: file.to_path_buf(),
        ..Module::default()
    };
    let tokens = tokenize(&code);
    let mut i = 0;
    while i < tokens.len() {
        let (token, line) = (&tokens[i].0, tokens[i].1);
        let previous = if i > 0 { tokens[i - 1].0.as_str() } else { "" };
        match token.as_str() {
            "mod" if is_ident(tokens.get(i + 1)) && tokens.get(i + 2).is_some_and(|t| t.0 == ";") => {
                module.children.insert(tokens[i + 1].0.clone());
                i += 3;
                continue;
            }
            "use" if previous != "$" => {
                let end = (i..tokens.len())
                    .find(|&j| tokens[j].0 == ";")
                    .unwrap_or(tokens.len());
                let mut entries = Vec::new();
                parse_use_tree(&tokens[i + 1..end], &[], &mut entries);
                for (segments, alias) in entries {
                    let Some(absolute) = absolute_path(path, &module.children, &segments) else {
                        continue;
                    };
                    match alias.as_deref() {
                        Some("*") => module.globs.push(absolute.clone()),
                        Some("_") => {}
                        Some(name) => {
                            module.imports.insert(name.to_string(), absolute.clone());
                        }
                        None => {
                            if let Some(last) = absolute.last() {
                                module.imports.insert(last.clone(), absolute.clone());
                            }
                        }
                    }
                    module.references.push((absolute, line));
                }
                i = end + 1;
                continue;
            }
            "fn" | "struct" | "enum" | "trait" | "type" | "const" | "static" | "union" | "mod"
            | "macro_rules" => {
                let name_at = if token == "macro_rules" { i + 2 } else { i + 1 };
                if is_ident(tokens.get(name_at)) {
                    module.items.insert(tokens[name_at].0.clone());
                }
            }
            "crate" | "super" | "self"
                if previous != "$" && tokens.get(i + 1).is_some_and(|t| t.0 == "::") =>
            {
                let mut segments = vec![token.clone()];
                let mut j = i + 1;
                while tokens.get(j).is_some_and(|t| t.0 == "::") && is_ident(tokens.get(j + 1)) {
                    segments.push(tokens[j + 1].0.clone());
                    j += 2;
                }
                if let Some(absolute) = absolute_path(path, &module.children, &segments) {
                    module.references.push((absolute, line));
                }
                i = j;
                continue;
            }
            _ => {}
        }
        i += 1;
    }
    module
}

fn is_ident(token: Option<&(String, usize)>) -> bool {
    token.is_some_and(|(t, _)| t.chars().next().is_some_and(|c| c.is_alphabetic() || c == '_'))
}

/// `segments` (as written in module `path`) made absolute, or `None` for a
/// path into another crate.
fn absolute_path(path: &[String], children: &BTreeSet<String>, segments: &[String]) -> Option<ModPath> {
    let mut base: ModPath = path.to_vec();
    let mut rest = segments;
    match segments.first().map(String::as_str) {
        Some("crate") => {
            base.clear();
            rest = &segments[1..];
        }
        Some("super" | "self") => {
            while let Some(first) = rest.first() {
                match first.as_str() {
                    "super" => {
                        base.pop()?;
                    }
                    "self" => {}
                    _ => break,
                }
                rest = &rest[1..];
            }
        }
        Some(first) if children.contains(first) => {}
        _ => return None,
    }
    base.extend(rest.iter().cloned());
    Some(base)
}

/// Expands a `use` tree's tokens (after `use`, before `;`) into paths, each
/// with its alias (`Some("*")` for a glob, `Some(name)` for `as name`).
fn parse_use_tree(
    tokens: &[(String, usize)],
    prefix: &[String],
    out: &mut Vec<(Vec<String>, Option<String>)>,
) {
    let mut segments = prefix.to_vec();
    let mut i = 0;
    let start_len = prefix.len();
    while i < tokens.len() {
        let token = tokens[i].0.as_str();
        match token {
            "::" => {}
            "{" => {
                // Split the braced list at top-level commas.
                let mut depth = 0;
                let mut item_start = i + 1;
                for j in i..tokens.len() {
                    match tokens[j].0.as_str() {
                        "{" => depth += 1,
                        "}" => {
                            depth -= 1;
                            if depth == 0 {
                                if item_start < j {
                                    parse_use_tree(&tokens[item_start..j], &segments, out);
                                }
                                break;
                            }
                        }
                        "," if depth == 1 => {
                            if item_start < j {
                                parse_use_tree(&tokens[item_start..j], &segments, out);
                            }
                            item_start = j + 1;
                        }
                        _ => {}
                    }
                }
                return;
            }
            "*" => {
                out.push((segments, Some("*".into())));
                return;
            }
            "as" => {
                let alias = tokens.get(i + 1).map(|t| t.0.clone());
                out.push((segments, alias));
                return;
            }
            "self" if i == 0 && start_len > 0 => {}
            "pub" | "(" | ")" | "in" => {}
            _ => segments.push(token.to_string()),
        }
        i += 1;
    }
    if segments.len() > start_len || (start_len > 0 && tokens.iter().any(|t| t.0 == "self")) {
        out.push((segments, None));
    }
}

/// Identifiers, `::` and single punctuation characters, with their line.
fn tokenize(code: &str) -> Vec<(String, usize)> {
    let mut tokens = Vec::new();
    let mut line = 1;
    let chars: Vec<char> = code.chars().collect();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if c == '\n' {
            line += 1;
            i += 1;
        } else if c.is_whitespace() {
            i += 1;
        } else if c.is_alphanumeric() || c == '_' {
            let start = i;
            while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            let word: String = chars[start..i].iter().collect();
            let word = word.strip_prefix("r#").map(str::to_string).unwrap_or(word);
            tokens.push((word, line));
        } else if c == ':' && chars.get(i + 1) == Some(&':') {
            tokens.push(("::".into(), line));
            i += 2;
        } else {
            tokens.push((c.to_string(), line));
            i += 1;
        }
    }
    tokens
}

/// `source` with comments and string/char literals blanked (newlines kept).
fn strip_comments_and_strings(source: &str) -> String {
    let chars: Vec<char> = source.chars().collect();
    let mut out = String::with_capacity(source.len());
    let blank = |c: char| if c == '\n' { '\n' } else { ' ' };
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let next = chars.get(i + 1).copied();
        if c == '/' && next == Some('/') {
            while i < chars.len() && chars[i] != '\n' {
                out.push(' ');
                i += 1;
            }
        } else if c == '/' && next == Some('*') {
            let mut depth = 0;
            while i < chars.len() {
                if chars[i] == '/' && chars.get(i + 1) == Some(&'*') {
                    depth += 1;
                    out.push_str("  ");
                    i += 2;
                } else if chars[i] == '*' && chars.get(i + 1) == Some(&'/') {
                    depth -= 1;
                    out.push_str("  ");
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    out.push(blank(chars[i]));
                    i += 1;
                }
            }
        } else if c == 'r' && (next == Some('"') || next == Some('#')) && !prev_is_ident(&chars, i) {
            // Raw string r"..." or r#"..."#.
            let mut j = i + 1;
            let mut hashes = 0;
            while chars.get(j) == Some(&'#') {
                hashes += 1;
                j += 1;
            }
            if chars.get(j) != Some(&'"') {
                out.push(c);
                i += 1;
                continue;
            }
            j += 1;
            while j < chars.len() {
                if chars[j] == '"' && (0..hashes).all(|h| chars.get(j + 1 + h) == Some(&'#')) {
                    j += 1 + hashes;
                    break;
                }
                j += 1;
            }
            for &ch in &chars[i..j.min(chars.len())] {
                out.push(blank(ch));
            }
            i = j;
        } else if c == '"' {
            out.push(' ');
            i += 1;
            while i < chars.len() && chars[i] != '"' {
                if chars[i] == '\\' {
                    out.push(' ');
                    i += 1;
                }
                if i < chars.len() {
                    out.push(blank(chars[i]));
                    i += 1;
                }
            }
            out.push(' ');
            i += 1;
        } else if c == '\'' {
            // A char literal ('a', '\n', '\u{..}') or a lifetime ('a).
            let close = if next == Some('\\') {
                (i + 2..chars.len().min(i + 12)).find(|&j| chars[j] == '\'')
            } else if chars.get(i + 2) == Some(&'\'') {
                Some(i + 2)
            } else {
                None
            };
            match close {
                Some(end) => {
                    for _ in i..=end {
                        out.push(' ');
                    }
                    i = end + 1;
                }
                None => {
                    out.push(c);
                    i += 1;
                }
            }
        } else {
            out.push(c);
            i += 1;
        }
    }
    out
}

fn prev_is_ident(chars: &[char], i: usize) -> bool {
    i > 0 && (chars[i - 1].is_alphanumeric() || chars[i - 1] == '_')
}

/// `code` (comments and strings already blanked) with every item under
/// `#[cfg(test)]` or `#[cfg(doc)]` blanked: up to its first `;` or through the braces it opens.
fn strip_test_items(code: &str) -> String {
    let mut chars: Vec<char> = code.chars().collect();
    let len = chars.len();
    let markers: Vec<Vec<char>> = ["#[cfg(test)]", "#[cfg(doc)]"]
        .iter()
        .map(|m| m.chars().collect())
        .collect();
    let mut i = 0;
    while i < chars.len() {
        let Some(marker) = markers.iter().find(|m| chars[i..].starts_with(m)) else {
            i += 1;
            continue;
        };
        let mut j = i;
        let mut depth = 0;
        while j < chars.len() {
            match chars[j] {
                ';' if depth == 0 && j > i + marker.len() => break,
                '{' => depth += 1,
                '}' => {
                    depth -= 1;
                    if depth == 0 {
                        break;
                    }
                }
                _ => {}
            }
            j += 1;
        }
        for ch in chars.iter_mut().take((j + 1).min(len)).skip(i) {
            if *ch != '\n' {
                *ch = ' ';
            }
        }
        i = j + 1;
    }
    chars.into_iter().collect()
}

/// Every `.rs` file under `dir` (recursively), skipping `target/` folders.
pub fn rust_files(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut pending = vec![dir.to_path_buf()];
    while let Some(d) = pending.pop() {
        let Ok(entries) = fs::read_dir(&d) else { continue };
        for entry in entries.flatten() {
            let p = entry.path();
            let name = entry.file_name();
            if p.is_dir() {
                if name != "target" && name != ".git" {
                    pending.push(p);
                }
            } else if p.extension().is_some_and(|e| e == "rs") {
                files.push(p);
            }
        }
    }
    files.sort();
    files
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(dir: &Path, name: &str, text: &str) {
        let p = dir.join(name);
        fs::create_dir_all(p.parent().unwrap()).unwrap();
        fs::write(p, text).unwrap();
    }

    #[test]
    fn finds_a_cycle_through_a_root_reexport_and_a_nested_use_tree() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        write(d, "lib.rs", "mod a;\npub mod b;\npub mod c;\npub use a::Thing;\n");
        write(
            d,
            "a.rs",
            "use crate::{b::{self, Other}, c::*};\npub struct Thing;\n",
        );
        write(d, "b/mod.rs", "mod inner;\npub struct Other;\n");
        // b's child reaches a through the root's re-export: a <-> b.
        write(
            d,
            "b/inner.rs",
            "// crate::c::x in a comment is no edge\nfn f() -> crate::Thing { crate::Thing }\n",
        );
        write(d, "c.rs", "#[cfg(test)]\nmod tests { use crate::a::Thing; }\n");
        let graph = CrateGraph::read(&d.join("lib.rs")).unwrap();
        assert_eq!(graph.len(), 5);
        let edges: Vec<(ModPath, ModPath)> = graph.edges().into_iter().map(|e| (e.from, e.to)).collect();
        let p = |s: &str| vec![s.to_string()];
        assert!(edges.contains(&(p("a"), p("b"))), "{edges:?}");
        assert!(edges.contains(&(p("b"), p("a"))), "{edges:?}");
        assert!(
            !edges.iter().any(|(from, _)| from == &p("c")),
            "test code counted: {edges:?}"
        );
        let cycles = graph.cycles();
        assert_eq!(cycles.len(), 1, "{cycles:?}");
        assert!(
            cycles[0].iter().any(|e| e.at.ends_with("inner.rs:2")),
            "{cycles:?}"
        );
    }

    #[test]
    fn parent_items_and_one_way_siblings_make_no_cycle() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        write(d, "lib.rs", "pub mod p;\npub struct Root;\n");
        write(
            d,
            "p/mod.rs",
            "mod low;\nmod high;\npub struct Shared;\npub use high::run;\n",
        );
        write(
            d,
            "p/low.rs",
            "use super::Shared;\npub fn f(_: &Shared, _: crate::Root) {}\n",
        );
        write(
            d,
            "p/high.rs",
            "use super::low::f;\nlet s = \"super::high\";\npub fn run() { f(&super::Shared, crate::Root) }\n",
        );
        let graph = CrateGraph::read(&d.join("lib.rs")).unwrap();
        let edges: Vec<(ModPath, ModPath)> = graph.edges().into_iter().map(|e| (e.from, e.to)).collect();
        let pp = |s: &str| vec!["p".to_string(), s.to_string()];
        assert_eq!(edges, vec![(pp("high"), pp("low"))]);
        assert!(graph.cycles().is_empty());
    }

    #[test]
    fn a_declared_module_without_a_file_is_an_error() {
        let dir = tempfile::tempdir().unwrap();
        write(dir.path(), "lib.rs", "mod gone;\n");
        let err = CrateGraph::read(&dir.path().join("lib.rs")).unwrap_err();
        assert!(err.contains("`gone`"), "{err}");
    }
}
