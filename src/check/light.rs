//! Stage 2, check: `light NAME = ...` → `ir::Light`.
//!
//! Syntax: `light bulb = point { position (0, 4, 0)  intensity rgb(10, 10, 10) }`;
//! `light ceiling = area { quad P0 P1 P2 P3  radiance rgb(17, 12, 4)  two_sided false
//! samples 4 }` (the quad emits from the side where P0 → P1 → P2 turns counter-clockwise:
//! normal = (P1 − P0) × (P2 − P0));
//! `light panel = area { mesh floor  transform { translate (0, 3, 0) }  radiance 5 }`;
//! `light sky = environment { image("sky.hdr")  intensity 1  rotate 90deg  visible true }` or
//! `environment { color rgb(0.5, 0.6, 0.9) }`. Defaults: point intensity 1; area two_sided
//! false, samples 1 (1..=1024); environment intensity 1, rotate 0deg, visible true.
//! A light that emits nothing is a warning.

use glam::{DMat4, DVec3, Vec3};

use super::names::Namespace;
use super::props::{Prop, Props};
use super::Checker;
use crate::diag::{suggest, Code, Diagnostic};
use crate::ir;
use crate::syntax::{Block, Decl};

use super::vocabulary::{LightKind, Word, LIGHT_KINDS as KINDS};

