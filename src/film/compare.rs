//! Stage 5, film: error of a film against a reference (`scnc bench quality`), on linear
//! radiance: RMSE over every channel of every pixel, and relative MSE
//! `mean((x − r)² / (r² + ε))` with ε = [`REL_EPSILON`] (a radiance floor of 0.01, so that
//! black reference pixels do not divide by zero).

use super::Film;

/// ε of the relative MSE: (0.01)².
pub const REL_EPSILON: f64 = 1e-4;

/// Error of one film against the reference.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FilmError {
    /// Root mean square error over pixels and channels.
    pub rmse: f64,
    /// Mean of (error² / (reference² + ε)): relative MSE, robust to black pixels.
    pub rel_mse: f64,
}

impl FilmError {
    /// √relMSE: the relative RMS error ("1% relative error" is 0.01).
    pub fn rel_rms(&self) -> f64 {
        self.rel_mse.sqrt()
    }
}

/// `None` when the sizes differ.
pub fn compare(film: &Film, reference: &Film) -> Option<FilmError> {
    if (film.width(), film.height()) != (reference.width(), reference.height()) {
        return None;
    }
    let (mut se, mut rel) = (0.0f64, 0.0f64);
    for (x, r) in film.pixels().iter().zip(reference.pixels()) {
        for c in 0..3 {
            let (x, r) = (x[c] as f64, r[c] as f64);
            let d2 = (x - r) * (x - r);
            se += d2;
            rel += d2 / (r * r + REL_EPSILON);
        }
    }
    let n = (film.pixels().len() * 3).max(1) as f64;
    Some(FilmError {
        rmse: (se / n).sqrt(),
        rel_mse: rel / n,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn errors_of_a_known_difference() {
        let mut a = Film::new(2, 1);
        let mut r = Film::new(2, 1);
        r.set(0, 0, Vec3::splat(1.0));
        r.set(1, 0, Vec3::splat(1.0));
        a.set(0, 0, Vec3::splat(1.1));
        a.set(1, 0, Vec3::splat(1.0));
        let e = compare(&a, &r).expect("same size");
        // Half the values off by 0.1: MSE 0.005.
        assert!((e.rmse - 0.005f64.sqrt()).abs() < 1e-6, "{e:?}");
        assert!((e.rel_mse - 0.005 / (1.0 + REL_EPSILON)).abs() < 1e-6);
        assert_eq!(compare(&a, &a).map(|e| e.rmse), Some(0.0));
        assert!(compare(&a, &Film::new(1, 1)).is_none());
    }
}
