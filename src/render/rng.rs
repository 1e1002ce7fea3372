//! Stage 4: deterministic random numbers. Each value is a pure hash of (seed, pixel, sample
//! index, dimension): never of the thread, the tile order or the time, so renders are
//! bit-identical whatever the thread count (`render { seed 0 }` changes every value).
//!
//! [`Sampler::point_2d`]: per-stream Owen-scrambled Sobol' (0,2)-sequences per pixel
//! (`render::owen_sobol`), whose point `j` does not depend on the pixel's sample count. Adaptive renders
//! use them ([`PixelSequences`]: a few independently scrambled replicates, each continued from
//! batch to batch); fixed-count renders keep the Hammersley sets above, which measured as good
//! for a known count (docs/speed.md), each stream visiting its set in its own per-pixel order
//! ([`permute_index`]): before that, sample `s`'s sub-pixel position, light pick and light
//! point all took index `s`, so a penumbra pixel converged to a seed-dependent value
//! (docs/quality.md, "The references are progressive renders").
//!
//! This lives in `render/`, not in `shade::sampling`: it is the render loop's sample sequence
//! (which pixel, which sample, which stratum of the pixel's set), while the shading layer only
//! maps the numbers it is handed (`u ∈ [0, 1)²`) to directions and points, whatever produced them.

use std::cell::OnceCell;

use glam::Vec2;

use super::integrator::STREAM_LIGHTS;
use super::owen_sobol::{points_side_by_side, OwenSobol};

/// The samplers of one batch of one pixel: what their keys share is hashed once per pixel, not
/// once per sample (the same values as [`Sampler::for_batch_sample`], bit for bit).
#[derive(Debug, Clone, Copy)]
pub struct PixelBatch {
    pixel_hash: u64,
    pixel_key: u64,
    batch: u32,
    count: u32,
    /// The first streams' keys, derived once for all the batch's samples.
    streams: [StreamKey; CACHED_STREAMS],
}

/// What [`Sampler::stratified_2d`] derives from the pixel's key for one stream (the same for
/// every sample of the pixel): the stream's random bits (shift and scramble) and the key of
/// the order in which the samples visit its points.
#[derive(Debug, Clone, Copy, Default)]
struct StreamKey {
    bits: u64,
    order: u32,
}

impl StreamKey {
    #[inline]
    fn of(pixel_key: u64, stream: u64) -> StreamKey {
        let bits = mix64(pixel_key ^ stream.wrapping_mul(0x9e37_79b9_7f4a_7c15));
        StreamKey {
            bits,
            order: mix64(bits ^ 0x7f4a_7c15_9e37_79b9) as u32,
        }
    }

    /// Point `j` of the stream's set of `n` ([`Sampler::stratified_2d`]).
    #[inline(always)]
    fn point(self, j: u32, n: u32) -> Vec2 {
        // Each stream visits the set in its own order: without it, sample `s` would take
        // point `s` of every stream, so its light point would be a fixed function of its
        // sub-pixel position (and of its light pick), and a penumbra pixel would converge to a
        // seed-dependent value instead of the pixel's integral (pbrt-v4's padded sampler
        // permutes each dimension's index the same way).
        self.at(permute_index(j, n, self.order), n)
    }

    /// Point `j` of the set of `n` in the stream's own order (`j` permuted already).
    #[inline(always)]
    fn at(self, j: u32, n: u32) -> Vec2 {
        let shift = to_unit(self.bits);
        let x = wrap_unit(stratum_centre(j, n) + shift);
        // The shift uses the top 24 bits, the scramble the low 32: independent.
        let y = ((j.reverse_bits() ^ self.bits as u32) >> 8) as f32 * (1.0 / (1u32 << 24) as f32);
        Vec2::new(x, y)
    }

    /// The keys of streams `0..CACHED_STREAMS`.
    fn first(pixel_key: u64) -> [StreamKey; CACHED_STREAMS] {
        std::array::from_fn(|s| StreamKey::of(pixel_key, s as u64))
    }
}

/// Streams `0..CACHED_STREAMS` (the integrator's light pick, environment, BRDF directions and
/// first light: `render::integrator`'s `STREAM_*`) have their keys derived once per pixel
/// rather than once per sample: two 64-bit hashes off every sample's light sample.
const CACHED_STREAMS: usize = 4;

impl PixelBatch {
    /// Batch `batch` of `count` samples of pixel (`px`, `py`).
    pub fn new(seed: u64, px: u32, py: u32, batch: u32, count: u32) -> PixelBatch {
        let pixel_hash = pixel_hash(seed, px, py);
        let pixel_key = mix64(key_of(pixel_hash, u32::MAX - batch) ^ 0x5851_f42d_4c95_7f2d);
        PixelBatch {
            pixel_hash,
            pixel_key,
            batch,
            count: count.max(1),
            streams: StreamKey::first(pixel_key),
        }
    }

    /// [`Sampler::pixel_bits`] of the batch's samplers (the same for all of them).
    pub fn pixel_bits(&self, dim: u64) -> u64 {
        pixel_bits(self.pixel_key, dim)
    }

