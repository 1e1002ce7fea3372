//! The query objects of the two-level BVH: the top level's leaf tests (each instance's bottom
//! level) and the queries handed to the AVX2 and AVX-512 kernels. Types rather than closures,
//! so that they are inlined into the kernel compiled for the instruction set (see
//! `docs/bvh.md`, "Instruction set").
//!
//! Stage: queries, for `two_level.rs`.

use std::marker::PhantomData;

use super::isa::Isa;
use super::mesh_bvh::TriTest;
use super::slot_hit::PackedSlotHit;
use super::traverse::{Entry, LeafVisitor, STACK_MAX};
use super::two_level::{Placed, TwoLevel};
use super::Hit;
use crate::geom::avx2::Kernel;
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

/// A query to run inside an instruction set's kernel function (`Avx2::run`, `Avx512::run`):
/// closest-hit (`ANY == false`) or any-hit, with triangle test `T`.
pub(super) struct OnKernel<'a, T, const ANY: bool> {
    pub(super) accel: &'a TwoLevel,
    pub(super) ray: &'a Ray,
    pub(super) stacks: &'a mut [Entry],
    pub(super) test: PhantomData<T>,
}

pub(super) type ClosestOn<'a, T> = OnKernel<'a, T, false>;
pub(super) type AnyOn<'a, T> = OnKernel<'a, T, true>;

impl<'a, T, const ANY: bool> OnKernel<'a, T, ANY> {
    pub(super) fn new(accel: &'a TwoLevel, ray: &'a Ray, stacks: &'a mut [Entry]) -> Self {
        OnKernel {
            accel,
            ray,
            stacks,
            test: PhantomData,
        }
    }
}

impl<T: TriTest, I: Isa> Kernel<I> for ClosestOn<'_, T> {
    type Output = Option<Hit>;
    #[inline(always)]
    fn call(self, isa: I) -> Option<Hit> {
        self.accel.closest_with::<T, I>(isa, self.ray, self.stacks)
    }
}

impl<T: TriTest, I: Isa> Kernel<I> for AnyOn<'_, T> {
    type Output = bool;
    #[inline(always)]
    fn call(self, isa: I) -> bool {
        self.accel.any_with::<T, I>(isa, self.ray, self.stacks)
    }
}

/// The closest-hit query of a structure with one placement `p` (no top level), run inside the
/// kernel: it returns the hit's slot, packed into two registers ([`PackedSlotHit`]), and the
/// caller resolves the triangle and instance after the kernel has returned.
pub(super) struct ClosestOneOn<'a, T> {
    accel: &'a TwoLevel,
    p: &'a Placed,
    ray: &'a Ray,
    stacks: &'a mut [Entry],
    test: PhantomData<T>,
}

impl<'a, T> ClosestOneOn<'a, T> {
    pub(super) fn new(
        accel: &'a TwoLevel,
        p: &'a Placed,
        ray: &'a Ray,
        stacks: &'a mut [Entry],
    ) -> Self {
        ClosestOneOn {
            accel,
            p,
            ray,
            stacks,
            test: PhantomData,
        }
    }
}

impl<T: TriTest, I: Isa> Kernel<I> for ClosestOneOn<'_, T> {
    type Output = PackedSlotHit;
    #[inline(always)]
    fn call(self, isa: I) -> PackedSlotHit {
        // The bottom level's half, as `TwoLevel::closest_with` splits them.
        let (_, mesh_stack) = self.stacks.split_at_mut(STACK_MAX);
        let mut t_max = self.ray.t_max;
        self.accel
            .closest_slot_in::<T, I>(isa, self.p, self.ray, &mut t_max, mesh_stack)
            .pack()
    }
}
