//! Stage 2, check: `transform { ... }` blocks → a 4×4 matrix.
//!
//! Syntax: `transform { translate V  rotate AXIS ANGLE  scale S|V  look_at EYE TARGET UP
//! matrix [16 numbers, row-major] }`. Operations compose in WRITTEN ORDER: each applies to the
//! result of the previous ones, so `rotate y 15deg  translate (10, 0, 0)` first rotates, then
//! translates (`world = T · R`). AXIS is `x`, `y`, `z` or a vector. `look_at` places the local
//! frame at EYE with local +z towards TARGET and local +y as close to UP as possible (how a
//! camera with a transform is aimed).

use glam::{DMat4, DVec3, Mat4};

use super::array;
use super::props::Prop;
use super::Checker;
use crate::diag::{Code, Diagnostic};
use crate::syntax::{Block, Expr, ExprKind};

/// The keys of `transform { ... }`, applied in the order written.
pub const TRANSFORM_KEYS: &[&str] = &["translate", "rotate", "scale", "look_at", "matrix"];

/// The rigid frame at `eye` with +z towards `target` and +y towards `up`; `None` if degenerate.
pub fn look_at(eye: DVec3, target: DVec3, up: DVec3) -> Option<DMat4> {
    let f = (target - eye).try_normalize()?;
    let s = up.cross(f);
    // A sine below 1e-9 is `up` along the view plus rounding noise, not a direction.
    if s.length() <= 1e-9 * up.length() {
        return None;
    }
    let s = s.try_normalize()?;
    let u = f.cross(s);
    Some(DMat4::from_cols(
        s.extend(0.0),
        u.extend(0.0),
        f.extend(0.0),
        eye.extend(1.0),
    ))
}

impl Checker<'_> {
    /// The matrix of every `transform` block in `blocks` (at most one is allowed), or identity.
    pub fn transforms(&mut self, blocks: &[&Block], what: &str) -> Option<DMat4> {
        if let [first, second, ..] = blocks {
            self.error(
                Diagnostic::error(
                    Code::CheckDuplicateKey,
                    format!("`transform` is given twice in {what}"),
                )
                .at(second.span, "given again here")
                .also(first.span, "first given here")
                .help("put every operation in one `transform` block, in order"),
            );
        }
        match blocks.first() {
            Some(b) => self.transform(b),
            None => Some(DMat4::IDENTITY),
        }
    }

    /// One `transform { ... }` block as a matrix (world from object).
    pub fn transform(&mut self, block: &Block) -> Option<DMat4> {
        let props = self.split(block, "a transform", TRANSFORM_KEYS, TRANSFORM_KEYS, &[]);
        let mut m = DMat4::IDENTITY;
        let mut ok = true;
        for p in &props.props {
            match self.op(p) {
                Some(op) => m = op * m,
                None => ok = false,
            }
        }
        // Kept in f64 to the build, which places the scene relative to an origin near it.
        ok.then_some(m)
    }

    fn op(&mut self, p: &Prop) -> Option<DMat4> {
        match p.key {
            "translate" => {
                let e = self.one(p, "translate (x, y, z)")?;
                Some(DMat4::from_translation(self.vec3(e)?))
            }
            "rotate" => {
                let v = self.arity::<2>(p, "rotate y 30deg")?;
                let axis = self.axis(v[0]);
                let angle = self.angle(v[1]);
                Some(DMat4::from_axis_angle(axis?, angle?))
            }
            "scale" => {
                let e = self.one(p, "scale 2  or  scale (1, 2, 1)")?;
                let s = self.vec3_or_num(e)?;
                if s.x * s.y * s.z == 0.0 {
                    self.error(
                        Diagnostic::error(Code::CheckDegenerateTransform, "scale of zero")
                            .at(e.span, "flattens everything")
                            .help("every scale factor must be non-zero"),
                    );
                    return None;
                }
                Some(DMat4::from_scale(s))
            }
            "look_at" => {
                let v = self.arity::<3>(p, "look_at EYE TARGET UP")?;
                let (eye, target, up) = (self.vec3(v[0]), self.vec3(v[1]), self.vec3(v[2]));
                let m = look_at(eye?, target?, up?);
                if m.is_none() {
                    self.error(
                        Diagnostic::error(
                            Code::CheckDegenerateTransform,
                            "look_at has no direction: eye equals target, or up is parallel to the view",
                        )
                        .at(p.span(), "this look_at")
                        .help("move the target away from the eye and pick an up not along the view"),
                    );
                }
                m
            }
            _ => {
                let e = self.one(p, "matrix [16 numbers, row-major]")?;
                self.matrix(e)
            }
        }
    }

    fn axis(&mut self, e: &Expr) -> Option<DVec3> {
        if let ExprKind::Name(n) = &e.kind {
            // Bytes: a `Name`'s `as_str` checks UTF-8.
            match n.as_bytes() {
                b"x" => return Some(DVec3::X),
                b"y" => return Some(DVec3::Y),
                b"z" => return Some(DVec3::Z),
                _ => {}
            }
        }
        let v = self.vec3(e)?;
        let n = v.try_normalize();
        if n.is_none() {
            self.error(
                Diagnostic::error(Code::CheckZeroDirection, "rotation axis has zero length")
                    .at(e.span, "cannot be normalised"),
            );
        }
        n
    }

    fn matrix(&mut self, e: &Expr) -> Option<DMat4> {
        if !matches!(e.kind, ExprKind::Array) {
            self.error(
                Diagnostic::error(Code::CheckWrongType, "expected `[16 numbers]`")
                    .at(e.span, "not an array"),
            );
            return None;
        }
        let text = self.sources.snippet(e.span);
        let nums = match array::numbers(text) {
            Ok(n) => n,
            Err(err) => {
                let span = err.span(e.span);
                self.error(Diagnostic::error(Code::CheckBadArray, err.message).at(span, "here"));
                return None;
            }
        };
        let Ok(rows) = <[f32; 16]>::try_from(nums.as_slice()) else {
            self.error(
                Diagnostic::error(
                    Code::CheckWrongArity,
                    format!("a matrix has 16 numbers, found {}", nums.len()),
                )
                .at(e.span, "this matrix"),
            );
            return None;
        };
        let m = Mat4::from_cols_array(&rows).transpose().as_dmat4();
        if m.determinant().abs() < 1e-12 {
            self.error(
                Diagnostic::error(Code::CheckDegenerateTransform, "matrix is not invertible")
                    .at(e.span, "determinant is zero"),
            );
            return None;
        }
        Some(m)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn look_at_maps_z_to_the_view_direction() {
        let m = look_at(
            DVec3::new(0.0, 1.0, -5.0),
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::Y,
        )
        .expect("valid");
        assert!((m.transform_vector3(DVec3::Z) - DVec3::Z).length() < 1e-12);
        assert!((m.transform_point3(DVec3::ZERO) - DVec3::new(0.0, 1.0, -5.0)).length() < 1e-12);
        assert!((m.determinant() - 1.0).abs() < 1e-12);
        assert!(look_at(DVec3::ZERO, DVec3::Y, DVec3::Y).is_none());
    }
}