    /// Points `j0, j0 + 1, …` of stream `stream`'s set of `n` (as many as `out` holds): what
    /// the batch's samplers' [`Sampler::stratified_2d`]`(stream, j, n)` give, the stream's key
    /// derived once, and the points of a power-of-two set computed side by side.
    #[inline(always)]
    pub fn stratified_run(&self, stream: u64, j0: u32, n: u32, out: &mut [Vec2]) {
        let key = stream_key(&self.streams, self.pixel_key, stream);
        let n1 = n.max(1);
        if n1.is_power_of_two() {
            let w = n1 - 1;
            for (j, p) in (j0..).zip(out.iter_mut()) {
                *p = key.at(
                    permute_round(j, w, key.order).wrapping_add(key.order) & w,
                    n,
                );
            }
        } else {
            // Past the set's end (a caller's fixed-length run past its last sample) the index
            // wraps: the cycle walk of `permute_index` only ends for indices inside the set.
            for (j, p) in (j0..).zip(out.iter_mut()) {
                *p = key.point(if j < n1 { j } else { j % n1 }, n);
            }
        }
    }

    /// The sampler of sample `index` of the batch.
    #[inline]
    pub fn sampler(&self, index: u32) -> Sampler {
        let global = self.batch.wrapping_mul(self.count).wrapping_add(index);
        Sampler {
            key: key_of(self.pixel_hash, global),
            dim: 0,
            pixel_key: self.pixel_key,
            index: index.min(self.count - 1),
            count: self.count,
            progressive: false,
            streams: self.streams,
        }
    }
}

/// Progressive sequences of one pixel for adaptive sampling. The first [`SHARED_ROUNDS`] round
/// (samples `g < REPLICATES`) is points `0..REPLICATES` of one Owen-scrambled Sobol' sequence of
/// the pixel, so its first 2 and 4 samples are (0,m,2)-nets in every stream, as good as a
/// fixed-count render's (independent first samples left flat walls with 1.5× the error); those
/// samples are in the pixel's mean but in no replicate ([`PixelSequences::replicate`]). After
/// it, sample `g` belongs to replicate `g mod REPLICATES` and is point `g / REPLICATES − 1` of
/// that replicate's own sequences ([`Sampler::point_2d`]), so each replicate's samples are one
/// low-discrepancy set however many batches the pixel takes (the sequence continues instead of
/// restarting; each batch of 16 adds a whole 4-point block to each replicate), while the
/// replicates, scrambled independently, give independent estimates whose spread measures the
/// error.
#[derive(Debug, Clone)]
pub struct PixelSequences {
    pixel_hash: u64,
    /// The replicates' scrambles, derived at the first sample past the shared rounds: most
    /// pixels of a loose target stop within them (two 64-bit hashes per replicate saved).
    replicate_keys: OnceCell<[u64; REPLICATES as usize]>,
    /// The scramble of the shared rounds' sequence (samples `0..SHARED_ROUNDS·REPLICATES`).
    shared_key: u64,
    /// The scrambles of the [`CACHED_POINT_STREAMS`] (by stream) of the shared rounds'
    /// sequence, and of the replicates' (by stream, then replicate), each set derived at its
    /// first point and kept for the pixel's later runs: before, each run of up to 8 samples
    /// derived them again (two 64-bit hashes a sequence and stream, 5.7% of an adaptive profile
    /// with the points themselves, docs/quality.md, thirteenth session). One cell a set, so a
    /// run of 8 reads one cell, not four a stream (docs/quality.md, twentieth session).
    shared_scrambles: OnceCell<[OwenSobol; CACHED_POINT_STREAMS.len()]>,
    replicate_scrambles: OnceCell<[[OwenSobol; REPLICATES as usize]; CACHED_POINT_STREAMS.len()]>,
}

/// The streams whose points [`PixelSequences::points_2d`] takes run after run (the sub-pixel
/// position, and the light point of `render::rect_lit`): their scrambles are kept per pixel.
const CACHED_POINT_STREAMS: [u64; 2] = [STREAM_SUBPIXEL, STREAM_LIGHTS];

/// Independent replicates of an adaptive pixel's samples.
pub const REPLICATES: u32 = 4;
/// Rounds (one sample per replicate each) at the start of an adaptive pixel that are one
/// stratified set of the pixel's rather than points of the replicates' own sequences.
pub const SHARED_ROUNDS: u32 = 1;

impl PixelSequences {
    /// The sequences of pixel (`px`, `py`).
    pub fn new(seed: u64, px: u32, py: u32) -> PixelSequences {
        let pixel_hash = pixel_hash(seed, px, py);
        PixelSequences {
            pixel_hash,
            replicate_keys: OnceCell::new(),
            shared_key: mix64(key_of(pixel_hash, u32::MAX - REPLICATES) ^ 0x2f1d_83a5_c3b9_0e47),
            shared_scrambles: OnceCell::new(),
            replicate_scrambles: OnceCell::new(),
        }
    }

    /// The replicates' scrambles.
    fn replicate_keys(&self) -> &[u64; REPLICATES as usize] {
        self.replicate_keys.get_or_init(|| {
            std::array::from_fn(|r| {
                mix64(key_of(self.pixel_hash, u32::MAX - r as u32) ^ 0x2f1d_83a5_c3b9_0e47)
            })
        })
    }

