//! Stage 2, check: `camera NAME { ... }` → `ir::Camera`.
//!
//! Syntax: `camera main { eye (278, 273, -800)  target (278, 273, 0)  up (0, 1, 0)  fov 39.3deg }`
//! or `camera side { transform { look_at (0, 1, -5) (0, 1, 0) (0, 1, 0) }  fov 40deg }` (the
//! camera sits at its local origin looking down local +z with +y up). `up` defaults to
//! (0, 1, 0), `fov` (vertical) to 40deg and must lie in (0deg, 180deg).

use glam::DVec3;

use super::props::Props;
use super::Checker;
use crate::diag::{Code, Diagnostic};
use crate::ir;
use crate::source::Span;
use crate::syntax::{Block, Ident};

use super::vocabulary::CAMERA_KEYS as KEYS;

/// Where a camera is and where it looks, before the frame is made orthonormal.
struct Placement {
    eye: DVec3,
    forward: DVec3,
    up: DVec3,
    /// Where to point when `up` turns out parallel to the view.
    up_span: Span,
}

impl Checker<'_> {
    pub(super) fn camera(&mut self, name: &Ident, body: &Block, span: Span) -> Option<ir::Camera> {
        let props = self.split(body, "a camera", KEYS, &[], &["transform"]);
        let fov = self.camera_fov(&props)?;
        let placed = if props.transforms.is_empty() {
            self.camera_look(name, &props)?
        } else {
            self.camera_transform(&props)?
        };
        let forward = placed.forward.try_normalize()?;
        let right = self.camera_right(forward, &placed)?;
        let up = right.cross(forward);
        Some(ir::Camera {
            name: name.name.as_str().to_owned(),
            eye: placed.eye,
            forward: forward.as_vec3(),
            up: up.as_vec3(),
            right: right.as_vec3(),
            fov_y_rad: fov as f32,
            span,
        })
    }

    /// `fov 40deg` (vertical, in radians), strictly between 0 and 180 degrees.
    fn camera_fov(&mut self, props: &Props) -> Option<f64> {
        let Some(p) = props.get("fov") else {
            return Some(40f64.to_radians());
        };
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
        Some(a)
    }

    /// `transform { ... }`: the camera at its local origin looking down +z, +y up; it excludes
    /// `eye`/`target`/`up`.
    fn camera_transform(&mut self, props: &Props) -> Option<Placement> {
        let look = props.get("eye").or(props.get("target")).or(props.get("up"));
        if let Some(p) = look {
            self.error(
                Diagnostic::error(
                    Code::CheckConflictingKeys,
                    "a camera takes either `eye`/`target`/`up` or a `transform`, not both",
                )
                .at(p.key_span, "here")
                .also(props.transforms[0].span, "and a transform here"),
            );
            return None;
        }
        let m = self.transforms(&props.transforms, "a camera")?;
        Some(Placement {
            eye: m.transform_point3(DVec3::ZERO),
            forward: m.transform_vector3(DVec3::Z),
            up: m.transform_vector3(DVec3::Y),
            up_span: props.transforms[0].span,
        })
    }

    /// `eye P  target Q  up U`: both points required, and distinct.
    fn camera_look(&mut self, name: &Ident, props: &Props) -> Option<Placement> {
        let (Some(eye_p), Some(target_p)) = (props.get("eye"), props.get("target")) else {
            self.error(
                Diagnostic::error(
                    Code::CheckMissingKey,
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
        let (up, up_span) = match props.get("up") {
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
                    Code::CheckZeroDirection,
                    "camera target equals its eye: no view direction",
                )
                .at(
                    target_e.map_or(target_p.key_span, |e| e.span),
                    "same point as `eye`",
                ),
            );
            return None;
        }
        Some(Placement {
            eye,
            forward: target - eye,
            up,
            up_span,
        })
    }

    /// The unit right vector, or an error when `up` is along the view.
    fn camera_right(&mut self, forward: DVec3, placed: &Placement) -> Option<DVec3> {
        // `up` exactly along the view still leaves a cross product of rounding noise (~1e-16),
        // which would normalise to an arbitrary frame: treat a sine below 1e-9 as parallel.
        let cross = forward.cross(placed.up);
        let right = cross
            .try_normalize()
            .filter(|_| cross.length() > 1e-9 * placed.up.length());
        if right.is_none() {
            self.error(
                Diagnostic::error(
                    Code::CheckUpParallel,
                    "`up` is parallel to the view direction",
                )
                .at(placed.up_span, "parallel to the view")
                .help("choose an up vector that is not along eye → target, e.g. (0, 0, 1)"),
            );
        }
        right
    }
}
