//! The environment map: an equirectangular radiance image, its lookup and its importance
//! sampling (`light sky = environment { image("sky.hdr")  rotate 90deg }`; decoding the file is
//! the build's, `scene::env_load`).
//!
//! **Mapping convention** (the benchmark's, `shared/bench/scenes/gen.py` `sky()`): pixel
//! (`col`, `row`) of a `W × H` map covers `u = φ / 2π ∈ [col/W, (col+1)/W)` and
//! `θ = π·v ∈ [π·row/H, π·(row+1)/H)`, its centre at `θ = π·(row + 0.5)/H`, for the map-space
//! direction `(sin θ cos φ, cos θ, sin θ sin φ)`: row 0 is up (+y), `φ = 0` is +x and
//! `φ = π/2` is +z. `rotate a` turns the whole map by `a` radians about +y, right-handed (+z
//! towards +x): world direction `d` reads the map at `R_y(−a)·d`, so a feature at map azimuth
//! `φ` appears at world azimuth `φ − a`.
//!
//! **Lookup: nearest texel**, no filtering, so the piecewise-constant sampling distribution
//! matches the radiance exactly (a sampled direction's radiance is its texel's value).
//!
//! **Sampling**: texel weights are luminance × sin θ (row centre); a compact bright region that
//! holds much of the power (a sun) is taken apart (`env_bright`), and `env_sampler` turns the
//! rest into tables (cells of texels, and per normal bin the cells weighted towards that
//! hemisphere). Each gives `pdf_uv`, and `pdf_solid_angle = pdf_uv / (2π² sin θ)` (the Jacobian
//! of `(u, v) → ω`). The render draws one sample of each part ([`EnvMap::sample_sky_facing`],
//! [`EnvMap::sample_bright`], their densities from [`EnvMap::densities_facing`]);
//! [`EnvMap::sample_facing`] is their one-sample mixture (the bright part with its power
//! share), beside its [`EnvMap::pdf_facing`] (their `None`-normal forms, [`EnvMap::sample`] and
//! [`EnvMap::pdf`], sample by radiance alone). Tables are built only when the scene has
//! geometry to shade (`Environment::prepare_sampling`).

use std::f32::consts::PI;

use glam::{Vec2, Vec3};

use super::env_angles::TexelGrid;
use super::env_bright::BrightTexels;
use super::env_harmonics::SkyHarmonics;
use super::env_sampler::{EnvSampler, TexelSample};
use super::env_texels::Texels;
use super::env_vertical::vertical_irradiance;
use crate::shade::color::luminance;

/// Texels per side of the blocks [`EnvMap::sky_harmonics`] projects.
pub const HARMONICS_BLOCK: usize = 4;

/// An equirectangular radiance map (intensity already applied), row 0 at the top (+y).
#[derive(Debug, Clone)]
pub struct EnvMap {
    width: usize,
    height: usize,
    texels: Texels,
    cos_rot: f32,
    sin_rot: f32,
    /// The texel edges' sines and cosines (lookups and samples without libm trigonometry).
    grid: TexelGrid,
    /// Solid-angle-weighted mean radiance.
    average: Vec3,
    /// The sky's tables (without the bright texels, if any).
    distribution: Option<EnvSampler>,
    /// The few texels that hold most of the power, sampled on their own (`env_bright`).
    bright: Option<BrightTexels>,
    /// A cone (world space) that holds every direction of the bright set's box.
    bright_cone: Option<Cone>,
}

/// A cone of directions: its unit axis and the sine of its half-angle (the half-angle below
/// π/2).
#[derive(Debug, Clone, Copy)]
struct Cone {
    axis: Vec3,
    sin_half: f32,
    cos_half: f32,
}

impl Cone {
    /// A cone that holds every direction of the texels in the box of `cols × rows` texels from
    /// (`col0`, `row0`) of a `width × height` map, `direction(u, v)` mapping map points to world
    /// directions; `None` if it would be half the sphere or more.
    fn around_texels(
        (col0, row0, cols, rows): (usize, usize, usize, usize),
        (width, height): (usize, usize),
        direction: impl Fn(f32, f32) -> Vec3,
    ) -> Option<Cone> {
        let corner =
            |c: usize, r: usize| direction(c as f32 / width as f32, r as f32 / height as f32);
        let corners =
            || (row0..=row0 + rows).flat_map(move |r| (col0..=col0 + cols).map(move |c| (c, r)));
        let axis = corners()
            .map(|(c, r)| corner(c, r))
            .sum::<Vec3>()
            .try_normalize()?;
        let cos_corners = corners()
            .map(|(c, r)| axis.dot(corner(c, r)))
            .fold(1.0f32, f32::min)
            .clamp(-1.0, 1.0);
        // A point of a texel lies within the texel's diagonal of one of its corners (a row's
        // span is π/H, a column's 2π/W at most); twice that, and 1e-3 rad for rounding.
        let diagonal = (2.0 * PI / width as f32).hypot(PI / height as f32);
        let half = cos_corners.acos() + 2.0 * diagonal + 1e-3;
        (half < 0.5 * PI).then(|| Cone {
            axis,
            sin_half: half.sin(),
            cos_half: half.cos(),
        })
    }

