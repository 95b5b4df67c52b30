//! Argument helpers shared by the benchmark tools.

/// Removes and returns a leading count argument (`tool 5 scene.obj` -> 5), or `default` if the
/// first argument is not a number. Never less than 1.
#[allow(dead_code)]
pub fn leading_count(args: &mut Vec<String>, default: usize) -> usize {
    match args.first().and_then(|a| a.parse::<usize>().ok()) {
        Some(n) => {
            args.remove(0);
            n.max(1)
        }
        None => default,
    }
}

/// The scenes named on the command line, or the benchmark views of Conference and Sponza when
/// none is given; None (after printing the usage line) for `-h` / `--help`.
#[allow(dead_code)]
pub fn scenes_or_default(tool: &str) -> Option<Vec<String>> {
    let scenes: Vec<String> = std::env::args().skip(1).collect();
    if scenes.iter().any(|a| a == "-h" || a == "--help") {
        println!("usage: {tool} [SCENE...]");
        return None;
    }
    if scenes.is_empty() {
        return Some(vec!["scenes/bench/conference.yaml".into(), "scenes/bench/sponza.yaml".into()]);
    }
    Some(scenes)
}