    /// The sampler of the pixel's sample `global` (counted over all its batches).
    #[inline]
    pub fn sampler(&self, global: u32) -> Sampler {
        let (_, pixel_key, index) = self.sequence_of(global);
        Sampler {
            key: key_of(self.pixel_hash, global),
            dim: 0,
            pixel_key,
            index,
            count: 0,
            progressive: true,
            // Progressive points (`point_2d`) do not read them.
            streams: [StreamKey::default(); CACHED_STREAMS],
        }
    }

    /// Stream `stream`'s points of samples `samples` into `out` (as many as both hold), each
    /// exactly `self.sampler(g).point_2d(stream, index)` for its sample `g`. The scramble of
    /// each sequence is derived once for the pixel (the [`CACHED_POINT_STREAMS`]) or for the
    /// run of samples (any other stream), not once per sample; the points of up to eight
    /// samples are computed side by side (`owen_sobol::points_side_by_side`, vectorised where
    /// this is inlined into `render::rect_lit`'s AVX2 kernel); and the
    /// points are taken apart from the rays that use them: the adaptive pixel loop takes its
    /// sub-pixel positions so, so that a sample's camera ray does not wait on the chain of
    /// hashes behind its position (the adaptive path's own work was about 9% of a sample's
    /// cost, this point about a third of it: docs/quality.md, sixth session).
    #[inline(always)]
    pub fn points_2d(&self, stream: u64, samples: std::ops::Range<u32>, out: &mut [Vec2]) {
        let cached = CACHED_POINT_STREAMS.iter().position(|&s| s == stream);
        let mut uncached = [None::<OwenSobol>; REPLICATES as usize + 1];
        let scramble = |slot: usize| OwenSobol::of(self.key_of_slot(slot), stream);
        let mut scramble_of = |slot: usize| match cached {
            Some(c) => self.cached_scrambles(slot)[c],
            None => *uncached[slot].get_or_insert_with(|| scramble(slot)),
        };
        // Eight at a time side by side (`owen_sobol::points_side_by_side`); lanes past the
        // samples repeat the first (computed, not read).
        const LANES: usize = 8;
        const SLOTS: usize = REPLICATES as usize + 1;
        let mut next = samples.start;
        for out in out.chunks_mut(LANES) {
            let len = (samples.end.saturating_sub(next) as usize).min(out.len());
            if len == 0 {
                break;
            }
            let mut points = [Vec2::ZERO; LANES];
            if len == LANES && next.is_multiple_of(REPLICATES) && next >= SHARED_ROUNDS * REPLICATES
            {
                // A whole run of replicates' samples from a round's start (every run of a
                // batch of 16): lane `k` is replicate `k mod REPLICATES`'s point of round
                // `k / REPLICATES`, as `slot_of` says, without its division and the table's
                // gather per lane.
                let round = next / REPLICATES - SHARED_ROUNDS;
                let each = match cached {
                    Some(c) => self.replicate_scrambles()[c],
                    None => std::array::from_fn(&mut scramble_of),
                };
                let scrambles = std::array::from_fn(|k| each[k % REPLICATES as usize]);
                let indices = std::array::from_fn(|k| round + k as u32 / REPLICATES);
                points_side_by_side(&scrambles, &indices, &mut points);
                out.copy_from_slice(&points);
                next += LANES as u32;
                continue;
            }
            // Each sequence the run touches resolved once (its cell read, its key derived
            // only if the cell is empty), then handed to its lanes: not a cell and a key per
            // lane.
            let mut slots = [0usize; LANES];
            let mut indices = [0u32; LANES];
            let mut used = [false; SLOTS];
            for k in 0..LANES {
                let g = next + if k < len { k as u32 } else { 0 };
                let (slot, index) = Self::slot_of(g);
                (slots[k], indices[k]) = (slot, index);
                used[slot] = true;
            }
            let mut table = [OwenSobol::default(); SLOTS];
            for (slot, scramble) in table.iter_mut().enumerate() {
                if used[slot] {
                    *scramble = scramble_of(slot);
                }
            }
            let scrambles: [OwenSobol; LANES] = std::array::from_fn(|k| table[slots[k]]);
            points_side_by_side(&scrambles, &indices, &mut points);
            out[..len].copy_from_slice(&points[..len]);
            next += len as u32;
        }
    }

    /// Sample `global`'s lane of a run gathered from several pixels ([`RunLanes::set`]): its
    /// index in its sequence and that sequence's scrambles of the [`CACHED_POINT_STREAMS`],
    /// kept for the pixel's later runs as [`PixelSequences::points_2d`] keeps them.
    #[inline(always)]
    fn lane(&self, global: u32) -> (u32, [OwenSobol; CACHED_POINT_STREAMS.len()]) {
        let (slot, index) = Self::slot_of(global);
        (index, self.cached_scrambles(slot))
    }

    /// The scrambles of the [`CACHED_POINT_STREAMS`] of the sequence in `slot`.
    #[inline(always)]
    fn cached_scrambles(&self, slot: usize) -> [OwenSobol; CACHED_POINT_STREAMS.len()] {
        if slot == REPLICATES as usize {
            *self.shared_scrambles.get_or_init(|| {
                CACHED_POINT_STREAMS.map(|stream| OwenSobol::of(self.shared_key, stream))
            })
        } else {
            let replicates = self.replicate_scrambles();
            std::array::from_fn(|c| replicates[c][slot])
        }
    }