    /// Whether unit direction `d` may lie in the cone (`false`: it surely does not).
    fn may_hold(&self, d: Vec3) -> bool {
        d.dot(self.axis) >= self.cos_half
    }

    /// Whether every direction `d` of the cone has `n · d < 0` (`n` unit).
    fn below_horizon_of(&self, n: Vec3) -> bool {
        n.dot(self.axis) < -self.sin_half
    }
}

/// A direction sampled from the environment.
#[derive(Debug, Clone, Copy)]
pub struct EnvSample {
    /// Unit world direction.
    pub wi: Vec3,
    /// Radiance arriving from `wi`.
    pub radiance: Vec3,
    /// Density over solid angle of the whole environment's sampling (all its parts).
    pub pdf_solid_angle: f32,
}

impl EnvMap {
    /// `texels.len()` must be `width · height` (checked: `None` otherwise); `texels` must be
    /// finite and non-negative (the image loader cleans them).
    pub fn new(
        width: usize,
        height: usize,
        texels: Vec<Vec3>,
        rotation_y_rad: f32,
    ) -> Option<EnvMap> {
        if width == 0 || height == 0 || texels.len() != width.checked_mul(height)? {
            return None;
        }
        let mut sum = glam::DVec3::ZERO;
        let mut weight = 0.0f64;
        for (row, line) in texels.chunks(width).enumerate() {
            let s = row_sin_theta(row, height) as f64;
            let row_sum: glam::DVec3 = line.iter().map(|t| t.as_dvec3()).sum();
            sum += row_sum * s;
            weight += s * width as f64;
        }
        Some(EnvMap {
            width,
            height,
            texels: Texels::new(texels),
            cos_rot: rotation_y_rad.cos(),
            sin_rot: rotation_y_rad.sin(),
            grid: TexelGrid::new(width, height),
            average: (sum / weight.max(f64::MIN_POSITIVE)).as_vec3(),
            distribution: None,
            bright: None,
            bright_cone: None,
        })
    }

    /// `(width, height)` in texels.
    pub fn size(&self) -> (usize, usize) {
        (self.width, self.height)
    }

    /// Solid-angle-weighted mean radiance.
    pub fn average(&self) -> Vec3 {
        self.average
    }

    /// Builds the sampling table (luminance × sin θ). Returns `false` (and builds nothing) when
    /// the map is black.
    pub fn build_distribution(&mut self) -> bool {
        let row_sines: Vec<f32> = (0..self.height)
            .map(|row| row_sin_theta(row, self.height))
            .collect();
        let mut weights: Vec<f32> = (0..self.texels.len())
            .map(|i| luminance(self.texels.get(i)) * row_sines[i / self.width])
            .collect();
        let (cos_rot, sin_rot) = (self.cos_rot, self.sin_rot);
        let to_world = |m: Vec3| {
            Vec3::new(
                cos_rot * m.x + sin_rot * m.z,
                m.y,
                -sin_rot * m.x + cos_rot * m.z,
            )
        };
        let direction = |u: f32, v: f32| {
            let (sin_theta, cos_theta) = (PI * v).sin_cos();
            let (sin_phi, cos_phi) = (2.0 * PI * u).sin_cos();
            to_world(Vec3::new(
                sin_theta * cos_phi,
                cos_theta,
                sin_theta * sin_phi,
            ))
        };
        self.bright = BrightTexels::find(self.width, self.height, &weights);
        self.bright_cone = self
            .bright
            .as_ref()
            .and_then(|b| Cone::around_texels(b.texel_box(), (self.width, self.height), direction));
        if let Some(b) = &self.bright {
            for (i, w) in weights.iter_mut().enumerate() {
                if b.contains(i % self.width, i / self.width) {
                    *w = 0.0;
                }
            }
        }
        self.distribution = EnvSampler::new(self.width, self.height, &weights, direction);
        self.has_distribution()
    }

