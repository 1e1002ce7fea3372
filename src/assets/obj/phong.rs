//! MTL material → scnc's Phong parameters (stage 3, asset decoding). No `.scn` syntax of its
//! own; `scene::build` turns the result into a material (or, for `Ke`, an area light) and
//! `scnc inspect` prints it.
//!
//! MTL is the Phong model, so the mapping is direct: `Kd` → diffuse, `Ks` → specular, `Ns` →
//! shininess, `Ke` → emitted radiance (a part with `Ke` > 0 becomes an area light). scnc's
//! Phong is energy-conserving, so `Kd`, `Ks` are clamped to [0, 1] and, where `Kd + Ks` exceeds 1
//! in a channel, both are scaled down (the mapping says so). `Ka` is read but not rendered:
//! scnc has no ambient light level for it to multiply, and Blender writes `Ka 1 1 1`, which as
//! ambient radiance would make every exported object glow. Missing values take the MTL
//! defaults (`Kd` 0.8, `Ks` 0, `Ns` 0). `map_Kd`, `map_Ks` and `norm` maps render (see
//! [`renders_map`]); the others keep their constants with a warning.

use glam::Vec3;

use super::mtl::{BumpKind, MtlMaterial, TexRef};

/// The Phong parameters of one MTL material.
#[derive(Debug, Clone, PartialEq)]
pub struct ObjPhong {
    /// Diffuse albedo (`Kd`), each channel in [0, 1].
    pub diffuse: Vec3,
    /// Specular albedo (`Ks`), each channel in [0, 1]; `diffuse + specular ≤ 1` per channel.
    pub specular: Vec3,
    /// Phong exponent (`Ns`), in [0, 10000].
    pub shininess: f32,
    /// Radiance emitted (zero: not a light).
    pub emission: Vec3,
    /// What was changed to make it energy-conserving, for `scnc inspect` and warnings.
    pub adjusted: Option<String>,
    /// Texture maps named by the MTL (which of them render: [`renders_map`]).
    pub maps: Vec<(&'static str, TexRef)>,
}

impl ObjPhong {
    /// Whether it emits (some channel of `Ke` > 0): its faces become an area light.
    pub fn is_emitter(&self) -> bool {
        self.emission.max_element() > 0.0
    }
}

/// The default for faces with no (or an unknown) material: MTL's default grey.
pub fn default_phong() -> ObjPhong {
    ObjPhong {
        diffuse: Vec3::splat(0.8),
        specular: Vec3::ZERO,
        shininess: 0.0,
        emission: Vec3::ZERO,
        adjusted: None,
        maps: Vec::new(),
    }
}

/// The Phong parameters of `m`: MTL defaults for missing values, zero for non-finite ones,
/// `Kd`/`Ks` made energy-conserving as the module doc describes.
pub fn phong_of(m: &MtlMaterial) -> ObjPhong {
    let finite = |v: Vec3| if v.is_finite() { v } else { Vec3::ZERO };
    let kd = finite(m.kd.unwrap_or(Vec3::splat(0.8)));
    let ks = finite(m.ks.unwrap_or(Vec3::ZERO));
    let mut diffuse = kd.clamp(Vec3::ZERO, Vec3::ONE);
    let mut specular = ks.clamp(Vec3::ZERO, Vec3::ONE);
    let sum = (diffuse + specular).max_element();
    if sum > 1.0 {
        diffuse /= sum;
        specular /= sum;
    }
    let adjusted = (diffuse != kd || specular != ks).then(|| {
        format!("Kd + Ks scaled to conserve energy (Kd {kd}, Ks {ks} → {diffuse}, {specular})")
    });
    let ns =
        m.ns.filter(|n| n.is_finite())
            .unwrap_or(0.0)
            .clamp(0.0, 10_000.0);
    let emission = finite(m.ke.unwrap_or(Vec3::ZERO)).max(Vec3::ZERO);
    let mut maps = Vec::new();
    for (key, t) in [
        ("map_Kd", &m.map_kd),
        ("map_Ks", &m.map_ks),
        ("map_Ns", &m.map_ns),
    ] {
        if let Some(t) = t {
            maps.push((key, t.clone()));
        }
    }
    if let Some((kind, t)) = &m.bump {
        let key = match kind {
            BumpKind::Height => "bump",
            BumpKind::Normal => "norm",
        };
        maps.push((key, t.clone()));
    }
    ObjPhong {
        diffuse,
        specular,
        shininess: ns,
        emission,
        adjusted,
        maps,
    }
}

/// Whether scnc renders an MTL map written with `key` (`map_Kd`, `map_Ks`, `norm`): colour maps
/// replace their constant, `norm` is a tangent-space normal map. `map_Ns` (scnc's scalar
/// textures give the exponent itself, not a 0..1 factor of `Ns`) and height maps (`bump`,
/// `map_Bump`: scnc has no bump mapping) keep their material's constants, with a warning.
pub fn renders_map(key: &str) -> bool {
    matches!(key, "map_Kd" | "map_Ks" | "norm")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn energy_is_conserved_and_defaults_apply() {
        let m = MtlMaterial {
            kd: Some(Vec3::new(0.9, 0.5, 2.0)),
            ks: Some(Vec3::splat(0.5)),
            ns: Some(64.0),
            ke: Some(Vec3::new(4.0, 4.0, 3.0)),
            ..MtlMaterial::default()
        };
        let p = phong_of(&m);
        assert!((p.diffuse + p.specular).max_element() <= 1.0 + 1e-6);
        assert!(p.adjusted.is_some() && p.is_emitter());
        assert_eq!(p.shininess, 64.0);
        let d = phong_of(&MtlMaterial::default());
        assert_eq!(
            (d.diffuse, d.specular, d.adjusted.clone()),
            (Vec3::splat(0.8), Vec3::ZERO, None)
        );
        assert!(!d.is_emitter());
    }
}
