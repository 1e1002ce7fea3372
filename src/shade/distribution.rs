//! Shading layer: a discrete distribution sampled by inverting its CDF. Used to pick a light
//! by power and a triangle of an area light by area, in O(log n) whatever the count.

/// Picks index `i` with probability `weights[i] / Σ weights`.
#[derive(Debug, Clone)]
pub struct Distribution1D {
    /// `cdf[i]` = Σ_{k<i} w_k / total; `cdf[0] = 0`, `cdf[n] = 1`.
    cdf: Vec<f32>,
    pmf: Vec<f32>,
    /// For tables of at least [`GUIDED_LEN`] entries, `len / 4` guides: entry `k` is the first
    /// index whose bucket ends past `k / guides` (a search then spans a few buckets).
    guide: Vec<u32>,
}

/// Tables this long get a guide.
const GUIDED_LEN: usize = 64;

/// A table weight as the samplers count it: itself when positive and finite, else 0 (a NaN or
/// negative texel must not break a table), in f64 for the sums.
pub fn clean_weight(w: f32) -> f64 {
    if w.is_finite() && w > 0.0 {
        w as f64
    } else {
        0.0
    }
}

impl Distribution1D {
    /// `None` when there is nothing to pick: no weights, or none positive and finite.
    pub fn new(weights: &[f32]) -> Option<Distribution1D> {
        let total: f64 = weights.iter().map(|&w| clean_weight(w)).sum();
        if total <= 0.0 {
            return None;
        }
        let mut cdf = Vec::with_capacity(weights.len() + 1);
        let mut acc = 0.0f64;
        cdf.push(0.0);
        for &w in weights {
            acc += clean_weight(w);
            cdf.push((acc / total) as f32);
        }
        if let Some(last) = cdf.last_mut() {
            *last = 1.0;
        }
        let pmf = weights
            .iter()
            .map(|&w| (clean_weight(w) / total) as f32)
            .collect();
        let n = weights.len();
        let guide = if n >= GUIDED_LEN {
            let g = n / 4;
            (0..=g)
                .map(|k| {
                    let threshold = k as f32 / g as f32;
                    cdf[1..].partition_point(|&c| c <= threshold).min(n - 1) as u32
                })
                .collect()
        } else {
            Vec::new()
        };
        Some(Distribution1D { cdf, pmf, guide })
    }

    /// Heap memory of the tables.
    pub fn bytes(&self) -> usize {
        (self.cdf.len() + self.pmf.len() + self.guide.len()) * std::mem::size_of::<f32>()
    }

    /// How many indices it picks from (zero-weight ones included).
    pub fn len(&self) -> usize {
        self.pmf.len()
    }

    /// Whether it has no index (never, for a table [`Distribution1D::new`] returned).
    pub fn is_empty(&self) -> bool {
        self.pmf.is_empty()
    }

    /// The first index whose bucket ends past `u`, searched between the guides of `u`'s
    /// bracket; `None` without guides, or when rounding put `u` outside its bracket (the caller
    /// then searches the whole table: the same answer either way).
    fn guided_search(&self, u: f32) -> Option<usize> {
        let g = self.guide.len().checked_sub(1).filter(|&g| g > 0)?;
        let k = ((u * g as f32) as usize).min(g - 1);
        let (lo, hi) = (self.guide[k] as usize, self.guide[k + 1] as usize);
        // The answer i satisfies cdf[i] <= u < cdf[i + 1]; check the bracket holds it.
        let inside = self.cdf[lo] <= u && u < self.cdf[(hi + 1).min(self.cdf.len() - 1)];
        inside.then(|| lo + self.cdf[lo + 1..=hi + 1].partition_point(|&c| c <= u))
    }

    /// The probability of picking `i` (0 outside the table).
    pub fn pmf(&self, i: usize) -> f32 {
        self.pmf.get(i).copied().unwrap_or(0.0)
    }

    /// For `u` in [0, 1): the index, its probability, and `u` rescaled to [0, 1) within the
    /// chosen bucket (so one random number can serve twice without losing stratification).
    pub fn sample(&self, u: f32) -> (usize, f32, f32) {
        // First i with cdf[i+1] > u, skipping zero-weight buckets.
        let n = self.pmf.len();
        let i = if n < GUIDED_LEN {
            // A short table: count the buckets that end at or before `u` (the same index as a
            // binary search of the monotone CDF, without its unpredictable branches).
            self.cdf[1..].iter().filter(|&&c| c <= u).count()
        } else {
            self.guided_search(u)
                .unwrap_or_else(|| self.cdf[1..].partition_point(|&c| c <= u))
        }
        .min(n - 1);
        let (lo, hi) = (self.cdf[i], self.cdf[i + 1]);
        let remapped = if hi > lo {
            ((u - lo) / (hi - lo)).clamp(0.0, 1.0 - f32::EPSILON / 2.0)
        } else {
            0.5
        };
        (i, self.pmf[i], remapped)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every `u` on a grid of `steps` picks what a binary search of the whole CDF picks, and
    /// never a zero weight.
    fn assert_picks_as_the_plain_search(weights: &[f32], steps: u32) {
        let d = Distribution1D::new(weights).expect("weights");
        for k in 0..=steps {
            let u = (k as f32 / steps as f32).min(1.0 - f32::EPSILON / 2.0);
            let plain = d.cdf[1..]
                .partition_point(|&c| c <= u)
                .min(weights.len() - 1);
            assert_eq!(d.sample(u).0, plain, "u = {u}");
            assert!(weights[plain] > 0.0, "u = {u} picked a zero weight");
        }
    }

    #[test]
    fn short_tables_count_to_the_plain_search() {
        let weights: Vec<f32> = (0..40).map(|i| [0.0, 1.0, 3.5, 0.25][i % 4]).collect();
        assert!(Distribution1D::new(&weights)
            .expect("weights")
            .guide
            .is_empty());
        assert_picks_as_the_plain_search(&weights, 10_000);
    }

    #[test]
    fn guided_search_is_the_plain_search() {
        // Zero runs, a spike and smooth weights: every u picks what a whole search picks.
        let weights: Vec<f32> = (0..1000)
            .map(|i| match i % 97 {
                0..=9 => 0.0,
                50 => 400.0,
                k => 1.0 + (k as f32 * 0.37).sin().abs(),
            })
            .collect();
        assert!(!Distribution1D::new(&weights)
            .expect("weights")
            .guide
            .is_empty());
        assert_picks_as_the_plain_search(&weights, 100_000);
    }

    #[test]
    fn empty_or_zero_weights_give_none() {
        assert!(Distribution1D::new(&[]).is_none());
        assert!(Distribution1D::new(&[0.0, f32::NAN, -1.0]).is_none());
    }

    #[test]
    fn frequencies_match_weights_and_zero_weights_are_never_picked() {
        let w = [1.0, 0.0, 3.0, 4.0];
        let d = Distribution1D::new(&w).expect("positive weights");
        let n = 8000;
        let mut counts = [0usize; 4];
        for k in 0..n {
            let (i, pmf, r) = d.sample((k as f32 + 0.5) / n as f32);
            assert!((0.0..1.0).contains(&r));
            assert_eq!(pmf, d.pmf(i));
            counts[i] += 1;
        }
        assert_eq!(counts[1], 0);
        for i in 0..4 {
            let expected = w[i] / 8.0 * n as f32;
            assert!((counts[i] as f32 - expected).abs() <= 1.0, "{counts:?}");
        }
        let sum: f32 = (0..4).map(|i| d.pmf(i)).sum();
        assert!((sum - 1.0).abs() < 1e-6);
    }
}
