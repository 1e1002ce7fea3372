//! The query objects of the two-level BVH: the top level's leaf tests (each instance's bottom
//! level) and the queries handed to the AVX2 kernel. Types rather than closures, so that they
//! are inlined into the kernel compiled for AVX2 (see `docs/bvh.md`, "Instruction set").
//!
//! Stage: queries, for `two_level.rs`.

use std::marker::PhantomData;

use super::isa::Isa;
use super::mesh_bvh::TriTest;
use super::traverse::{Entry, LeafVisitor};
use super::two_level::TwoLevel;
use super::Hit;
use crate::geom::avx2::{Avx2, Avx2Kernel};
use crate::geom::Ray;

/// The top level's closest-hit leaf test: each instance's bottom level.
pub(super) struct TopClosest<'a, T, I> {
    pub(super) accel: &'a TwoLevel,
    pub(super) isa: I,
    pub(super) ray: &'a Ray,
    pub(super) stack: &'a mut [Entry],
    pub(super) best: Option<Hit>,
    pub(super) test: PhantomData<T>,
}

impl<T: TriTest, I: Isa> LeafVisitor for &mut TopClosest<'_, T, I> {
    #[inline(always)]
    fn visit(&mut self, first: u32, count: u32, t_max: &mut f32) -> bool {
        let a = self.accel;
        for &k in &a.top_order[first as usize..(first + count) as usize] {
            let p = &a.placed[k as usize];
            if let Some(h) = a.closest_in::<T, I>(self.isa, p, self.ray, t_max, self.stack) {
                self.best = Some(h);
            }
        }
        false
    }
}

/// The top level's any-hit leaf test.
pub(super) struct TopAny<'a, T, I> {
    pub(super) accel: &'a TwoLevel,
    pub(super) isa: I,
    pub(super) ray: &'a Ray,
    pub(super) stack: &'a mut [Entry],
    pub(super) test: PhantomData<T>,
}

impl<T: TriTest, I: Isa> LeafVisitor for TopAny<'_, T, I> {
    #[inline(always)]
    fn visit(&mut self, first: u32, count: u32, t_max: &mut f32) -> bool {
        let a = self.accel;
        for &k in &a.top_order[first as usize..(first + count) as usize] {
            let p = &a.placed[k as usize];
            if a.any_in::<T, I>(self.isa, p, self.ray, *t_max, self.stack) {
                return true;
            }
        }
        false
    }
}

/// A query to run on the AVX2 kernels ([`Avx2::run`]): closest-hit (`ANY == false`) or
/// any-hit, with triangle test `T`.
pub(super) struct OnAvx2<'a, T, const ANY: bool> {
    pub(super) accel: &'a TwoLevel,
    pub(super) ray: &'a Ray,
    pub(super) stacks: &'a mut [Entry],
    pub(super) test: PhantomData<T>,
}

pub(super) type ClosestOn<'a, T> = OnAvx2<'a, T, false>;
pub(super) type AnyOn<'a, T> = OnAvx2<'a, T, true>;

impl<'a, T, const ANY: bool> OnAvx2<'a, T, ANY> {
    pub(super) fn new(accel: &'a TwoLevel, ray: &'a Ray, stacks: &'a mut [Entry]) -> Self {
        OnAvx2 {
            accel,
            ray,
            stacks,
            test: PhantomData,
        }
    }
}

impl<T: TriTest> Avx2Kernel for ClosestOn<'_, T> {
    type Output = Option<Hit>;
    #[inline(always)]
    fn call(self, avx: Avx2) -> Option<Hit> {
        self.accel.closest_with::<T, _>(avx, self.ray, self.stacks)
    }
}

impl<T: TriTest> Avx2Kernel for AnyOn<'_, T> {
    type Output = bool;
    #[inline(always)]
    fn call(self, avx: Avx2) -> bool {
        self.accel.any_with::<T, _>(avx, self.ray, self.stacks)
    }
}
