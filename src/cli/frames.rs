//! `scnc render scene.scn --frames A..B[:STEP] -o out_####.png`: renders frames A to B
//! (inclusive) every STEP, each as `scnc render --frame F` would, into `-o`'s name with its
//! run of `#`s replaced by the zero-padded frame number.
//!
//! One `scene::BuildCache` is kept across the frames: meshes, the BVH (when no instance
//! transform depends on `frame`), the environment map and image textures are built once and
//! reused; each frame's line says what was rebuilt. A frame that fails is reported and the
//! others still render (exit 1 at the end); Ctrl-C stops the run.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use super::render::{run_frame, RenderArgs};
use super::report::{report, JsonTo};
use crate::diag::{Code, Diagnostic, Staged};
use crate::scene::BuildCache;
use crate::source::SourceMap;

/// `--frames A..B[:STEP]`: frames `start..=end` every `step`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FrameRange {
    /// First frame.
    pub start: i64,
    /// Last frame (inclusive).
    pub end: i64,
    /// Distance between frames, at least 1.
    pub step: u64,
}

impl FrameRange {
    /// The frames, in order.
    pub fn frames(self) -> impl Iterator<Item = i64> {
        let step = usize::try_from(self.step).unwrap_or(usize::MAX);
        (self.start..=self.end).step_by(step.max(1))
    }
}

/// Parses `A..B` or `A..B:STEP` (whole numbers, `A <= B`, `STEP >= 1`).
pub fn parse_frames(s: &str) -> Result<FrameRange, String> {
    let usage = || format!("expected A..B or A..B:STEP such as 0..239:2, got `{s}`");
    let (range, step) = match s.split_once(':') {
        Some((r, st)) => (r, st.trim().parse::<u64>().map_err(|_| usage())?),
        None => (s, 1),
    };
    let (a, b) = range.split_once("..").ok_or_else(usage)?;
    let (start, end) = (
        a.trim().parse::<i64>().map_err(|_| usage())?,
        b.trim().parse::<i64>().map_err(|_| usage())?,
    );
    if step == 0 || start > end {
        return Err(format!(
            "the frames run from A up to B (inclusive) by a STEP of at least 1, got `{s}`"
        ));
    }
    Ok(FrameRange { start, end, step })
}

/// `pattern` with its first run of `#`s replaced by `frame`, zero-padded to the run's length;
/// `None` if the file name has no `#`.
pub fn numbered(pattern: &Path, frame: i64) -> Option<PathBuf> {
    let name = pattern.file_name()?.to_str()?;
    let at = name.find('#')?;
    let len = name[at..].chars().take_while(|c| *c == '#').count();
    let digits = format!("{:0len$}", frame.unsigned_abs());
    let sign = if frame < 0 { "-" } else { "" };
    let new = format!("{}{sign}{digits}{}", &name[..at], &name[at + len..]);
    Some(pattern.with_file_name(new))
}

/// Renders every frame of `range` (see the module doc).
pub fn run(args: &RenderArgs, range: FrameRange) -> ExitCode {
    let Some(pattern) = args.output.as_deref().filter(|p| numbered(p, 0).is_some()) else {
        let d = Diagnostic::error(
            Code::CliFramesWithoutPattern,
            "`--frames` writes a file per frame, but `-o` has no `#`s to number them",
        )
        .help("give `-o NAME_####.png`: the #s become the zero-padded frame number");
        report(
            &Staged::<()>::failed(vec![d]),
            &SourceMap::new(),
            &args.diag,
            JsonTo::Stdout,
        );
        return ExitCode::FAILURE;
    };
    let mut cache = BuildCache::new();
    let mut failed = false;
    for frame in range.frames() {
        let mut one = args.clone();
        one.frames = None;
        one.frame = Some(frame as f64);
        one.output = numbered(pattern, frame);
        let code = run_frame(&one, Some(&mut cache));
        let rebuilt = cache.report().rebuilt();
        eprintln!(
            "frame {frame}: rebuilt {}",
            if rebuilt.is_empty() {
                "nothing".to_string()
            } else {
                rebuilt.join(", ")
            }
        );
        if code == ExitCode::from(130) {
            return code;
        }
        failed |= code != ExitCode::SUCCESS;
    }
    if failed {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_ranges() {
        let r = parse_frames("0..6:3").expect("range");
        assert_eq!(r.frames().collect::<Vec<_>>(), [0, 3, 6]);
        assert_eq!(parse_frames("-2..1").expect("range").frames().count(), 4);
        for bad in ["3..1", "0..4:0", "0-4", "a..b", "1..2:x"] {
            assert!(parse_frames(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn numbers_the_first_run_of_hashes() {
        let n = |p: &str, f| numbered(Path::new(p), f).map(|p| p.display().to_string());
        assert_eq!(n("out/f_####.png", 7).as_deref(), Some("out/f_0007.png"));
        assert_eq!(n("f#.exr", 123).as_deref(), Some("f123.exr"));
        assert_eq!(n("f_###.png", -4).as_deref(), Some("f_-004.png"));
        assert_eq!(n("dir#/f.png", 1), None, "only the file name is numbered");
    }
}
