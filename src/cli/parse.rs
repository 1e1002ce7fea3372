//! Value parsers of `scnc render`'s and `scnc watch`'s flags: each turns a flag's text into
//! its value or a message clap prints (exit 2), before anything is compiled.

use std::path::PathBuf;

use crate::film;
use crate::ir;

/// `--noise`: a relative standard error in 0.0001..=1, as in the scene language.
pub fn parse_noise(s: &str) -> Result<f32, String> {
    let x: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("`{s}` is not a number (try 0.01 for 1%)"))?;
    if (1e-4..=1.0).contains(&x) {
        Ok(x as f32)
    } else {
        Err(format!(
            "the noise target is a relative error in 0.0001..=1 (0.01 is 1%), got {s}"
        ))
    }
}

/// `--frame F`: a finite number.
pub fn parse_frame(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(f) if f.is_finite() => Ok(f),
        _ => Err(format!(
            "the frame is a finite number such as 12, got `{s}`"
        )),
    }
}

/// `--variance-out FILE`: a linear float format (.exr or .pfm).
pub fn parse_variance_path(s: &str) -> Result<PathBuf, String> {
    let path = PathBuf::from(s);
    match film::format_for_path(&path) {
        Some(ir::OutputFormat::Exr | ir::OutputFormat::Pfm) => Ok(path),
        _ => Err(format!(
            "the variance image is linear float: give a .exr or .pfm file, got `{s}`"
        )),
    }
}

/// Largest side accepted by `--resolution`, as in the scene language.
const MAX_SIDE: u32 = 16384;

/// `--resolution WxH`: each side in 1..=16384.
pub fn parse_resolution(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("expected WIDTHxHEIGHT such as 320x240, got `{s}`"))?;
    let side = |v: &str| -> Result<u32, String> {
        let n: u32 = v
            .trim()
            .parse()
            .map_err(|_| format!("`{v}` is not a whole number"))?;
        if (1..=MAX_SIDE).contains(&n) {
            Ok(n)
        } else {
            Err(format!("each side must be 1..={MAX_SIDE}, got {n}"))
        }
    };
    Ok((side(w)?, side(h)?))
}

/// `--define NAME=VALUE`: a name (letters, digits, `_`, not starting with a digit) and a
/// non-empty value, split at the first `=`.
pub fn parse_define(s: &str) -> Result<(String, String), String> {
    let (name, value) = s
        .split_once('=')
        .ok_or_else(|| format!("expected NAME=VALUE such as radius=2, got `{s}`"))?;
    let name = name.trim();
    let ident = name
        .chars()
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
    if !ident || value.trim().is_empty() {
        return Err(format!("expected NAME=VALUE such as radius=2, got `{s}`"));
    }
    Ok((name.to_string(), value.trim().to_string()))
}
