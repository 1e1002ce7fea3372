//! Stage 2, check: `camera NAME { ... }` → `ir::Camera`.
//!
//! Syntax: `camera main { eye (278, 273, -800)  target (278, 273, 0)  up (0, 1, 0)  fov 39.3deg }`
//! or `camera side { transform { look_at (0, 1, -5) (0, 1, 0) (0, 1, 0) }  fov 40deg }` (the
//! camera sits at its local origin looking down local +z with +y up). `up` defaults to
//! (0, 1, 0), `fov` (vertical) to 40deg and must lie in (0deg, 180deg).

use glam::DVec3;

use super::Checker;
use crate::diag::Diagnostic;
use crate::ir;
use crate::source::Span;
use crate::syntax::{Block, Ident};

use super::vocabulary::CAMERA_KEYS as KEYS;

impl Checker<'_> {
    pub(super) fn camera(&mut self, name: &Ident, body: &Block, span: Span) -> Option<ir::Camera> {
        let props = self.split(body, "a camera", KEYS, &[], &["transform"]);
        let fov = match props.get("fov") {
            Some(p) => {
                let e = self.one(p, "fov 40deg")?;
                let a = self.angle(e)?;
                if !(a > 0.0 && a < std::f64::consts::PI) {
                    self.out_of_range(
                        e.span,
                        &format!(
                            "fov must be between 0deg and 180deg (exclusive), found {}deg",
                            a.to_degrees()
                        ),
                    );
                    return None;
                }
                a
            }
            None => 40f64.to_radians(),
        };
        let eye_p = props.get("eye");
        let target_p = props.get("target");
        let up_p = props.get("up");
        let (eye, forward, up, up_span) = if !props.transforms.is_empty() {
            if let Some(p) = eye_p.or(target_p).or(up_p) {
                self.error(
                    Diagnostic::error(
                        "scnc::check::conflicting_keys",
                        "a camera takes either `eye`/`target`/`up` or a `transform`, not both",
                    )
                    .at(p.key_span, "here")
                    .also(props.transforms[0].span, "and a transform here"),
                );
                return None;
            }
            let m = self.transforms(&props.transforms, "a camera")?;
            (
                m.transform_point3(DVec3::ZERO),
                m.transform_vector3(DVec3::Z),
                m.transform_vector3(DVec3::Y),
                props.transforms[0].span,
            )
        } else {
            let (Some(eye_p), Some(target_p)) = (eye_p, target_p) else {
                self.error(
                    Diagnostic::error(
                        "scnc::check::missing_key",
                        format!(
                            "camera `{}` needs `eye` and `target` (or a `transform`)",
                            name.name
                        ),
                    )
                    .at(name.span, "incomplete camera")
                    .help("write `eye (0, 1, -5)  target (0, 1, 0)`"),
                );
                return None;
            };
            let eye = self.one(eye_p, "eye (x, y, z)").and_then(|e| self.vec3(e));
            let target_e = self.one(target_p, "target (x, y, z)");
            let target = target_e.and_then(|e| self.vec3(e));
            let (up, up_span) = match up_p {
                Some(p) => {
                    let e = self.one(p, "up (0, 1, 0)")?;
                    (self.vec3(e)?, e.span)
                }
                None => (DVec3::Y, target_p.key_span),
            };
            let (eye, target) = (eye?, target?);
            if (target - eye).length() == 0.0 {
                self.error(
                    Diagnostic::error(
                        "scnc::check::zero_direction",
                        "camera target equals its eye: no view direction",
                    )
                    .at(
                        target_e.map_or(target_p.key_span, |e| e.span),
                        "same point as `eye`",
                    ),
                );
                return None;
            }
            (eye, target - eye, up, up_span)
        };
        let forward = forward.try_normalize()?;
        // `up` exactly along the view still leaves a cross product of rounding noise (~1e-16),
        // which would normalise to an arbitrary frame: treat a sine below 1e-9 as parallel.
        let cross = forward.cross(up);
        let Some(right) = cross
            .try_normalize()
            .filter(|_| cross.length() > 1e-9 * up.length())
        else {
            self.error(
                Diagnostic::error(
                    "scnc::check::up_parallel",
                    "`up` is parallel to the view direction",
                )
                .at(up_span, "parallel to the view")
                .help("choose an up vector that is not along eye → target, e.g. (0, 0, 1)"),
            );
            return None;
        };
        let up = right.cross(forward);
        Some(ir::Camera {
            name: name.name.clone(),
            eye,
            forward: forward.as_vec3(),
            up: up.as_vec3(),
            right: right.as_vec3(),
            fov_y_rad: fov as f32,
            span,
        })
    }
}
