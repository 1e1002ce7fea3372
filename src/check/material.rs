//! Stage 2, check: `material NAME = phong { ... }` → `ir::Material`.
//!
//! Syntax: `material shiny = phong { diffuse #808080  specular 0.4  shininess 64  ambient 0 }`,
//! `material wood = phong { diffuse woodtex  normal_map bumps  normal_strength 0.8
//! normal_green opengl }`. Defaults: diffuse 0.5 grey, specular 0, shininess 32, ambient 0,
//! no normal map, normal_strength 1, normal_green opengl. Albedos (diffuse, specular) are
//! reflectances: each channel in [0, 1]. `diffuse`, `specular` and `shininess` may name a
//! texture instead of giving a constant.

use glam::DVec3;

use super::names::Namespace;
use super::props::Props;
use super::Checker;
use crate::diag::{suggest, Code, Diagnostic};
use crate::ir;
use crate::source::Span;
use crate::syntax::{Decl, Expr};

use super::vocabulary::{MaterialKind, Word, MATERIAL_KEYS as KEYS};

impl Checker<'_> {
    /// Lowers a material; also returns the texture table indices it refers to.
    pub(super) fn material(&mut self, d: &Decl) -> (Option<ir::Material>, Vec<usize>) {
        let mut textures = Vec::new();
        let kind = MaterialKind::from_word(&d.ctor.name.name);
        if !matches!((kind, &d.ctor.args), (Some(MaterialKind::Phong), None)) {
            self.unknown_material_kind(d);
            return (None, textures);
        }
        let empty = crate::syntax::Block {
            items: Vec::new(),
            span: d.span,
        };
        let body = d.body.as_ref().unwrap_or(&empty);
        let props = self.split(body, "a phong material", KEYS, &[], &[]);
        let diffuse = self.color_input(&props, "diffuse", 0.5, &mut textures);
        let specular = self.color_input(&props, "specular", 0.0, &mut textures);
        let shininess = self.shininess(&props, &mut textures);
        let ambient = match props.get("ambient") {
            None => Some(DVec3::ZERO),
            Some(p) => self.one(p, "ambient 0").and_then(|e| self.color(e)),
        };
        let normal_map = self.normal_map(&props, &mut textures);
        let (Some(diffuse), Some(specular), Some(shininess), Some(ambient), Some(normal_map)) =
            (diffuse, specular, shininess, ambient, normal_map)
        else {
            return (None, textures);
        };
        let m = ir::Material {
            name: d.name.name.as_str().to_owned(),
            diffuse,
            specular,
            shininess,
            ambient: ambient.as_vec3(),
            normal_map,
            span: d.name.span,
        };
        (Some(m), textures)
    }

    fn unknown_material_kind(&mut self, d: &Decl) {
        self.error(
            Diagnostic::error(
                Code::CheckUnknownMaterialKind,
                format!("unknown material kind `{}`", d.ctor.name.name),
            )
            .at(d.ctor.span, "not a material kind")
            .help(suggest::help_for(
                &d.ctor.name.name,
                super::vocabulary::MATERIAL_KINDS,
                "material kinds",
            )),
        );
    }

    /// `diffuse C` / `specular C`: a texture name or a constant albedo.
    fn color_input(
        &mut self,
        props: &Props,
        key: &str,
        default: f64,
        textures: &mut Vec<usize>,
    ) -> Option<ir::ColorInput> {
        let Some(p) = props.get(key) else {
            return Some(ir::ColorInput::Constant(DVec3::splat(default).as_vec3()));
        };
        let e = self.one(p, format_args!("{key} rgb(0.8, 0.8, 0.8)"))?;
        if let Some(t) = self.texture_ref(e) {
            textures.push(t);
            return Some(ir::ColorInput::Texture(t as u32));
        }
        let c = self.albedo(e, key)?;
        Some(ir::ColorInput::Constant(c.as_vec3()))
    }

    /// `shininess N`: a texture name or a number in [0, 1e6].
    fn shininess(&mut self, props: &Props, textures: &mut Vec<usize>) -> Option<ir::ScalarInput> {
        let Some(p) = props.get("shininess") else {
            return Some(ir::ScalarInput::Constant(32.0));
        };
        let e = self.one(p, "shininess 64")?;
        if let Some(t) = self.texture_ref(e) {
            textures.push(t);
            return Some(ir::ScalarInput::Texture(t as u32));
        }
        self.num_in(e, 0.0, 1.0e6, "shininess")
            .map(|x| ir::ScalarInput::Constant(x as f32))
    }

    /// `normal_map T  normal_strength S  normal_green opengl|directx`; `Some(None)` without
    /// a map. Every key is checked before any error returns.
    fn normal_map(
        &mut self,
        props: &Props,
        textures: &mut Vec<usize>,
    ) -> Option<Option<ir::NormalMap>> {
        let strength = match props.get("normal_strength") {
            None => Some(1.0),
            Some(p) => self
                .one(p, "normal_strength 1")
                .and_then(|e| self.num_in(e, 0.0, 16.0, "normal_strength")),
        };
        let green = match props.get("normal_green") {
            None => Some(ir::GreenConvention::OpenGl),
            Some(p) => self
                .one(p, "normal_green opengl")
                .and_then(|e| self.choice::<ir::GreenConvention>(e, "normal map convention")),
        };
        let texture = match props.get("normal_map") {
            None => Some(None),
            Some(p) => self.one(p, "normal_map TEXTURE").and_then(|e| {
                let t = self.resolve(Namespace::Texture, e)?;
                textures.push(t);
                self.warn_srgb_normal_map(t, e);
                Some(Some(t))
            }),
        };
        let (strength, green, texture) = (strength?, green?, texture?);
        Some(texture.map(|t| ir::NormalMap {
            texture: t as u32,
            strength: strength as f32,
            green,
        }))
    }

    /// The texture a bare name refers to, if it names one (constants are tried otherwise).
    fn texture_ref(&mut self, e: &Expr) -> Option<usize> {
        let name = e.as_name()?;
        if self.lets.contains_key(name) {
            return None;
        }
        let found = self.has(Namespace::Texture, name);
        if found {
            return self.resolve(Namespace::Texture, e);
        }
        None
    }

    /// A reflectance: a colour with every channel in [0, 1].
    fn albedo(&mut self, e: &Expr, key: &str) -> Option<DVec3> {
        if let Some(name) = e.as_name() {
            if !self.lets.contains_key(name)
                && !self.poisoned.contains(name)
                && !matches!(name, "true" | "false")
            {
                // Neither a texture nor a constant: say both were looked for. The constants
                // in the order they were declared (a map's order would change from run to run).
                let mut lets: Vec<(&str, Span)> = self.lets.names_and_spans().collect();
                lets.sort_unstable_by_key(|&(_, at)| (at.file.0, at.start));
                let mut candidates: Vec<String> =
                    lets.into_iter().map(|(name, _)| name.to_string()).collect();
                candidates.extend(self.texture_names());
                let refs: Vec<&str> = candidates.iter().map(String::as_str).collect();
                self.error(
                    Diagnostic::error(
                        Code::CheckUnknownName,
                        format!("unknown texture or constant `{name}`"),
                    )
                    .at(e.span, "not declared")
                    .help(suggest::help_for(
                        name,
                        &refs,
                        "textures and constants",
                    )),
                );
                return None;
            }
        }
        let c = self.color(e)?;
        if c.max_element() > 1.0 {
            self.error(
                Diagnostic::error(
                    Code::CheckAlbedoOutOfRange,
                    format!(
                        "{key} albedo must be at most 1 per channel, found {}",
                        c.max_element()
                    ),
                )
                .at(e.span, "reflects more light than it receives")
                .help(
                    "albedo is a reflectance in [0, 1]; to emit light use a `light` or `ambient`",
                ),
            );
            return None;
        }
        Some(c)
    }
}