    /// The replicates' scrambles of the [`CACHED_POINT_STREAMS`] (by stream, then replicate).
    #[inline(always)]
    fn replicate_scrambles(
        &self,
    ) -> &[[OwenSobol; REPLICATES as usize]; CACHED_POINT_STREAMS.len()] {
        self.replicate_scrambles.get_or_init(|| {
            let keys = self.replicate_keys();
            CACHED_POINT_STREAMS.map(|stream| keys.map(|key| OwenSobol::of(key, stream)))
        })
    }

    /// Sample `global`'s slot among the replicates' sequences and the shared one's, and its
    /// index in that sequence.
    #[inline]
    fn slot_of(global: u32) -> (usize, u32) {
        let r = (global % REPLICATES) as usize;
        match global / REPLICATES {
            round if round < SHARED_ROUNDS => (REPLICATES as usize, global),
            round => (r, round - SHARED_ROUNDS),
        }
    }

    /// The key of the sequence in `slot` ([`PixelSequences::slot_of`]).
    #[inline]
    fn key_of_slot(&self, slot: usize) -> u64 {
        // The replicates' keys only for their own slots: the shared round never derives them.
        if slot == REPLICATES as usize {
            self.shared_key
        } else {
            self.replicate_keys()[slot]
        }
    }

    /// Sample `global`'s sequence (a slot for it among the replicates' and the shared one's,
    /// its key) and its index in that sequence.
    #[inline]
    fn sequence_of(&self, global: u32) -> (usize, u64, u32) {
        let (slot, index) = Self::slot_of(global);
        (slot, self.key_of_slot(slot), index)
    }

    /// The replicate sample `global` belongs to; `None` for the shared rounds' samples, which
    /// are in the pixel's mean but in no replicate.
    #[inline]
    pub fn replicate(global: u32) -> Option<usize> {
        (global >= SHARED_ROUNDS * REPLICATES).then_some((global % REPLICATES) as usize)
    }
}

/// The lanes of a run whose samples come from several pixels' sequences (`render::rect_lit`'s
/// side-by-side runs: an adaptive render's batches of 2 samples, four pixels a run): each
/// lane's sequence and index, so that the run's points of a stream are one eight-lane
/// computation (`owen_sobol::points_side_by_side`) where each pixel's
/// [`PixelSequences::points_2d`] computed eight lanes for its two, four times a run
/// (docs/quality.md, twentieth session). Lane `k`'s point is
/// `sequences.points_2d(stream, g..g + 1)`'s, bit for bit.
#[derive(Debug, Clone, Copy, Default)]
pub struct RunLanes {
    index: [u32; RUN_LANES],
    /// By stream (in the order of [`CACHED_POINT_STREAMS`]), then lane.
    scrambles: [[OwenSobol; RUN_LANES]; CACHED_POINT_STREAMS.len()],
}

/// The lanes of a [`RunLanes`] (`shade::light::rect_lanes::LANES`).
const RUN_LANES: usize = 8;

impl RunLanes {
    /// Lane `k` takes sample `global` of the pixel of `sequences`.
    #[inline(always)]
    pub fn set(&mut self, k: usize, sequences: &PixelSequences, global: u32) {
        let (index, scrambles) = sequences.lane(global);
        self.index[k] = index;
        for (lanes, scramble) in self.scrambles.iter_mut().zip(scrambles) {
            lanes[k] = scramble;
        }
    }

    /// Stream `stream`'s points of the lanes (one of the [`CACHED_POINT_STREAMS`]: the
    /// sub-pixel position or the light point). Lanes never [`RunLanes::set`] give some point
    /// (computed, not meant to be read).
    #[inline(always)]
    pub fn points_2d(&self, stream: u64, out: &mut [Vec2; RUN_LANES]) {
        let c = CACHED_POINT_STREAMS.iter().position(|&s| s == stream);
        debug_assert!(c.is_some(), "stream {stream} is not one of a run's");
        let scrambles = &self.scrambles[c.unwrap_or(0)];
        points_side_by_side(scrambles, &self.index, out);
    }
}

/// The key of stream `stream` of a pixel whose first streams' keys are `cached`.
#[inline(always)]
fn stream_key(cached: &[StreamKey; CACHED_STREAMS], pixel_key: u64, stream: u64) -> StreamKey {
    match cached.get(stream as usize) {
        Some(&key) if stream < CACHED_STREAMS as u64 => key,
        _ => StreamKey::of(pixel_key, stream),
    }
}

/// [`Sampler::pixel_bits`] of a pixel key.
fn pixel_bits(pixel_key: u64, dim: u64) -> u64 {
    mix64(pixel_key ^ dim.wrapping_mul(0x9e37_79b9_7f4a_7c15))
}

/// murmur3's 64-bit finaliser: a bijective avalanche mix.
#[inline]
pub(super) fn mix64(mut x: u64) -> u64 {
    x ^= x >> 33;
    x = x.wrapping_mul(0xff51_afd7_ed55_8ccd);
    x ^= x >> 33;
    x = x.wrapping_mul(0xc4ce_b9fe_1a85_ec53);
    x ^ (x >> 33)
}

