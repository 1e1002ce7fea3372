//! The IR after an edit (the incremental compile): every span of a [`SceneDesc`] moved by the
//! edit's [`Shift`](crate::source::Shift) (or its files' ids by a
//! [`Renumber`](crate::source::Renumber)), so that a scene whose statements were not re-checked
//! points into the new text exactly as a fresh check's would.

use super::{EnvSource, Light, Material, Mesh, MeshSource, SceneDesc, Texture, TextureSource};
use crate::source::{MoveSpans, Span};

impl SceneDesc {
    /// Moves every span by `shift`; `false` when one reaches into the edited bytes (or names
    /// a file removed).
    pub fn shift_spans(&mut self, shift: &impl MoveSpans) -> bool {
        let mut ok = true;
        for m in &mut self.meshes {
            ok &= m.shift_spans(shift);
        }
        for t in &mut self.textures {
            ok &= t.shift_spans(shift);
        }
        for m in &mut self.materials {
            ok &= m.shift_spans(shift);
        }
        let mut apply = |span: &mut Span| ok &= shift.apply(span);
        for c in &mut self.cameras {
            apply(&mut c.span);
        }
        for o in &mut self.objects {
            apply(&mut o.span);
        }
        for l in &mut self.lights {
            match l {
                Light::Point(p) => apply(&mut p.span),
                Light::Area(a) => apply(&mut a.span),
                Light::Environment(e) => {
                    apply(&mut e.span);
                    if let EnvSource::Image(path) = &mut e.source {
                        apply(&mut path.span);
                    }
                }
            }
        }
        for o in &mut self.render.outputs {
            apply(&mut o.file.span);
        }
        ok
    }
}

impl Mesh {
    /// Moves every span of the mesh by `shift`; `false` when one reaches into the edited bytes.
    pub fn shift_spans(&mut self, shift: &impl MoveSpans) -> bool {
        let mut ok = shift.apply(&mut self.span);
        if let MeshSource::Obj(path) = &mut self.source {
            ok &= shift.apply(&mut path.span);
        }
        for o in self.obj.iter_mut().flat_map(|o| &mut o.materials) {
            ok &= shift.apply(&mut o.span);
        }
        ok
    }
}

impl Texture {
    /// Moves every span of the texture by `shift` (as [`Mesh::shift_spans`]).
    pub fn shift_spans(&mut self, shift: &impl MoveSpans) -> bool {
        let mut ok = shift.apply(&mut self.span);
        if let TextureSource::Image { file, .. } = &mut self.source {
            ok &= shift.apply(&mut file.span);
        }
        ok
    }
}

impl Material {
    /// Moves the material's span by `shift` (as [`Mesh::shift_spans`]).
    pub fn shift_spans(&mut self, shift: &impl MoveSpans) -> bool {
        shift.apply(&mut self.span)
    }
}
