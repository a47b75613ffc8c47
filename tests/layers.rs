//! The library's modules point one way: the graph of references between
//! the top-level modules of `src/` (a file or a directory directly under
//! `src/`) has no cycle.
//!
//! The sources are parsed with `syn`; every path that names an item of the
//! crate counts, wherever it stands: `use` trees, paths in types and
//! expressions, `#[cfg(test)]` code, and string attributes such as
//! `serialize_with = "crate::ser::display"`. A path through a re-export
//! (`crate::Finger`, `super::Load`) counts for the module that defines the
//! item, and for the module that re-exports it. `cargo test --test layers
//! -- --nocapture` prints the layers, lowest first.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use syn::visit::Visit;

/// A module's path from the crate root (`[]` is `lib.rs`).
type ModPath = Vec<String>;

/// The files of `src/`, each with its module path.
fn sources() -> Vec<(ModPath, PathBuf)> {
    fn walk(dir: &Path, prefix: &[String], out: &mut Vec<(ModPath, PathBuf)>) {
        let mut entries: Vec<_> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .collect();
        entries.sort();
        for path in entries {
            let name = path.file_name().unwrap().to_str().unwrap().to_string();
            if path.is_dir() {
                let mut p = prefix.to_vec();
                p.push(name);
                walk(&path, &p, out);
            } else if let Some(stem) = name.strip_suffix(".rs") {
                let mut p = prefix.to_vec();
                if !(stem == "mod" || (prefix.is_empty() && stem == "lib")) {
                    p.push(stem.to_string());
                }
                out.push((p, path));
            }
        }
    }
    let mut out = Vec::new();
    walk(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("src"),
        &[],
        &mut out,
    );
    out
}

/// What the crate's sources say about their paths: the modules, the
/// re-exports, and every path reference with the module it stands in.
#[derive(Default)]
struct Crate {
    modules: BTreeSet<ModPath>,
    /// (module, name) -> the absolute path it re-exports
    reexports: BTreeMap<(ModPath, String), ModPath>,
    /// (the module the path stands in, the path as written, is a re-export)
    refs: Vec<(ModPath, Vec<String>, bool)>,
}

struct Collector<'a> {
    krate: &'a mut Crate,
    module: ModPath,
}

impl Collector<'_> {
    fn use_tree(&mut self, tree: &syn::UseTree, prefix: &mut Vec<String>, public: bool) {
        match tree {
            syn::UseTree::Path(p) => {
                prefix.push(p.ident.to_string());
                self.use_tree(&p.tree, prefix, public);
                prefix.pop();
            }
            syn::UseTree::Name(n) => {
                let mut path = prefix.clone();
                let name = n.ident.to_string();
                if name != "self" {
                    path.push(name.clone());
                }
                self.add_use(path, name, public);
            }
            syn::UseTree::Rename(r) => {
                let mut path = prefix.clone();
                path.push(r.ident.to_string());
                self.add_use(path, r.rename.to_string(), public);
            }
            syn::UseTree::Glob(_) => {
                self.krate
                    .refs
                    .push((self.module.clone(), prefix.clone(), public));
            }
            syn::UseTree::Group(g) => {
                for t in &g.items {
                    self.use_tree(t, prefix, public);
                }
            }
        }
    }

    fn add_use(&mut self, path: Vec<String>, name: String, public: bool) {
        if public {
            self.krate
                .reexports
                .insert((self.module.clone(), name), path.clone());
        }
        self.krate.refs.push((self.module.clone(), path, public));
    }
}

