//! The two-level BVH: a top-level BVH over instances (world bounds = the transformed bounds of
//! their mesh's BVH) whose leaves send the ray, mapped into object space, into the one shared
//! bottom-level BVH of the instance's mesh. Meshes are never copied per instance. The object
//! ray's direction is transformed without renormalising, so `t` means the same point in both
//! spaces and one `t_max` serves the whole query.

use std::marker::PhantomData;

use glam::{Affine3A, Vec3A};
use rayon::prelude::*;

use super::build::{build, PrimBox, PrimRef};
use super::dispatch::Path;
use super::isa::Isa;
use super::mesh_bvh::{MeshBvh, TriTest};
use super::query::{TopAny, TopClosest};
use super::rebuild::{build_like, Trace};
use super::slot_hit::SlotHit;
use super::traverse::{traverse, Entry, STACK_MAX};
use super::wide::{collapse, Wide, WideNode, WideRay};
use super::{AccelStats, Hit, Instance, MeshRef, TriangleTest};
use crate::geom::{Aabb, Ray};

/// An instance that survived validation (its mesh exists and has triangles, its transform is
/// finite and invertible).
#[derive(Debug, Clone, Copy)]
pub(super) struct Placed {
    /// Which bottom-level BVH: a mesh index, or `meshes.len()` for the merged group.
    pub group: u32,
    /// Index in the caller's instance list, reported in hits (unused for the merged group,
    /// whose hits name their instance through `merged_instances`).
    pub index: u32,
    pub merged: bool,
    pub object_from_world: Affine3A,
    /// Skip the ray transform (the common single-instance case).
    pub identity: bool,
    pub world_bounds: Aabb,
}

/// The two-level acceleration structure: instances over shared per-mesh BVHs.
#[derive(Debug)]
pub struct TwoLevel {
    /// Bottom-level BVHs: one per mesh that some non-merged instance places (empty for the
    /// others), then the merged group.
    pub(super) meshes: Vec<MeshBvh>,
    /// The instance of each part of the merged group.
    pub(super) merged_instances: Vec<u32>,
    /// The mesh of each part of the merged group (for the invariant checker).
    pub(super) merged_meshes: Vec<u32>,
    pub(super) placed: Vec<Placed>,
    pub(super) top: Wide,
    /// Leaf order of the top level: indices into `placed`.
    pub(super) top_order: Vec<u32>,
    /// The kernels and triangle test queries run on (`dispatch.rs`).
    pub(super) path: Path,
}

fn finite_affine(m: &Affine3A) -> bool {
    m.matrix3.is_finite() && m.translation.is_finite()
}

/// What the build does with an instance.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Role {
    /// Its mesh does not exist or its transform is not finite: left out.
    Invalid,
    /// An identity placement of a mesh placed once: its triangles join the merged group.
    Merged,
    /// Traced through its mesh's own bottom-level BVH.
    Own,
}

fn is_identity(inst: &Instance) -> bool {
    inst.world_from_object == Affine3A::IDENTITY && inst.object_from_world == Affine3A::IDENTITY
}