/// The random stream of one pixel sample: dimension `d` is `hash(key, d)`. It also knows the
/// sample's index among the pixel's samples and a per-pixel stream (the same for every sample
/// of the pixel) so that light samples can be stratified across the whole pixel.
#[derive(Debug, Clone)]
pub struct Sampler {
    key: u64,
    dim: u64,
    pixel_key: u64,
    index: u32,
    count: u32,
    /// Points come from the replicate's progressive sequences ([`PixelSequences`]).
    progressive: bool,
    /// The first streams' keys (fixed-count samplers; unused by progressive ones).
    streams: [StreamKey; CACHED_STREAMS],
}

impl Sampler {
    /// A stand-alone stream: sample 0 of 1, so calls with different `sample` are independent.
    pub fn new(seed: u64, px: u32, py: u32, sample: u32) -> Sampler {
        let key = sample_key(seed, px, py, sample);
        let pixel_key = mix64(key ^ 0x5851_f42d_4c95_7f2d);
        Sampler {
            key,
            dim: 0,
            pixel_key,
            index: 0,
            count: 1,
            progressive: false,
            streams: StreamKey::first(pixel_key),
        }
    }

    /// Sample `index` of the `count` samples of pixel (`px`, `py`).
    pub fn for_pixel_sample(seed: u64, px: u32, py: u32, index: u32, count: u32) -> Sampler {
        Sampler::for_batch_sample(seed, px, py, 0, index, count)
    }

    /// Sample `index` of the `count` samples of batch `batch` of pixel (`px`, `py`): each batch
    /// of adaptive sampling is stratified on its own (its own per-pixel stream), and its sample
    /// keys follow the previous batches' (batch 0 is [`Sampler::for_pixel_sample`]).
    pub fn for_batch_sample(
        seed: u64,
        px: u32,
        py: u32,
        batch: u32,
        index: u32,
        count: u32,
    ) -> Sampler {
        PixelBatch::new(seed, px, py, batch, count).sampler(index)
    }

    /// A value in [0, 1) (24 random bits, so exactly representable).
    pub fn next_1d(&mut self) -> f32 {
        let h = mix64(self.key ^ self.dim.wrapping_mul(0x9e37_79b9_7f4a_7c15));
        self.dim += 1;
        to_unit(h)
    }

    /// The next two dimensions.
    pub fn next_2d(&mut self) -> Vec2 {
        Vec2::new(self.next_1d(), self.next_1d())
    }

    /// Random bits shared by every sample of the pixel, for per-pixel scrambling.
    pub fn pixel_bits(&self, dim: u64) -> u64 {
        pixel_bits(self.pixel_key, dim)
    }

    /// This sample's index among the pixel's samples, and their count (0 for a progressive
    /// sample, whose set has no fixed size: its index is within its replicate).
    pub fn index(&self) -> (u32, u32) {
        (self.index, self.count)
    }

    /// Point `j` of a 2-D set of `n` points shared by the pixel's samples (Hammersley points
    /// with a per-pixel Cranley–Patterson shift in x and a per-pixel digit scramble in y,
    /// keyed by `stream`): stratified over [0, 1)², and each point uniform on its own. For a
    /// progressive sample, point `j` of its replicate's sequence ([`Sampler::point_2d`]),
    /// whatever `n`.
    pub fn stratified_2d(&self, stream: u64, j: u32, n: u32) -> Vec2 {
        if self.progressive {
            return self.point_2d(stream, j);
        }
        stream_key(&self.streams, self.pixel_key, stream).point(j, n)
    }

    /// Point `j` of the pixel's Owen-scrambled Sobol' sequence for `stream` (see the module
    /// doc): every power-of-two prefix is a (0,k,2)-net, each point is uniform on [0, 1)².
    pub fn point_2d(&self, stream: u64, j: u32) -> Vec2 {
        OwenSobol::of(self.pixel_key, stream).point(j)
    }
}

/// `(j + 0.5) / n`. A power-of-two `n` (every square pattern's sample count at 4, 16, 64 or 256
/// samples per pixel) is a multiplication by its exact reciprocal, the same bits as the
/// division without its latency on the sample's chain.
#[inline]
fn stratum_centre(j: u32, n: u32) -> f32 {
    let centre = j as f32 + 0.5;
    if n.is_power_of_two() {
        // 2^-k: an exponent field of 127 − k, k ≤ 31.
        centre * f32::from_bits((127 - n.trailing_zeros()) << 23)
    } else {
        centre / n as f32
    }
}

/// Element `i` of a pseudo-random permutation of `0..len` keyed by `key` (Kensler 2013,
/// "Correlated Multi-Jittered Sampling": a hash bijective on the next power of two, cycle-walked
/// into `0..len`). `len` 0 is treated as 1; unless `len` is a power of two, `i` must lie in
/// `0..len`: the walk only ends there.
#[inline]
fn permute_index(i: u32, len: u32, key: u32) -> u32 {
    let len = len.max(1);
    let mut w = len - 1;
    w |= w >> 1;
    w |= w >> 2;
    w |= w >> 4;
    w |= w >> 8;
    w |= w >> 16;
    // A power-of-two length (every fixed-count render's) takes one round, and no division.
    if len & w == 0 {
        return permute_round(i, w, key).wrapping_add(key) & w;
    }
    debug_assert!(i < len, "index {i} outside the permutation of 0..{len}");
    let mut i = i;
    loop {
        i = permute_round(i, w, key);
        if i < len {
            return ((u64::from(i) + u64::from(key)) % u64::from(len)) as u32;
        }
    }
}

