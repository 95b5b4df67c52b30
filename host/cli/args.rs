//! Value parsers for the command line: each turns a flag's text into its value or into one
//! plain sentence saying what is wrong ("must be a whole number of at least 1, not -5").

use crate::output::display::Exposure;
use glam::Vec3;

/// A whole number of at least 1 (`--spp`, `--width`, `--max-depth`, ...).
pub fn at_least_one(s: &str) -> Result<u32, String> {
    let s = s.trim();
    match s.parse::<i64>() {
        Ok(n) if n >= 1 && n <= u32::MAX as i64 => Ok(n as u32),
        Ok(n) if n < 1 => Err(format!("must be a whole number of at least 1, not {n}")),
        Ok(n) => Err(format!("{n} is too large (at most {})", u32::MAX)),
        Err(_) => Err(format!("must be a whole number of at least 1, not '{s}'")),
    }
}

/// A whole number of at least 0 (`--seed`, `--camera`).
pub fn whole(s: &str) -> Result<u32, String> {
    let s = s.trim();
    match s.parse::<i64>() {
        Ok(n) if (0..=u32::MAX as i64).contains(&n) => Ok(n as u32),
        Ok(n) if n < 0 => Err(format!("must be a whole number of at least 0, not {n}")),
        Ok(n) => Err(format!("{n} is too large (at most {})", u32::MAX)),
        Err(_) => Err(format!("must be a whole number, not '{s}'")),
    }
}

/// A finite number above 0 (`--time`, `--target-relmse`, intervals).
pub fn positive(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(x) if x.is_finite() && x > 0.0 => Ok(x),
        Ok(x) => Err(format!("must be a number above 0, not {x}")),
        Err(_) => Err(format!("must be a number above 0, not '{}'", s.trim())),
    }
}

/// A vertical field of view in degrees, strictly between 0 and 180.
pub fn fov(s: &str) -> Result<f32, String> {
    match s.trim().parse::<f32>() {
        Ok(x) if x > 0.0 && x < 180.0 => Ok(x),
        _ => Err(format!("must be an angle in degrees between 0 and 180, not '{}'", s.trim())),
    }
}

/// A finite number of at least 0 (`--aperture`, `--focus-distance`).
pub fn non_negative(s: &str) -> Result<f32, String> {
    match s.trim().parse::<f32>() {
        Ok(x) if x.is_finite() && x >= 0.0 => Ok(x),
        _ => Err(format!("must be a number of at least 0, not '{}'", s.trim())),
    }
}

/// Three finite numbers `X,Y,Z` (`--eye`, `--target`, `--up`).
pub fn vec3(s: &str) -> Result<Vec3, String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    let nums: Vec<f32> = parts.iter().filter_map(|p| p.parse::<f32>().ok()).filter(|x| x.is_finite()).collect();
    match (parts.len(), nums.as_slice()) {
        (3, &[x, y, z]) => Ok(Vec3::new(x, y, z)),
        _ => Err(format!("must be three numbers X,Y,Z (e.g. 0,1.5,-3), not '{s}'")),
    }
}

/// An exposure in stops (`--exposure -1.5`), or `auto`.
pub fn exposure(s: &str) -> Result<Exposure, String> {
    let s = s.trim();
    if s.eq_ignore_ascii_case("auto") {
        return Ok(Exposure::Auto);
    }
    match s.parse::<f32>() {
        Ok(ev) if ev.is_finite() && ev.abs() <= 64.0 => Ok(Exposure::Ev(ev)),
        _ => Err(format!("must be a number of stops (e.g. 1.5 or -2) or 'auto', not '{s}'")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plain_messages_for_bad_numbers() {
        assert_eq!(at_least_one("4"), Ok(4));
        assert!(at_least_one("-5").unwrap_err().contains("at least 1, not -5"));
        assert!(at_least_one("0").is_err() && at_least_one("many").is_err() && at_least_one("1e20").is_err());
        assert_eq!(whole("0"), Ok(0));
        assert!(whole("-1").unwrap_err().contains("not -1"));
        assert_eq!(vec3(" 1, -2,3.5"), Ok(Vec3::new(1.0, -2.0, 3.5)));
        assert!(vec3("1,2").is_err() && vec3("1,2,nan").is_err() && vec3("1,2,3,4").is_err());
        assert!(positive("0").is_err() && positive("inf").is_err() && positive("2.5") == Ok(2.5));
        assert!(fov("180").is_err() && fov("60") == Ok(60.0));
        assert_eq!(exposure("AUTO"), Ok(Exposure::Auto));
        assert_eq!(exposure("-1.5"), Ok(Exposure::Ev(-1.5)));
        assert!(exposure("bright").is_err());
    }
}
