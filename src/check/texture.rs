//! Stage 2, check: `texture NAME = ...` → `ir::Texture`.
//!
//! Syntax: `texture wood = image("wood.png") { wrap repeat  filter trilinear }` (colour,
//! sRGB-decoded), `texture bumps = image("bumps.png") { encoding data }` (data, read raw),
//! `texture board = checker { even #ffffff  odd #202020  scale 8 }`,
//! `texture grey = constant { color 0.5 }`. Defaults: wrap repeat, filter anisotropic, encoding
//! srgb; checker even 0.8, odd 0.2, scale 4 (squares per UV unit).

use glam::DVec3;

use super::names::Namespace;
use super::Checker;
use crate::diag::{suggest, Code, Diagnostic};
use crate::ir;
use crate::syntax::{Block, Decl, Expr};

use super::vocabulary::{TextureKind, Word, TEXTURE_KINDS as KINDS};

impl Checker<'_> {
    pub(super) fn texture(&mut self, d: &Decl) -> Option<ir::Texture> {
        let empty = Block {
            items: Vec::new(),
            span: d.span,
        };
        let body = d.body.as_ref().unwrap_or(&empty);
        let name = d.ctor.name.name.as_str();
        let source = match (TextureKind::from_word(name), &d.ctor.args) {
            (Some(TextureKind::Image), Some(args)) => self.image_texture(args, d, body)?,
            (Some(TextureKind::Checker), None) => {
                let props = self.split(
                    body,
                    "a checker texture",
                    super::vocabulary::CHECKER_KEYS,
                    &[],
                    &[],
                );
                let col = |cx: &mut Self, key: &str, default: f64| match props.get(key) {
                    None => Some(DVec3::splat(default)),
                    Some(p) => cx
                        .one(p, format_args!("{key} #ffffff"))
                        .and_then(|e| cx.color(e)),
                };
                let even = col(self, "even", 0.8);
                let odd = col(self, "odd", 0.2);
                let scale = match props.get("scale") {
                    None => Some(4.0),
                    Some(p) => self
                        .one(p, "scale 8")
                        .and_then(|e| self.positive(e, "scale")),
                };
                ir::TextureSource::Checker {
                    even: ir::ColorInput::Constant(even?.as_vec3()),
                    odd: ir::ColorInput::Constant(odd?.as_vec3()),
                    scale: scale? as f32,
                }
            }
            (Some(TextureKind::Constant), None) => {
                let props = self.split(
                    body,
                    "a constant texture",
                    super::vocabulary::CONSTANT_TEXTURE_KEYS,
                    &[],
                    &[],
                );
                let c = match props.get("color") {
                    None => DVec3::splat(0.5),
                    Some(p) => {
                        let e = self.one(p, "color rgb(0.5, 0.5, 0.5)")?;
                        self.color(e)?
                    }
                };
                ir::TextureSource::Constant(c.as_vec3())
            }
            (kind, _) => {
                let help = if kind.is_some() {
                    "write `image(\"file.png\")`, `checker { ... }` or `constant { ... }`"
                        .to_string()
                } else {
                    suggest::help_for(name, KINDS, "texture kinds")
                };
                self.error(
                    Diagnostic::error(
                        Code::CheckUnknownTextureKind,
                        format!("unknown texture kind `{name}`"),
                    )
                    .at(d.ctor.span, "not a texture kind")
                    .help(help),
                );
                return None;
            }
        };
        Some(ir::Texture {
            name: d.name.name.as_str().to_owned(),
            source,
            span: d.name.span,
        })
    }

    fn image_texture(
        &mut self,
        args: &[Expr],
        d: &Decl,
        body: &Block,
    ) -> Option<ir::TextureSource> {
        let props = self.split(
            body,
            "an image texture",
            super::vocabulary::IMAGE_TEXTURE_KEYS,
            &[],
            &[],
        );
        let file = match args {
            [one] => self.asset_path(one),
            _ => {
                self.error(
                    Diagnostic::error(Code::CheckWrongArity, "`image` takes one file name")
                        .at(d.ctor.span, "here")
                        .help("write `image(\"file.png\")`"),
                );
                None
            }
        };
        let wrap = match props.get("wrap") {
            None => Some(ir::WrapMode::Repeat),
            Some(p) => self
                .one(p, "wrap repeat")
                .and_then(|e| self.choice::<ir::WrapMode>(e, "wrap mode")),
        };
        let filter = match props.get("filter") {
            None => Some(ir::Filter::Anisotropic),
            Some(p) => self
                .one(p, "filter anisotropic")
                .and_then(|e| self.choice::<ir::Filter>(e, "filter")),
        };
        let encoding = match props.get("encoding") {
            None => Some(ir::TextureEncoding::Srgb),
            Some(p) => self
                .one(p, "encoding data")
                .and_then(|e| self.choice::<ir::TextureEncoding>(e, "encoding")),
        };
        Some(ir::TextureSource::Image {
            file: file?,
            encoding: encoding?,
            wrap: wrap?,
            filter: filter?,
        })
    }

    pub(super) fn texture_names(&self) -> Vec<String> {
        let table = &self.tables[Namespace::Texture as usize];
        table.names().into_iter().map(str::to_string).collect()
    }

    /// A normal map read through the sRGB curve is almost always a mistake.
    pub(super) fn warn_srgb_normal_map(&mut self, t: usize, e: &Expr) {
        if let Some(Some(ir::Texture {
            source:
                ir::TextureSource::Image {
                    encoding: ir::TextureEncoding::Srgb,
                    ..
                },
            ..
        })) = self.textures.get(t)
        {
            self.error(
                Diagnostic::warning(
                    Code::CheckSrgbNormalMap,
                    "this normal map is decoded as an sRGB colour image",
                )
                .at(e.span, "normal map")
                .help("add `encoding data` to the texture so its values are read raw"),
            );
        }
    }

    /// A number > 0.
    pub fn positive(&mut self, e: &Expr, what: &str) -> Option<f64> {
        let x = self.num(e, "a number")?;
        if x <= 0.0 {
            self.out_of_range(e.span, &format!("{what} must be greater than 0, found {x}"));
            return None;
        }
        Some(x)
    }
}