/// Each instance's [`Role`].
fn roles(meshes: &[MeshRef<'_>], instances: &[Instance]) -> Vec<Role> {
    let valid = |inst: &Instance| {
        (inst.mesh as usize) < meshes.len()
            && finite_affine(&inst.world_from_object)
            && finite_affine(&inst.object_from_world)
    };
    let mut placements = vec![0u32; meshes.len()];
    for inst in instances.iter().filter(|i| valid(i)) {
        placements[inst.mesh as usize] += 1;
    }
    instances
        .iter()
        .map(|inst| {
            if !valid(inst) {
                Role::Invalid
            } else if is_identity(inst) && placements[inst.mesh as usize] == 1 {
                Role::Merged
            } else {
                Role::Own
            }
        })
        .collect()
}

/// One BVH per mesh that some [`Role::Own`] instance places (empty for the others; each built
/// once however often placed), then the merged group's, built in parallel.
fn bottom_levels(
    meshes: &[MeshRef<'_>],
    instances: &[Instance],
    roles: &[Role],
    merged_instances: &[u32],
) -> Vec<MeshBvh> {
    let mut own = vec![false; meshes.len()];
    for (inst, _) in instances
        .iter()
        .zip(roles)
        .filter(|(_, r)| **r == Role::Own)
    {
        own[inst.mesh as usize] = true;
    }
    let mut jobs: Vec<Vec<MeshRef<'_>>> = meshes
        .iter()
        .zip(&own)
        .map(|(m, &o)| if o { vec![*m] } else { Vec::new() })
        .collect();
    jobs.push(
        merged_instances
            .iter()
            .map(|&i| meshes[instances[i as usize].mesh as usize])
            .collect(),
    );
    jobs.par_iter().map(|parts| MeshBvh::build(parts)).collect()
}

/// Instance `index` through its mesh's own BVH; `None` if that is empty or its world bounds
/// are not finite.
fn own_placement(bvh: &MeshBvh, index: usize, inst: &Instance) -> Option<Placed> {
    let world_bounds = bvh.bounds().transformed(&inst.world_from_object);
    let ok = !bvh.is_empty() && world_bounds.min.is_finite() && world_bounds.max.is_finite();
    ok.then(|| Placed {
        group: inst.mesh,
        index: index as u32,
        merged: false,
        object_from_world: inst.object_from_world,
        identity: is_identity(inst),
        world_bounds,
    })
}

/// How [`TwoLevel::build_top`] builds the top level: from scratch, with or without keeping
/// its trace, or beside an earlier build's trace.
enum Top<'a> {
    Fresh,
    Traced,
    Like(&'a Trace),
}

impl TwoLevel {
    /// Identity instances of meshes placed only once are merged into one bottom-level BVH (no
    /// triangle is stored twice, and a ray then traverses one tree instead of several that
    /// overlap); every other mesh gets its own BVH, shared by all its instances.
    pub fn build(meshes: &[MeshRef<'_>], instances: &[Instance], test: TriangleTest) -> TwoLevel {
        Self::build_top(meshes, instances, test, Top::Fresh).0
    }

    /// [`TwoLevel::build`], its top level built from an `earlier` build's trace where the
    /// instances' world boxes are unchanged (the same structure, bit for bit; `rebuild.rs`),
    /// and the trace of this build for the next.
    pub fn build_traced(
        meshes: &[MeshRef<'_>],
        instances: &[Instance],
        test: TriangleTest,
        earlier: Option<&Trace>,
    ) -> (TwoLevel, Trace) {
        let top = match earlier {
            Some(earlier) => Top::Like(earlier),
            None => Top::Traced,
        };
        let (two, trace) = Self::build_top(meshes, instances, test, top);
        (two, trace.unwrap_or_default())
    }

    /// The build; the trace only when `top` asks for one (a plain build keeps no copy of its
    /// input).
    fn build_top(
        meshes: &[MeshRef<'_>],
        instances: &[Instance],
        test: TriangleTest,
        top: Top<'_>,
    ) -> (TwoLevel, Option<Trace>) {
        let roles = roles(meshes, instances);
        let merged_instances: Vec<u32> = (0..instances.len() as u32)
            .filter(|&i| roles[i as usize] == Role::Merged)
            .collect();
        let bvhs = bottom_levels(meshes, instances, &roles, &merged_instances);
        let merged_group = meshes.len() as u32;
        let mut placed: Vec<Placed> = instances
            .iter()
            .enumerate()
            .filter(|(i, _)| roles[*i] == Role::Own)
            .filter_map(|(i, inst)| own_placement(&bvhs[inst.mesh as usize], i, inst))
            .collect();
        let merged = &bvhs[merged_group as usize];
        if !merged.is_empty() {
            placed.push(Placed {
                group: merged_group,
                index: u32::MAX,
                merged: true,
                object_from_world: Affine3A::IDENTITY,
                identity: true,
                world_bounds: merged.bounds(),
            });
        }
        let refs: Vec<PrimRef> = placed
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let bounds = PrimBox {
                    min: Vec3A::from(p.world_bounds.min),
                    max: Vec3A::from(p.world_bounds.max),
                };
                PrimRef::new(bounds, i as u32)
            })
            .collect();
        let (built, trace) = match top {
            Top::Fresh => (build(refs, 1), None),
            Top::Traced => {
                let input = refs.clone();
                let built = build(refs, 1);
                (built, Some(input))
            }
            Top::Like(earlier) => {
                let input = refs.clone();
                (build_like(refs, 1, earlier), Some(input))
            }
        };
        let (top_nodes, top_order, trace) = match trace {
            Some(input) => {
                let trace = Trace::new(input, built);
                (collapse(trace.nodes()), trace.order().to_vec(), Some(trace))
            }
            None => (collapse(&built.nodes), built.order, None),
        };
        let two = TwoLevel {
            meshes: bvhs,
            merged_meshes: merged_instances
                .iter()
                .map(|&i| instances[i as usize].mesh)
                .collect(),
            merged_instances,
            placed,
            top: top_nodes,
            top_order,
            path: Path::detect(test),
        };
        (two, trace)
    }

    #[inline(always)]
    fn object_ray(p: &Placed, ray: &Ray) -> Ray {
        if p.identity {
            *ray
        } else {
            Ray {
                origin: p.object_from_world.transform_point3(ray.origin),
                dir: p.object_from_world.transform_vector3(ray.dir),
                t_max: ray.t_max,
            }
        }
    }

    #[inline(always)]
    pub(super) fn closest_in<T: TriTest, I: Isa>(
        &self,
        isa: I,
        p: &Placed,
        ray: &Ray,
        t_max: &mut f32,
        stack: &mut [Entry],
    ) -> Option<Hit> {
        let obj = Self::object_ray(p, ray);
        let h = self.meshes[p.group as usize].closest::<T, I>(isa, &obj, t_max, stack)?;
        let instance = if p.merged {
            self.merged_instances[h.part as usize]
        } else {
            p.index
        };
        Some(Hit {
            t: *t_max,
            u: h.u,
            v: h.v,
            instance,
            prim: h.prim,
        })
    }

    /// [`Self::closest_in`] as the kernel leaves it (see [`SlotHit`]).
    #[inline(always)]
    pub(super) fn closest_slot_in<T: TriTest, I: Isa>(
        &self,
        isa: I,
        p: &Placed,
        ray: &Ray,
        t_max: &mut f32,
        stack: &mut [Entry],
    ) -> SlotHit {
        let obj = Self::object_ray(p, ray);
        self.meshes[p.group as usize].closest_slot::<T, I>(isa, &obj, t_max, stack)
    }

    /// The closest hit, on `isa`'s kernels, with `stacks` (two `STACK_MAX` halves: the top
    /// level's and the bottom level's). No closures: everything here is inlined into the
    /// AVX2 kernel, which a closure's body might not be.
    #[inline(always)]
    pub(super) fn closest_with<T: TriTest, I: Isa>(
        &self,
        isa: I,
        ray: &Ray,
        stacks: &mut [Entry],
    ) -> Option<Hit> {
        let (top_stack, mesh_stack) = stacks.split_at_mut(STACK_MAX);
        let mut t_max = ray.t_max;
        // One group (the common case: every mesh placed once, unmoved): no top level.
        if let [p] = self.placed.as_slice() {
            return self.closest_in::<T, I>(isa, p, ray, &mut t_max, mesh_stack);
        }
        let wr = WideRay::new(ray);
        let mut leaf = TopClosest::<T, I> {
            accel: self,
            isa,
            ray,
            stack: mesh_stack,
            best: None,
            test: PhantomData,
        };
        traverse(isa, &self.top, &wr, &mut t_max, &mut leaf, top_stack);
        leaf.best
    }

    /// Whether anything blocks `ray` inside instance `p`.
    #[inline(always)]
    pub(super) fn any_in<T: TriTest, I: Isa>(
        &self,
        isa: I,
        p: &Placed,
        ray: &Ray,
        t_max: f32,
        stack: &mut [Entry],
    ) -> bool {
        let obj = Self::object_ray(p, ray);
        self.meshes[p.group as usize].any::<T, I>(isa, &obj, t_max, stack)
    }

    /// The any-hit query, as [`Self::closest_with`].
    #[inline(always)]
    pub(super) fn any_with<T: TriTest, I: Isa>(
        &self,
        isa: I,
        ray: &Ray,
        stacks: &mut [Entry],
    ) -> bool {
        let (top_stack, mesh_stack) = stacks.split_at_mut(STACK_MAX);
        if let [p] = self.placed.as_slice() {
            return self.any_in::<T, I>(isa, p, ray, ray.t_max, mesh_stack);
        }
        let wr = WideRay::new(ray);
        let mut t_max = ray.t_max;
        let leaf = TopAny::<T, I> {
            accel: self,
            isa,
            ray,
            stack: mesh_stack,
            test: PhantomData,
        };
        traverse(isa, &self.top, &wr, &mut t_max, leaf, top_stack)
    }

    /// Node, leaf and triangle counts and memory, for `--stats`.
    pub fn stats(&self) -> AccelStats {
        let leaves = |w: &Wide| {
            let inner: usize = w
                .nodes
                .iter()
                .map(|n| n.count.iter().filter(|&&c| c > 0).count())
                .sum();
            inner + usize::from(w.root_count > 0)
        };
        let top_bytes = self.top.nodes.len() * std::mem::size_of::<WideNode>()
            + self.top_order.len() * 4
            + self.placed.len() * std::mem::size_of::<Placed>()
            + self.merged_instances.len() * 8;
        let mut s = AccelStats {
            nodes: self.top.nodes.len(),
            leaves: leaves(&self.top),
            triangles: 0,
            bytes: top_bytes,
            instance_bytes: top_bytes,
        };
        for m in &self.meshes {
            s.nodes += m.tree.nodes.len();
            s.leaves += leaves(&m.tree);
            s.triangles += m.triangle_count();
            s.bytes += m.bytes();
        }
        s
    }
}
