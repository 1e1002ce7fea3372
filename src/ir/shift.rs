//! The IR after an edit (the incremental compile): every span of a [`SceneDesc`] moved by the
//! edit's [`Shift`], so that a scene whose statements were not re-checked points into the new
//! text exactly as a fresh check's would.

use super::{EnvSource, Light, MeshSource, SceneDesc, TextureSource};
use crate::source::{Shift, Span};

impl SceneDesc {
    /// Moves every span by `shift`; `false` when one reaches into the edited bytes.
    pub fn shift_spans(&mut self, shift: &Shift) -> bool {
        let mut ok = true;
        let mut apply = |span: &mut Span| ok &= shift.apply(span);
        for c in &mut self.cameras {
            apply(&mut c.span);
        }
        for m in &mut self.meshes {
            apply(&mut m.span);
            if let MeshSource::Obj(path) = &mut m.source {
                apply(&mut path.span);
            }
            for o in m.obj.iter_mut().flat_map(|o| &mut o.materials) {
                apply(&mut o.span);
            }
        }
        for t in &mut self.textures {
            apply(&mut t.span);
            if let TextureSource::Image { file, .. } = &mut t.source {
                apply(&mut file.span);
            }
        }
        for m in &mut self.materials {
            apply(&mut m.span);
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