/// One round of [`permute_index`]'s hash, bijective on `0..=w` (`w + 1` a power of two).
#[inline(always)]
fn permute_round(mut i: u32, w: u32, key: u32) -> u32 {
    i ^= key;
    i = i.wrapping_mul(0xe170_893d);
    i ^= key >> 16;
    i ^= (i & w) >> 4;
    i ^= key >> 8;
    i = i.wrapping_mul(0x0929_eb3f);
    i ^= key >> 23;
    i ^= (i & w) >> 1;
    i = i.wrapping_mul(1 | key >> 27);
    i = i.wrapping_mul(0x6935_fa69);
    i ^= (i & w) >> 11;
    i = i.wrapping_mul(0x74dc_b303);
    i ^= (i & w) >> 2;
    i = i.wrapping_mul(0x9e50_1cc3);
    i ^= (i & w) >> 2;
    i = i.wrapping_mul(0xc860_a3df);
    i &= w;
    i ^ (i >> 5)
}

fn sample_key(seed: u64, px: u32, py: u32, sample: u32) -> u64 {
    key_of(pixel_hash(seed, px, py), sample)
}

/// The part of a sample's key that only depends on the seed and the pixel.
#[inline]
fn pixel_hash(seed: u64, px: u32, py: u32) -> u64 {
    let pixel = ((py as u64) << 32) | px as u64;
    mix64(mix64(seed) ^ pixel)
}

#[inline]
fn key_of(pixel_hash: u64, sample: u32) -> u64 {
    mix64(pixel_hash ^ (sample as u64).wrapping_add(0x9e37_79b9))
}

/// `x mod 1` for `x` in [0, 2): a sum of two values in [0, 1) wrapped back, without the libm
/// call `fract` is on a baseline x86-64 build (no SSE4.1 `roundss`); the same bits.
#[inline]
pub fn wrap_unit(x: f32) -> f32 {
    if x >= 1.0 {
        x - 1.0
    } else {
        x
    }
}

/// The per-pixel stream of adaptive batches' sub-pixel shifts (far from the integrator's).
pub const STREAM_SUBPIXEL: u64 = 1 << 40;

/// The top 24 bits of `h` as a value in [0, 1).
pub fn unit(h: u64) -> f32 {
    to_unit(h)
}