impl<'ast> Visit<'ast> for Collector<'_> {
    fn visit_item_mod(&mut self, m: &'ast syn::ItemMod) {
        self.module.push(m.ident.to_string());
        self.krate.modules.insert(self.module.clone());
        syn::visit::visit_item_mod(self, m);
        self.module.pop();
    }

    fn visit_item_use(&mut self, u: &'ast syn::ItemUse) {
        let public = !matches!(u.vis, syn::Visibility::Inherited);
        self.use_tree(&u.tree, &mut Vec::new(), public);
    }

    fn visit_path(&mut self, p: &'ast syn::Path) {
        if p.segments.len() > 1 {
            let path = p.segments.iter().map(|s| s.ident.to_string()).collect();
            self.krate.refs.push((self.module.clone(), path, false));
        }
        syn::visit::visit_path(self, p);
    }

    fn visit_macro(&mut self, m: &'ast syn::Macro) {
        // paths inside a macro's tokens: `crate :: a :: b`, `super :: a`
        fn scan(tokens: proc_macro2::TokenStream, out: &mut Vec<Vec<String>>) {
            let tokens: Vec<_> = tokens.into_iter().collect();
            let mut i = 0;
            while i < tokens.len() {
                if let proc_macro2::TokenTree::Group(g) = &tokens[i] {
                    scan(g.stream(), out);
                }
                let starts = matches!(&tokens[i], proc_macro2::TokenTree::Ident(id)
                    if id == "crate" || id == "super");
                let before = i > 0
                    && matches!(&tokens[i - 1], proc_macro2::TokenTree::Punct(p) if p.as_char() == ':');
                if starts && !before {
                    let mut path = vec![tokens[i].to_string()];
                    let mut j = i + 1;
                    while j + 2 < tokens.len()
                        && matches!(&tokens[j], proc_macro2::TokenTree::Punct(p) if p.as_char() == ':')
                        && matches!(&tokens[j + 1], proc_macro2::TokenTree::Punct(p) if p.as_char() == ':')
                    {
                        match &tokens[j + 2] {
                            proc_macro2::TokenTree::Ident(id) => path.push(id.to_string()),
                            _ => break,
                        }
                        j += 3;
                    }
                    if path.len() > 1 {
                        out.push(path);
                    }
                    i = j;
                } else {
                    i += 1;
                }
            }
        }
        let mut paths = Vec::new();
        scan(m.tokens.clone(), &mut paths);
        for path in paths {
            self.krate.refs.push((self.module.clone(), path, false));
        }
        syn::visit::visit_macro(self, m);
    }

    fn visit_lit_str(&mut self, s: &'ast syn::LitStr) {
        let value = s.value();
        if value.starts_with("crate::") || value.starts_with("super::") {
            let path = value.split("::").map(str::to_string).collect();
            self.krate.refs.push((self.module.clone(), path, false));
        }
    }
}