    /// The map's sky, its bright set left out (that is sampled on its own), projected onto
    /// spherical harmonics in world space (`env_harmonics`). The quadrature takes blocks of up
    /// to [`HARMONICS_BLOCK`]² texels: their radiance summed over the texels' exact solid
    /// angles, the basis read at the block's centre. The fit only needs to be close to the sky
    /// (the render's estimate is unbiased for any coefficients), and the blocks keep this
    /// build step to a few milliseconds.
    pub fn sky_harmonics(&self) -> Option<SkyHarmonics> {
        let (w, h) = (self.width, self.height);
        let b = HARMONICS_BLOCK;
        let row_edges: Vec<f64> = (0..=h)
            .map(|r| (std::f64::consts::PI * r as f64 / h as f64).cos())
            .collect();
        let col_span = std::f64::consts::TAU / w as f64;
        let blocks = (0..h.div_ceil(b)).flat_map(|by| (0..w.div_ceil(b)).map(move |bx| (bx, by)));
        let points = blocks.map(|(bx, by)| {
            let (c0, c1) = (bx * b, ((bx + 1) * b).min(w));
            let (r0, r1) = (by * b, ((by + 1) * b).min(h));
            let mut sum = glam::DVec3::ZERO;
            for row in r0..r1 {
                let solid_angle = col_span * (row_edges[row] - row_edges[row + 1]);
                for col in c0..c1 {
                    if !self.bright.as_ref().is_some_and(|t| t.contains(col, row)) {
                        sum += self.texels.get(row * w + col).as_dvec3() * solid_angle;
                    }
                }
            }
            let solid_angle = col_span * (c1 - c0) as f64 * (row_edges[r0] - row_edges[r1]);
            let theta = std::f64::consts::PI * (r0 + r1) as f64 / (2 * h) as f64;
            let phi = std::f64::consts::PI * (c0 + c1) as f64 / w as f64;
            let m = glam::DVec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            );
            let radiance = (sum / solid_angle.max(f64::MIN_POSITIVE)).as_vec3();
            (
                self.to_world(m.as_vec3()).normalize(),
                radiance,
                solid_angle,
            )
        });
        SkyHarmonics::project(&points.collect::<Vec<_>>())
    }

    /// The sky's exact cosine-weighted integral for the normals `+y` and `−y`, the bright set
    /// left out (`env_vertical`).
    pub fn vertical_irradiance(&self) -> [Vec3; 2] {
        let bright = |col, row| self.bright.as_ref().is_some_and(|b| b.contains(col, row));
        let texel = |col, row| (!bright(col, row)).then(|| self.texels.get(row * self.width + col));
        vertical_irradiance(self.width, self.height, texel)
    }

    /// The radiance from direction `d` (unit) with the bright set left out: the nearest
    /// texel's, or zero if that texel is in the set.
    pub fn radiance_apart_from_bright(&self, d: Vec3) -> Vec3 {
        let (col, row, _) = self.texel_of(d);
        let in_set = || self.bright.as_ref().is_some_and(|b| b.contains(col, row));
        if self.may_be_bright(d) && in_set() {
            Vec3::ZERO
        } else {
            self.texels.get(row * self.width + col)
        }
    }

    /// Whether the sampling table was built.
    pub fn has_distribution(&self) -> bool {
        self.distribution.is_some() || self.bright.is_some()
    }

    /// How many normal bins' tables the renders so far have built (they are built on first
    /// use: `env_sampler`); 0 without a table.
    pub fn normal_bins_built(&self) -> usize {
        self.distribution
            .as_ref()
            .map_or(0, EnvSampler::normal_bins_built)
    }

    /// Whether the map has a bright set sampled on its own ([`EnvMap::sample_bright`]).
    pub fn has_bright(&self) -> bool {
        self.bright.is_some()
    }

    /// Whether every direction of the bright set lies below the horizon of unit `n` (then no
    /// sample of it can light a surface facing `n`): `false` when unsure or without a set.
    pub fn bright_below_horizon_of(&self, n: Vec3) -> bool {
        self.bright_cone.is_some_and(|c| c.below_horizon_of(n))
    }

    /// The probability with which [`EnvMap::sample_facing`] takes the bright set: its share of
    /// the power (1 when nothing else is lit, 0 without a set).
    fn bright_fraction(&self) -> f32 {
        match (&self.bright, &self.distribution) {
            (None, _) => 0.0,
            (Some(_), None) => 1.0,
            (Some(b), Some(_)) => b.share(),
        }
    }

    /// Heap memory of the texels and of the importance table (if built).
    pub fn bytes(&self) -> (usize, usize) {
        (
            self.texels.bytes(),
            self.distribution.as_ref().map_or(0, EnvSampler::bytes)
                + self.bright.as_ref().map_or(0, BrightTexels::bytes),
        )
    }

    fn to_map(&self, d: Vec3) -> Vec3 {
        // R_y(−a)·d.
        Vec3::new(
            self.cos_rot * d.x - self.sin_rot * d.z,
            d.y,
            self.sin_rot * d.x + self.cos_rot * d.z,
        )
    }

    fn to_world(&self, m: Vec3) -> Vec3 {
        // R_y(a)·m.
        Vec3::new(
            self.cos_rot * m.x + self.sin_rot * m.z,
            m.y,
            -self.sin_rot * m.x + self.cos_rot * m.z,
        )
    }

    /// The texel (`col`, `row`) world direction `d` (unit) reads, and the map-space sin θ.
    pub fn texel_of(&self, d: Vec3) -> (usize, usize, f32) {
        self.grid.texel_of(self.to_map(d))
    }

    /// Radiance arriving from world direction `d` (unit): the nearest texel.
    pub fn radiance(&self, d: Vec3) -> Vec3 {
        let (col, row, _) = self.texel_of(d);
        self.texels.get(row * self.width + col)
    }

    /// A direction by the table (`None` without one, or at a pole where the density is
    /// singular): world direction, its texel's radiance and `pdf_solid_angle` of the map alone.
    pub fn sample(&self, u: Vec2) -> Option<EnvSample> {
        self.sample_facing(u, None)
    }

    /// [`EnvMap::sample`] for a surface facing unit `normal` (`None`: by radiance alone): the
    /// bright set with its share of the power (`u.y` below it), else the map's cells weighted
    /// towards the normal's hemisphere (see `env_sampler`). The render draws the two parts
    /// apart ([`EnvMap::sample_sky_facing`], [`EnvMap::sample_bright`]); this one-sample mixture
    /// is the map's whole distribution.
    pub fn sample_facing(&self, u: Vec2, normal: Option<Vec3>) -> Option<EnvSample> {
        let q = self.bright_fraction();
        if q == 0.0 {
            return self.sample_sky_facing(u, normal);
        }
        let mut s = if u.y < q {
            let v = (u.y / q).min(1.0 - f32::EPSILON / 2.0);
            self.bright.as_ref()?.sample(Vec2::new(u.x, v))?
        } else {
            let v = ((u.y - q) / (1.0 - q)).clamp(0.0, 1.0 - f32::EPSILON / 2.0);
            self.distribution
                .as_ref()?
                .sample(Vec2::new(u.x, v), normal)?
        };
        // The mixture's density at the drawn texel (each part's is 0 on the other's texels).
        let bright = self.bright.as_ref().map_or(0.0, |b| b.pdf_uv(s.col, s.row));
        let sky = self
            .distribution
            .as_ref()
            .map_or(0.0, |t| t.pdf_uv(s.col, s.row, normal));
        s.pdf_uv = q * bright + (1.0 - q) * sky;
        self.texel_sample(s)
    }

    /// A direction from the sky's tables alone (the bright set left out): `pdf_solid_angle` is
    /// that strategy's density ([`EnvMap::densities_facing`]'s first).
    pub fn sample_sky_facing(&self, u: Vec2, normal: Option<Vec3>) -> Option<EnvSample> {
        let s = self.distribution.as_ref()?.sample(u, normal)?;
        self.texel_sample(s)
    }

    /// A direction in one of the bright texels: `pdf_solid_angle` is that strategy's density
    /// ([`EnvMap::densities_facing`]'s second).
    pub fn sample_bright(&self, u: Vec2) -> Option<EnvSample> {
        let s = self.bright.as_ref()?.sample(u)?;
        self.texel_sample(s)
    }

    /// The world direction of a drawn point of the map, its texel's radiance and its density.
    fn texel_sample(&self, s: TexelSample) -> Option<EnvSample> {
        if s.pdf_uv <= 0.0 {
            return None;
        }
        // The point's place inside its texel.
        let fx = (s.uv.x * self.width as f32 - s.col as f32).clamp(0.0, 1.0);
        let fy = (s.uv.y * self.height as f32 - s.row as f32).clamp(0.0, 1.0);
        let m = self.grid.direction(s.col, s.row, fx, fy);
        if m.y.abs() >= 1.0 {
            return None;
        }
        let wi = self.to_world(m).normalize();
        // The Jacobian's sin θ as `pdf_facing` computes it from the direction (`texel_of`), so
        // that both strategies of multiple importance sampling read one density function (near
        // the poles, f32's sin θ from θ and from cos θ differ by up to a percent).
        let cos_back = self.to_map(wi).y.clamp(-1.0, 1.0);
        let sin_back = (1.0 - cos_back * cos_back).max(0.0).sqrt();
        if sin_back <= 0.0 {
            return None;
        }
        Some(EnvSample {
            wi,
            radiance: self.texels.get(s.row * self.width + s.col),
            pdf_solid_angle: s.pdf_uv / (2.0 * PI * PI * sin_back),
        })
    }

    /// The solid-angle density with which [`EnvMap::sample`] produces direction `d` (unit).
    pub fn pdf(&self, d: Vec3) -> f32 {
        self.pdf_facing(d, None)
    }

    /// The density of [`EnvMap::sample_facing`] for the same `normal`.
    pub fn pdf_facing(&self, d: Vec3, normal: Option<Vec3>) -> f32 {
        self.radiance_and_pdf_facing(d, normal).1
    }

    /// [`EnvMap::radiance`] and [`EnvMap::pdf_facing`] of one direction, finding its texel once.
    pub fn radiance_and_pdf_facing(&self, d: Vec3, normal: Option<Vec3>) -> (Vec3, f32) {
        let (radiance, sky, bright) = self.densities_facing(d, normal);
        let q = self.bright_fraction();
        (radiance, q * bright + (1.0 - q) * sky)
    }

    /// [`EnvMap::radiance`] of direction `d` (unit), and the solid-angle densities of
    /// [`EnvMap::sample_sky_facing`] and [`EnvMap::sample_bright`] there, finding its texel once.
    pub fn densities_facing(&self, d: Vec3, normal: Option<Vec3>) -> (Vec3, f32, f32) {
        let (col, row, jacobian, radiance) = self.texel_towards(d);
        if jacobian <= 0.0 {
            return (radiance, 0.0, 0.0);
        }
        let sky = self
            .distribution
            .as_ref()
            .map_or(0.0, |t| t.pdf_uv(col, row, normal));
        let bright = self.bright.as_ref().map_or(0.0, |b| b.pdf_uv(col, row));
        (radiance, sky / jacobian, bright / jacobian)
    }

    /// [`EnvMap::densities_facing`] without the sky's density (whose tables are the costly
    /// part): the radiance from direction `d` (unit) and the density of
    /// [`EnvMap::sample_bright`] there.
    pub fn radiance_and_bright_density(&self, d: Vec3) -> (Vec3, f32) {
        let (col, row, jacobian, radiance) = self.texel_towards(d);
        match &self.bright {
            Some(b) if jacobian > 0.0 && self.may_be_bright(d) => {
                (radiance, b.pdf_uv(col, row) / jacobian)
            }
            _ => (radiance, 0.0),
        }
    }

    /// The density of [`EnvMap::sample_bright`] at direction `d` (unit), without its radiance:
    /// outside the bright set's cone no texel is looked up (most directions).
    pub fn bright_density(&self, d: Vec3) -> f32 {
        let Some(b) = self.bright.as_ref().filter(|_| self.may_be_bright(d)) else {
            return 0.0;
        };
        let (col, row, sin_theta) = self.texel_of(d);
        let jacobian = 2.0 * PI * PI * sin_theta.max(0.0);
        if jacobian > 0.0 {
            b.pdf_uv(col, row) / jacobian
        } else {
            0.0
        }
    }

    /// Whether unit direction `d` may read a texel of the bright set: `false` only when it
    /// lies outside the set's cone (which holds every direction of the set's box).
    pub fn may_be_bright(&self, d: Vec3) -> bool {
        self.bright_cone.is_none_or(|c| c.may_hold(d))
    }

    /// The texel world direction `d` (unit) reads, the Jacobian `2π² sin θ` from the map's
    /// unit square to solid angle there (0 at a pole), and the texel's radiance.
    fn texel_towards(&self, d: Vec3) -> (usize, usize, f32, Vec3) {
        let (col, row, sin_theta) = self.texel_of(d);
        let radiance = self.texels.get(row * self.width + col);
        (col, row, 2.0 * PI * PI * sin_theta.max(0.0), radiance)
    }
}

fn row_sin_theta(row: usize, height: usize) -> f32 {
    (PI * (row as f32 + 0.5) / height as f32).sin()
}
