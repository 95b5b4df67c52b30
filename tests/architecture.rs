//! The module rule of docs/ARCHITECTURE.md, checked on the source: every `crate::<module>` a
//! module's code names (comments aside) must be in that module's "may import" column of the
//! table there. So data flows one way (no import cycles) and no GPU format reaches `geom`,
//! `scene` or `bvh`.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// module -> the modules it may import, from the table in docs/ARCHITECTURE.md.
fn rule() -> BTreeMap<String, BTreeSet<String>> {
    let doc = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/ARCHITECTURE.md")).unwrap();
    let mut rule = BTreeMap::new();
    for line in doc.lines().filter(|l| l.starts_with("| `")) {
        let cells: Vec<&str> = line.trim_matches('|').split('|').map(str::trim).collect();
        let names = |cell: &str| -> BTreeSet<String> { cell.split('`').skip(1).step_by(2).map(str::to_string).collect() };
        let module = names(cells[0]).into_iter().next().unwrap();
        rule.insert(module, names(cells[cells.len() - 1]));
    }
    rule
}

/// Every module `crate::<name>` or `crate::{<name>, ...}` names in the code of `file`: comments
/// are skipped, and so is a file's `#[cfg(test)]` part (its unit tests, at the end by habit).
fn crate_refs(file: &Path) -> BTreeSet<String> {
    let text = std::fs::read_to_string(file).unwrap();
    let ident = |s: &str| -> String { s.trim().chars().take_while(|c| c.is_ascii_alphanumeric() || *c == '_').collect() };
    let mut code = String::new();
    for line in text.lines() {
        if line.trim() == "#[cfg(test)]" {
            break;
        }
        code.push_str(line.split("//").next().unwrap_or(""));
        code.push(' ');
    }
    let mut out = BTreeSet::new();
    let mut rest = code.as_str();
    // `$crate::` in a macro is the crate root, the same as `crate::`.
    while let Some(i) = rest.find("crate::") {
        let after = &rest[i + "crate::".len()..];
        if let Some(list) = after.strip_prefix('{') {
            out.extend(list.split('}').next().unwrap_or("").split(',').map(ident).filter(|n| !n.is_empty()));
        } else {
            out.insert(ident(after));
        }
        rest = after;
    }
    out
}

fn rust_files(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

#[test]
fn every_module_imports_only_what_the_architecture_allows() {
    let rule = rule();
    let host = Path::new(env!("CARGO_MANIFEST_DIR")).join("host");
    let mut checked = BTreeSet::new();
    let mut violations = Vec::new();
    for entry in std::fs::read_dir(&host).unwrap() {
        let path = entry.unwrap().path();
        let module = path.file_stem().unwrap().to_string_lossy().into_owned();
        if ["lib", "main", "build"].contains(&module.as_str()) {
            continue;
        }
        let allowed = rule.get(&module).unwrap_or_else(|| panic!("module {module} is not in docs/ARCHITECTURE.md's table"));
        let mut files = Vec::new();
        if path.is_dir() {
            rust_files(&path, &mut files)
        } else {
            files.push(path.clone())
        }
        for file in files {
            for name in crate_refs(&file) {
                if name != module && !allowed.contains(&name) {
                    violations.push(format!("{} uses crate::{name}, which {module} may not import", file.display()));
                }
            }
        }
        checked.insert(module);
    }
    assert!(violations.is_empty(), "{}", violations.join("\n"));
    let documented: BTreeSet<String> = rule.keys().cloned().collect();
    assert_eq!(checked, documented, "modules in host/ vs modules in docs/ARCHITECTURE.md");
}

/// The rule itself has no cycle (so it is a one-way flow) and keeps the GPU formats out of the
/// foundations.
#[test]
fn the_rule_is_one_way_and_the_foundations_know_no_gpu_format() {
    let rule = rule();
    for low in ["geom", "scene", "bvh"] {
        assert!(!rule[low].contains("gpu_abi"), "{low} may import gpu_abi");
    }
    assert!(!rule["scene"].contains("bvh") && !rule["bvh"].contains("scene"), "scene and bvh may import each other");
    assert!(!rule["integrator"].contains("scene"), "integrators may reach back to the CPU scene");
    // Files are output's (checkpoints included): an integrator hands over sums and images.
    assert!(!rule["integrator"].contains("files") && !rule["integrator"].contains("bytes"), "integrators may write files");
    // Depth-first search for a cycle.
    fn visit(m: &str, rule: &BTreeMap<String, BTreeSet<String>>, path: &mut Vec<String>, done: &mut BTreeSet<String>) {
        if done.contains(m) {
            return;
        }
        assert!(!path.iter().any(|p| p == m), "import cycle: {} -> {m}", path.join(" -> "));
        path.push(m.to_string());
        for next in rule.get(m).into_iter().flatten() {
            visit(next, rule, path, done);
        }
        path.pop();
        done.insert(m.to_string());
    }
    let mut done = BTreeSet::new();
    for m in rule.keys() {
        visit(m, &rule, &mut Vec::new(), &mut done);
    }
}