impl Checker<'_> {
    pub(super) fn light(&mut self, d: &Decl) {
        let empty = Block {
            items: Vec::new(),
            span: d.span,
        };
        let body = d.body.as_ref().unwrap_or(&empty);
        let name = d.ctor.name.name.as_str();
        let light = match (LightKind::from_word(name), &d.ctor.args) {
            (Some(LightKind::Point), None) => self.point_light(d, body),
            (Some(LightKind::Area), None) => self.area_light(d, body),
            (Some(LightKind::Environment), None) => self.environment_light(d, body),
            (_, _) => {
                self.error(
                    Diagnostic::error(
                        Code::CheckUnknownLightKind,
                        format!("unknown light kind `{name}`"),
                    )
                    .at(d.ctor.span, "not a light kind")
                    .help(suggest::help_for(name, KINDS, "light kinds")),
                );
                None
            }
        };
        if let Some(l) = light {
            self.lights.push(l);
        }
    }

    fn dark_warning(&mut self, d: &Decl, emitted: Vec3) {
        if emitted.max_element() == 0.0 {
            self.error(
                Diagnostic::warning(
                    Code::CheckDarkLight,
                    format!("light `{}` emits nothing", d.name.name),
                )
                .at(d.name.span, "zero radiance")
                .help("give it a positive radiance or intensity, or remove it"),
            );
        }
    }

    fn point_light(&mut self, d: &Decl, body: &Block) -> Option<ir::Light> {
        let props = self.split(
            body,
            "a point light",
            super::vocabulary::POINT_LIGHT_KEYS,
            &[],
            &[],
        );
        let position = match props.get("position") {
            Some(p) => self.one(p, "position (0, 4, 0)").and_then(|e| self.vec3(e)),
            None => {
                self.error(
                    Diagnostic::error(Code::CheckMissingKey, "a point light needs `position`")
                        .at(d.name.span, "no position")
                        .help("write `position (x, y, z)`"),
                );
                None
            }
        };
        let intensity = match props.get("intensity") {
            None => Some(DVec3::ONE),
            Some(p) => self
                .one(p, "intensity rgb(10, 10, 10)")
                .and_then(|e| self.color(e)),
        };
        let intensity = intensity?.as_vec3();
        self.dark_warning(d, intensity);
        Some(ir::Light::Point(ir::PointLight {
            name: d.name.name.as_str().to_owned(),
            position: position?,
            intensity,
            span: d.name.span,
        }))
    }

    fn area_light(&mut self, d: &Decl, body: &Block) -> Option<ir::Light> {
        let keys = super::vocabulary::AREA_LIGHT_KEYS;
        let props = self.split(body, "an area light", keys, &[], &["transform"]);
        let world = self.transforms(&props.transforms, "an area light");
        let mesh = self.area_light_shape(d, &props);
        let radiance = match props.get("radiance") {
            Some(p) => self
                .one(p, "radiance rgb(17, 12, 4)")
                .and_then(|e| self.color(e)),
            None => {
                self.error(
                    Diagnostic::error(Code::CheckMissingKey, "an area light needs `radiance`")
                        .at(d.name.span, "no radiance")
                        .help("write `radiance rgb(17, 12, 4)` (linear)"),
                );
                None
            }
        };
        let two_sided = match props.get("two_sided") {
            None => Some(false),
            Some(p) => self.one(p, "two_sided true").and_then(|e| self.boolean(e)),
        };
        let samples = match props.get("samples") {
            None => Some(1),
            Some(p) => self
                .one(p, "samples 4")
                .and_then(|e| self.int_in(e, 1, 1024, "area light samples")),
        };
        let radiance = radiance?.as_vec3();
        self.dark_warning(d, radiance);
        Some(ir::Light::Area(ir::AreaLight {
            name: d.name.name.as_str().to_owned(),
            mesh: mesh? as u32,
            world_from_object: world.unwrap_or(DMat4::IDENTITY),
            radiance,
            two_sided: two_sided?,
            samples: samples? as u32,
            span: d.name.span,
        }))
        .filter(|_| world.is_some())
    }

    /// The mesh an area light emits from: `quad P0 P1 P2 P3` (a new mesh) or `mesh NAME`.
    fn area_light_shape(&mut self, d: &Decl, props: &Props) -> Option<usize> {
        match (props.get("quad"), props.get("mesh")) {
            (Some(q), None) => self.quad_light_mesh(d, q),
            (None, Some(m)) => self.one(m, "mesh NAME").and_then(|e| {
                let id = self.resolve(Namespace::Mesh, e)?;
                if let Some(u) = self.used_meshes.get_mut(id) {
                    *u = true;
                }
                Some(id)
            }),
            (Some(q), Some(m)) => {
                self.error(
                    Diagnostic::error(
                        Code::CheckConflictingKeys,
                        "an area light takes either `quad` or `mesh`, not both",
                    )
                    .at(m.key_span, "mesh here")
                    .also(q.key_span, "quad here"),
                );
                None
            }
            (None, None) => {
                self.error(
                    Diagnostic::error(
                        Code::CheckMissingKey,
                        "an area light needs a shape: `quad P0 P1 P2 P3` or `mesh NAME`",
                    )
                    .at(d.name.span, "no shape"),
                );
                None
            }
        }
    }

    /// `quad P0 P1 P2 P3` as a two-triangle mesh of its own; its first three corners must
    /// span an area.
    fn quad_light_mesh(&mut self, d: &Decl, q: &Prop) -> Option<usize> {
        let v = self.arity::<4>(q, "quad P0 P1 P2 P3")?;
        let pts: Vec<Option<DVec3>> = v.iter().map(|e| self.vec3(e)).collect();
        let pts: Vec<DVec3> = pts.into_iter().collect::<Option<_>>()?;
        let [p0, p1, p2, _] = pts[..] else {
            return None;
        };
        if (p1 - p0).cross(p2 - p0).length() == 0.0 {
            self.error(
                Diagnostic::error(Code::CheckDegenerateQuad, "the quad has no area")
                    .at(q.span(), "its first three corners are in a line"),
            );
            return None;
        }
        let id = self.meshes.len();
        self.meshes.push(Some(ir::Mesh {
            name: format!("light {}", d.name.name),
            source: ir::MeshSource::Inline(Box::new(ir::InlineMesh {
                positions: pts.iter().map(|p| p.as_vec3()).collect(),
                normals: Vec::new(),
                uvs: Vec::new(),
                indices: vec![[0, 1, 2], [0, 2, 3]],
            })),
            span: q.key_span,
            obj: None,
        }));
        Some(id)
    }

    fn environment_light(&mut self, d: &Decl, body: &Block) -> Option<ir::Light> {
        let keys = super::vocabulary::ENVIRONMENT_LIGHT_KEYS;
        let props = self.split(body, "an environment light", keys, &[], &[]);
        let source = match (props.get("image"), props.get("color")) {
            (Some(i), None) => self
                .one(i, "image(\"sky.hdr\")")
                .and_then(|e| self.asset_path(e))
                .map(ir::EnvSource::Image),
            (None, Some(c)) => self
                .one(c, "color rgb(0.5, 0.6, 0.9)")
                .and_then(|e| self.color(e))
                .map(|c| ir::EnvSource::Constant(c.as_vec3())),
            (Some(i), Some(c)) => {
                self.error(
                    Diagnostic::error(
                        Code::CheckConflictingKeys,
                        "an environment takes either `image(...)` or `color`, not both",
                    )
                    .at(c.key_span, "color here")
                    .also(i.key_span, "image here"),
                );
                None
            }
            (None, None) => {
                self.error(
                    Diagnostic::error(
                        Code::CheckMissingKey,
                        "an environment needs `image(\"file.hdr\")` or `color C`",
                    )
                    .at(d.name.span, "no source"),
                );
                None
            }
        };
        let intensity = match props.get("intensity") {
            None => Some(1.0),
            Some(p) => self
                .one(p, "intensity 1")
                .and_then(|e| self.num_in(e, 0.0, f64::MAX, "intensity")),
        };
        let rotation = match props.get("rotate") {
            None => Some(0.0),
            Some(p) => self.one(p, "rotate 90deg").and_then(|e| self.angle(e)),
        };
        let visible = match props.get("visible") {
            None => Some(true),
            Some(p) => self.one(p, "visible true").and_then(|e| self.boolean(e)),
        };
        let intensity = intensity? as f32;
        let emitted = match &source {
            Some(ir::EnvSource::Constant(c)) => *c * intensity,
            _ => Vec3::splat(intensity),
        };
        self.dark_warning(d, emitted);
        Some(ir::Light::Environment(ir::EnvironmentLight {
            name: d.name.name.as_str().to_owned(),
            source: source?,
            intensity,
            rotation_y_rad: rotation? as f32,
            visible: visible?,
            span: d.name.span,
        }))
    }
}