impl Crate {
    fn read() -> Crate {
        let mut krate = Crate::default();
        let files = sources();
        for (module, _) in &files {
            krate.modules.insert(module.clone());
        }
        for (module, path) in files {
            let text = std::fs::read_to_string(&path).unwrap();
            let file = syn::parse_file(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            let mut c = Collector {
                krate: &mut krate,
                module,
            };
            c.visit_file(&file);
        }
        krate
    }

    /// The absolute path of `path` written in `module`, or `None` for a
    /// path outside the crate (`std::`, `serde::`, a local item, a variant).
    fn absolute(&self, module: &[String], path: &[String]) -> Option<ModPath> {
        let mut base = module.to_vec();
        let mut rest = path;
        match rest.first().map(String::as_str) {
            Some("crate") => {
                base.clear();
                rest = &rest[1..];
            }
            Some("self") => rest = &rest[1..],
            Some("super") => {
                while rest.first().map(String::as_str) == Some("super") {
                    base.pop()?;
                    rest = &rest[1..];
                }
            }
            Some(first) => {
                let mut child = base.clone();
                child.push(first.to_string());
                if !self.modules.contains(&child)
                    && !self
                        .reexports
                        .contains_key(&(base.clone(), first.to_string()))
                {
                    return None;
                }
            }
            None => return None,
        }
        base.extend(rest.iter().cloned());
        Some(base)
    }

    /// The module that defines the item `path` names, following
    /// re-exports.
    fn defining_module(&self, mut path: ModPath) -> ModPath {
        for _ in 0..16 {
            // the longest prefix that is a module
            let mut k = path.len();
            while k > 0 && !self.modules.contains(&path[..k]) {
                k -= 1;
            }
            if k == path.len() {
                return path;
            }
            let key = (path[..k].to_vec(), path[k].clone());
            match self.reexports.get(&key) {
                Some(target) => match self.absolute(&path[..k], target) {
                    Some(mut abs) if abs != path[..=k] => {
                        abs.extend(path[k + 1..].iter().cloned());
                        path = abs;
                    }
                    _ => return path[..k].to_vec(),
                },
                None => return path[..k].to_vec(),
            }
        }
        panic!("re-exports loop at {path:?}");
    }

    /// The edges between the nodes `node` maps modules to (`None`: not a
    /// node), each with one reference that makes it, for the message.
    fn graph(&self, node: impl Fn(&[String]) -> Option<String>) -> Graph {
        let mut graph = Graph::new();
        for (module, path, public) in &self.refs {
            let Some(from) = node(module) else { continue };
            graph.entry(from.clone()).or_default();
            let Some(abs) = self.absolute(module, path) else {
                continue;
            };
            let mut targets = vec![self.defining_module(abs.clone())];
            if *public {
                // a re-export also depends on the module it names
                let mut k = abs.len();
                while k > 0 && !self.modules.contains(&abs[..k]) {
                    k -= 1;
                }
                targets.push(abs[..k].to_vec());
            }
            for target in targets {
                if let Some(to) = node(&target) {
                    if to != from {
                        graph
                            .entry(from.clone())
                            .or_default()
                            .entry(to)
                            .or_insert_with(|| {
                                format!("{} in {}", path.join("::"), module.join("::"))
                            });
                    }
                }
            }
        }
        graph
    }
}

/// node -> (node it depends on -> one reference that makes the edge)
type Graph = BTreeMap<String, BTreeMap<String, String>>;

/// A cycle of `graph` (its nodes in order, the first repeated at the end),
/// if it has one.
fn find_cycle(graph: &Graph) -> Option<Vec<String>> {
    #[derive(Clone, Copy, PartialEq)]
    enum Mark {
        Open,
        Done,
    }
    fn visit(
        node: &str,
        graph: &Graph,
        marks: &mut BTreeMap<String, Mark>,
        stack: &mut Vec<String>,
    ) -> Option<Vec<String>> {
        match marks.get(node) {
            Some(Mark::Done) => return None,
            Some(Mark::Open) => {
                let start = stack.iter().position(|n| n == node).unwrap();
                let mut cycle = stack[start..].to_vec();
                cycle.push(node.to_string());
                return Some(cycle);
            }
            None => {}
        }
        marks.insert(node.to_string(), Mark::Open);
        stack.push(node.to_string());
        for next in graph.get(node).into_iter().flat_map(|e| e.keys()) {
            if let Some(cycle) = visit(next, graph, marks, stack) {
                return Some(cycle);
            }
        }
        stack.pop();
        marks.insert(node.to_string(), Mark::Done);
        None
    }
    let mut marks = BTreeMap::new();
    for node in graph.keys() {
        if let Some(cycle) = visit(node, graph, &mut marks, &mut Vec::new()) {
            return Some(cycle);
        }
    }
    None
}

/// The nodes of an acyclic `graph` in layers: each node above all it
/// depends on.
fn layers(graph: &Graph) -> Vec<Vec<String>> {
    let mut nodes: BTreeSet<&String> = graph
        .keys()
        .chain(graph.values().flat_map(|e| e.keys()))
        .collect();
    let mut placed = BTreeSet::new();
    let mut out = Vec::new();
    while !nodes.is_empty() {
        let layer: Vec<String> = nodes
            .iter()
            .filter(|n| {
                graph
                    .get(n.as_str())
                    .is_none_or(|e| e.keys().all(|d| placed.contains(d)))
            })
            .map(|n| n.to_string())
            .collect();
        assert!(!layer.is_empty(), "a cycle among {nodes:?}");
        for n in &layer {
            nodes.remove(n);
        }
        placed.extend(layer.iter().cloned());
        out.push(layer);
    }
    out
}

fn check(name: &str, graph: &Graph) {
    if let Some(cycle) = find_cycle(graph) {
        eprintln!("the {name} graph:");
        for (from, edges) in graph {
            for (to, why) in edges {
                eprintln!("  {from} -> {to}   ({why})");
            }
        }
        let steps: Vec<String> = cycle
            .windows(2)
            .map(|w| format!("  {} -> {}   ({})", w[0], w[1], graph[&w[0]][&w[1]]))
            .collect();
        panic!(
            "the {name} modules import in a circle:\n{}",
            steps.join("\n")
        );
    }
    println!("{name} layers, lowest first:");
    for (i, layer) in layers(graph).iter().enumerate() {
        println!("  {i}: {}", layer.join(", "));
    }
}

#[test]
fn top_level_modules_point_one_way() {
    let krate = Crate::read();
    let graph = krate.graph(|m| m.first().cloned());
    // the check sees the graph: the finger core uses the element models
    assert!(graph["finger"].contains_key("model"), "{graph:?}");
    check("top-level", &graph);
}

fn hand_made(edges: &[(&str, &str)]) -> Graph {
    let mut g = Graph::new();
    for (a, b) in edges {
        g.entry(a.to_string())
            .or_default()
            .insert(b.to_string(), String::new());
        g.entry(b.to_string()).or_default();
    }
    g
}

#[test]
fn the_cycle_finder_finds_a_cycle() {
    let g = hand_made(&[("a", "b"), ("b", "c"), ("c", "d"), ("d", "b"), ("a", "e")]);
    let cycle = find_cycle(&g).expect("b -> c -> d -> b");
    assert_eq!(cycle, ["b", "c", "d", "b"]);
    let g = hand_made(&[("a", "a")]);
    assert_eq!(find_cycle(&g).unwrap(), ["a", "a"]);
}

#[test]
fn the_cycle_finder_passes_a_layered_graph() {
    let g = hand_made(&[("a", "b"), ("a", "c"), ("b", "c"), ("c", "d"), ("e", "d")]);
    assert_eq!(find_cycle(&g), None);
    assert_eq!(
        layers(&g),
        [vec!["d"], vec!["c", "e"], vec!["b"], vec!["a"]]
    );
}

#[test]
fn a_path_resolves_through_re_exports() {
    let mut krate = Crate::default();
    for m in [vec![], vec!["a".to_string()], vec!["b".to_string()]] {
        krate.modules.insert(m);
    }
    let s = |v: &[&str]| v.iter().map(|x| x.to_string()).collect::<Vec<_>>();
    // lib.rs: pub use a::X;  a: pub use crate::b::X;
    krate.reexports.insert((vec![], "X".into()), s(&["a", "X"]));
    krate
        .reexports
        .insert((s(&["a"]), "X".into()), s(&["crate", "b", "X"]));
    let abs = krate.absolute(&s(&["b"]), &s(&["crate", "X"])).unwrap();
    assert_eq!(krate.defining_module(abs), s(&["b"]));
    assert_eq!(krate.absolute(&s(&["b"]), &s(&["std", "fmt"])), None);
    assert_eq!(
        krate.absolute(&s(&["a", "tests"]), &s(&["super", "super", "b", "Y"])),
        Some(s(&["b", "Y"]))
    );
}

#[test]
fn every_module_points_one_way() {
    let krate = Crate::read();
    let graph = krate.graph(|m| Some(m.join("::")));
    // the check sees the files: the finger's solver uses its chain
    assert!(
        graph["finger::solver"].contains_key("finger::chain"),
        "{graph:?}"
    );
    check("module", &graph);
}
