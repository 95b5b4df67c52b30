//! Argument helpers shared by the benchmark tools (each tool includes this file as a module).

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