fn to_unit(h: u64) -> f32 {
    (h >> 40) as f32 * (1.0 / (1u64 << 24) as f32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stratum_centres_are_the_division_bit_for_bit() {
        for k in 0..32 {
            let n = 1u32 << k;
            for j in [0, 1, 7, n / 2, n.saturating_sub(1), n.wrapping_mul(3) / 4] {
                let by_division = (j as f32 + 0.5) / n as f32;
                assert_eq!(
                    stratum_centre(j, n).to_bits(),
                    by_division.to_bits(),
                    "{j}/{n}"
                );
            }
        }
        for (j, n) in [(0, 3), (5, 9), (11, 12), (0, 0), (4, 1000)] {
            let by_division = (j as f32 + 0.5) / n as f32;
            assert_eq!(
                stratum_centre(j, n).to_bits(),
                by_division.to_bits(),
                "{j}/{n}"
            );
        }
    }

    #[test]
    fn cached_stream_keys_are_the_ones_derived_per_sample() {
        let batch = PixelBatch::new(5, 3, 9, 0, 16);
        for s in 0..16 {
            let sampler = batch.sampler(s);
            for stream in 0..(CACHED_STREAMS as u64 + 3) {
                let key = StreamKey::of(sampler.pixel_key, stream);
                assert_eq!(key.bits, sampler.pixel_bits(stream));
                if let Some(cached) = sampler.streams.get(stream as usize) {
                    assert_eq!((cached.bits, cached.order), (key.bits, key.order));
                }
            }
        }
        let lone = Sampler::new(1, 2, 3, 4);
        for (stream, cached) in lone.streams.iter().enumerate() {
            let key = StreamKey::of(lone.pixel_key, stream as u64);
            assert_eq!((cached.bits, cached.order), (key.bits, key.order));
        }
    }

    /// A run's points taken together are the samplers' own, a power-of-two count or not; past
    /// the last sample (what a partly filled run computes and does not read) a power-of-two set
    /// goes on with its own permutation and any other wraps to its start, and either ends (the
    /// cycle walk of a count like 9 never ended for an index past the set).
    #[test]
    fn a_runs_stratified_points_are_its_samplers_points() {
        for count in [1, 4, 5, 9, 16, 17, 25, 256] {
            let batch = PixelBatch::new(11, 4, 7, 0, count);
            for stream in [3, 6] {
                for first in (0..count).step_by(8) {
                    let mut run = [Vec2::ZERO; 8];
                    batch.stratified_run(stream, first, count, &mut run);
                    for (j, p) in (first..).zip(run) {
                        let sampler = batch.sampler(j.min(count - 1));
                        let inside = if count.is_power_of_two() {
                            j
                        } else {
                            j % count
                        };
                        let q = sampler.stratified_2d(stream, inside, count);
                        assert_eq!(
                            p.to_array().map(f32::to_bits),
                            q.to_array().map(f32::to_bits)
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn same_inputs_same_values_and_uniform_mean() {
        let mut a = Sampler::new(7, 3, 4, 5);
        let mut b = Sampler::new(7, 3, 4, 5);
        let xs: Vec<f32> = (0..10_000).map(|_| a.next_1d()).collect();
        assert!(xs
            .iter()
            .all(|&x| x == b.next_1d() && (0.0..1.0).contains(&x)));
        let mean = xs.iter().sum::<f32>() / xs.len() as f32;
        // Standard error of the mean of U(0,1) over 1e4 values is 0.0029.
        assert!((mean - 0.5).abs() < 4.0 * 0.0029, "mean {mean}");
        let mut c = Sampler::new(7, 3, 4, 6);
        assert_ne!(xs[0], c.next_1d());
    }

    #[test]
    fn pixel_stratified_points_cover_every_stratum_once() {
        let count = 16;
        let mut xs = vec![0; count as usize];
        let mut ys = vec![0; count as usize];
        for s in 0..count {
            let sampler = Sampler::for_pixel_sample(3, 10, 20, s, count);
            assert_eq!(sampler.index(), (s, count));
            let p = sampler.stratified_2d(7, s, count);
            assert!((0.0..1.0).contains(&p.x) && (0.0..1.0).contains(&p.y));
            xs[(p.x * count as f32) as usize] += 1;
            ys[(p.y * count as f32) as usize] += 1;
        }
        assert!(xs.iter().chain(&ys).all(|&c| c == 1), "{xs:?} {ys:?}");
        // Across independent samplers the two coordinates are uncorrelated: E[xy] = 1/4
        // (standard error of the mean of xy over 1e4 values ≈ 0.0022).
        let n = 10_000;
        let exy: f32 = (0..n)
            .map(|i| {
                let p = Sampler::new(0, 0, 0, i).stratified_2d(5, 0, 1);
                p.x * p.y
            })
            .sum::<f32>()
            / n as f32;
        assert!((exy - 0.25).abs() < 4.0 * 0.0022, "E[xy] = {exy}");
        // Stand-alone samplers do not share their pixel stream.
        let a = Sampler::new(0, 0, 0, 1).stratified_2d(0, 0, 1);
        let b = Sampler::new(0, 0, 0, 2).stratified_2d(0, 0, 1);
        assert_ne!(a, b);
    }

    #[test]
    fn index_permutations_are_permutations() {
        for len in [1u32, 2, 3, 7, 16, 17, 100, 1024] {
            for key in [0u32, 1, 0xdead_beef, u32::MAX] {
                let mut seen = vec![false; len as usize];
                for i in 0..len {
                    let j = permute_index(i, len, key);
                    assert!(j < len && !seen[j as usize], "len {len} key {key}");
                    seen[j as usize] = true;
                }
            }
        }
        assert_eq!(permute_index(0, 0, 5), 0);
    }

    #[test]
    fn streams_of_one_pixel_are_not_tied_to_each_other() {
        // Sample s's points in two streams: their pairs must fill the square (a light point
        // that is a function of the sub-pixel position never averages to the pixel's integral).
        // 4096 samples in an 8×8 grid: 64 expected per cell.
        let count = 4096;
        for (px, py) in [(0, 0), (17, 3), (200, 411)] {
            let mut cells = [0u32; 64];
            for s in 0..count {
                let sampler = Sampler::for_pixel_sample(1, px, py, s, count);
                let a = sampler.stratified_2d(0, s, count).x;
                let b = sampler.stratified_2d(3, s, count).x;
                cells[(a * 8.0) as usize * 8 + (b * 8.0) as usize] += 1;
            }
            assert!(
                cells.iter().all(|&c| (32..=96).contains(&c)),
                "pixel ({px}, {py}): {cells:?}"
            );
        }
    }

    /// Whether the points put exactly one point in every elementary interval of area 1/n
    /// (every `2^a × 2^b` grid with `a + b = log2 n`).
    fn is_02_net(points: &[Vec2]) -> bool {
        let n = points.len();
        let m = n.trailing_zeros();
        (0..=m).all(|a| {
            let (cols, rows) = (1usize << a, 1usize << (m - a));
            let mut cells = vec![0u32; n];
            for p in points {
                let (cx, cy) = ((p.x * cols as f32) as usize, (p.y * rows as f32) as usize);
                cells[cy.min(rows - 1) * cols + cx.min(cols - 1)] += 1;
            }
            cells.iter().all(|&c| c == 1)
        })
    }

    #[test]
    fn every_power_of_two_prefix_of_every_stream_is_a_02_net() {
        for (seed, px, py, stream) in [(0, 0, 0, 0), (3, 10, 20, 7), (9, 511, 3, 1 << 40)] {
            let points: Vec<Vec2> = (0..2048)
                .map(|j| Sampler::for_pixel_sample(seed, px, py, 0, 1).point_2d(stream, j))
                .collect();
            assert!(points
                .iter()
                .all(|p| (0.0..1.0).contains(&p.x) && (0.0..1.0).contains(&p.y)));
            for k in 0..=10 {
                assert!(
                    is_02_net(&points[..1 << k]),
                    "prefix 2^{k}, stream {stream}"
                );
                // The next block of the same size is a net too (continuation in batches).
                assert!(is_02_net(&points[1 << k..2 << k]), "block 2^{k}");
            }
        }
    }

    #[test]
    fn an_adaptive_pixels_shared_rounds_are_one_stratified_set_then_replicates_go_their_own_way() {
        let shared = (SHARED_ROUNDS * REPLICATES) as usize;
        for (seed, px, py, stream) in [(0, 0, 0, 0), (3, 10, 20, 7), (9, 511, 3, 1 << 40)] {
            let sequences = PixelSequences::new(seed, px, py);
            let point = |g: u32| {
                let sampler = sequences.sampler(g);
                sampler.point_2d(stream, sampler.index().0)
            };
            let first: Vec<Vec2> = (0..shared as u32).map(point).collect();
            for k in [2, 4].into_iter().filter(|&k| k <= shared) {
                assert!(is_02_net(&first[..k]), "the first {k}");
            }
            assert!((0..shared as u32).all(|g| PixelSequences::replicate(g).is_none()));
            // Replicate r's later samples are its own sequence from its start: a net at every
            // power of two, each batch of 16 adding a block of 4.
            for r in 0..REPLICATES {
                let own: Vec<u32> = (SHARED_ROUNDS..SHARED_ROUNDS + 8)
                    .map(|k| k * REPLICATES + r)
                    .collect();
                assert!(own
                    .iter()
                    .all(|&g| PixelSequences::replicate(g) == Some(r as usize)));
                let own: Vec<Vec2> = own.into_iter().map(point).collect();
                assert!(is_02_net(&own[..4]) && is_02_net(&own), "replicate {r}");
            }
        }
    }

    #[test]
    fn a_pixels_points_taken_together_are_its_samplers_points() {
        for (seed, px, py) in [(0, 0, 0), (3, 10, 20), (9, 511, 3)] {
            let sequences = PixelSequences::new(seed, px, py);
            for stream in [0, 3, STREAM_SUBPIXEL] {
                for samples in [0..2, 2..4, 4..20, 20..36, 1..7, 36..40] {
                    let mut out = [Vec2::splat(-1.0); 16];
                    sequences.points_2d(stream, samples.clone(), &mut out);
                    for (k, g) in samples.enumerate() {
                        let sampler = sequences.sampler(g);
                        let one = sampler.point_2d(stream, sampler.index().0);
                        assert_eq!(out[k], one, "sample {g}, stream {stream}");
                    }
                }
            }
        }
    }

    #[test]
    fn a_runs_lanes_gathered_from_several_pixels_are_each_pixels_points() {
        let pixels = [(0, 0), (3, 10), (511, 3), (4, 4)].map(|(x, y)| PixelSequences::new(9, x, y));
        for (first, each) in [(0, 2), (2, 2), (0, 1), (1, 3), (4, 4), (20, 8), (17, 2)] {
            let mut lanes = RunLanes::default();
            let mut expected = [[Vec2::ZERO; RUN_LANES]; 2];
            for k in 0..RUN_LANES / each {
                let samples = first..first + each as u32;
                for (i, g) in (k * each..).zip(samples.clone()) {
                    lanes.set(i, &pixels[k % pixels.len()], g);
                }
                for (c, stream) in CACHED_POINT_STREAMS.into_iter().enumerate() {
                    let out = &mut expected[c][k * each..(k + 1) * each];
                    pixels[k % pixels.len()].points_2d(stream, samples.clone(), out);
                }
            }
            for (c, stream) in CACHED_POINT_STREAMS.into_iter().enumerate() {
                let mut out = [Vec2::splat(-1.0); RUN_LANES];
                lanes.points_2d(stream, &mut out);
                let filled = RUN_LANES / each * each;
                assert_eq!(
                    out[..filled],
                    expected[c][..filled],
                    "{first}, {each}, {stream}"
                );
            }
        }
    }

    #[test]
    fn scrambled_points_are_uniform_and_coordinates_uncorrelated() {
        // Point 0 of independent scrambles: E[x] = E[y] = 1/2, E[xy] = 1/4 (standard errors
        // of the means over 1e4 values: 0.0029 and ≈ 0.0022).
        let n = 10_000;
        let (mut sx, mut sy, mut sxy) = (0.0f64, 0.0f64, 0.0f64);
        for i in 0..n {
            let p = Sampler::new(0, 0, 0, i).point_2d(5, 0);
            sx += p.x as f64;
            sy += p.y as f64;
            sxy += (p.x * p.y) as f64;
        }
        let n = n as f64;
        assert!((sx / n - 0.5).abs() < 4.0 * 0.0029 && (sy / n - 0.5).abs() < 4.0 * 0.0029);
        assert!((sxy / n - 0.25).abs() < 4.0 * 0.0022, "E[xy] = {}", sxy / n);
        let a = Sampler::new(0, 0, 0, 1).point_2d(0, 0);
        let b = Sampler::new(0, 0, 0, 2).point_2d(0, 0);
        assert_ne!(a, b);
    }
}
