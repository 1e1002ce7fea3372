//! The bottom level: one BVH per mesh, in the mesh's object space, with the triangles' vertices
//! copied in leaf order into packets of four (structure of arrays, 144 bytes per packet, read
//! sequentially by a leaf and tested four at a time) beside their original indices. Each leaf
//! starts a new packet; the build's cost model counts leaf tests in packets, so leaves fill them.
//! Triangles with a non-finite vertex or an out-of-range index are left out at build.

use glam::{Vec3, Vec3A};
use rayon::prelude::*;

use super::build::{build, Built, PrimBox, PrimRef};
use super::isa::Isa;
use super::octant::OctantQuery;
use super::slot_hit::SlotHit;
use super::traverse::{traverse, Entry, LeafVisitor};
use super::wide::{collapse, Wide, WideNode, WideRay, WIDTH};
use super::MeshRef;
use crate::geom::triangle::{moller_trumbore, TriangleHit, WatertightRay};
use crate::geom::triangle4::{Tri4, LANES};
use crate::geom::{Aabb, Ray};

/// Triangles a leaf test handles at once (the packet width), for the build's cost model.
const TRI_BLOCK: u32 = LANES as u32;

/// A slot of the leaf order that holds no triangle (the padding of a leaf's last packet).
const NO_TRIANGLE: u32 = u32::MAX;

/// The two ray–triangle tests, chosen once per query so each traversal loop is monomorphic
/// (a private trait for static dispatch; the public choice is the `TriangleTest` enum).
pub trait TriTest {
    /// Per-ray constants, computed once per query.
    type Prepared: Copy;
    /// Computes the per-ray constants of `ray`.
    fn prepare(ray: &Ray) -> Self::Prepared;
    /// The closest hit in the packets `tris` with `0 < t < *t_max`, as testing their triangles
    /// one by one in order (a later hit kept only if strictly nearer); shrinks `*t_max`.
    /// Returns the hit's slot within `tris` (packet · 4 + lane).
    fn closest<I: Isa>(
        isa: I,
        pre: &Self::Prepared,
        t_max: &mut f32,
        tris: &[Tri4],
    ) -> Option<(usize, TriangleHit)>;
    /// Whether any triangle of the packets `tris` is hit with `0 < t < t_max`.
    fn any<I: Isa>(isa: I, pre: &Self::Prepared, t_max: f32, tris: &[Tri4]) -> bool;
}

/// [`TriTest`] running [`moller_trumbore`], one triangle at a time.
pub struct MollerTrumbore;
/// [`TriTest`] running the watertight test, four or eight triangles at a time (the [`Isa`]'s).
pub struct Watertight;

impl TriTest for MollerTrumbore {
    type Prepared = Ray;
    #[inline(always)]
    fn prepare(ray: &Ray) -> Ray {
        *ray
    }
    #[inline(always)]
    fn closest<I: Isa>(
        _: I,
        ray: &Ray,
        t_max: &mut f32,
        tris: &[Tri4],
    ) -> Option<(usize, TriangleHit)> {
        let mut best = None;
        for (p, packet) in tris.iter().enumerate() {
            for lane in 0..LANES {
                let Some([p0, p1, p2]) = packet.get(lane) else {
                    continue;
                };
                let r = Ray {
                    t_max: *t_max,
                    ..*ray
                };
                if let Some(h) = moller_trumbore(&r, p0.into(), p1.into(), p2.into()) {
                    *t_max = h.t;
                    best = Some((p * LANES + lane, h));
                }
            }
        }
        best
    }
    #[inline(always)]
    fn any<I: Isa>(_: I, ray: &Ray, t_max: f32, tris: &[Tri4]) -> bool {
        let r = Ray { t_max, ..*ray };
        tris.iter().any(|packet| {
            (0..LANES).any(|lane| {
                packet.get(lane).is_some_and(|[p0, p1, p2]| {
                    moller_trumbore(&r, p0.into(), p1.into(), p2.into()).is_some()
                })
            })
        })
    }
}

impl TriTest for Watertight {
    type Prepared = WatertightRay;
    #[inline(always)]
    fn prepare(ray: &Ray) -> WatertightRay {
        WatertightRay::new(ray)
    }
    #[inline(always)]
    fn closest<I: Isa>(
        isa: I,
        r: &WatertightRay,
        t_max: &mut f32,
        tris: &[Tri4],
    ) -> Option<(usize, TriangleHit)> {
        isa.closest_tris(r, t_max, tris)
    }
    #[inline(always)]
    fn any<I: Isa>(isa: I, r: &WatertightRay, t_max: f32, tris: &[Tri4]) -> bool {
        isa.any_tris(r, t_max, tris)
    }
}

/// A triangle's vertices: 16-byte aligned for single-load SIMD use.
pub type Tri = [Vec3A; 3];

/// A closest hit inside one bottom-level BVH: triangle `prim` of its mesh number `part`.
#[derive(Debug, Clone, Copy)]
pub struct MeshHit {
    /// Which of the parts given to [`MeshBvh::build`] the triangle belongs to.
    pub part: u32,
    /// Index into that part's `triangles`.
    pub prim: u32,
    /// Barycentric weight of the triangle's second vertex.
    pub u: f32,
    /// Barycentric weight of the triangle's third vertex.
    pub v: f32,
}

/// A bottom-level BVH over the triangles of one or more meshes, in their object space.
#[derive(Debug, Default)]
pub struct MeshBvh {
    /// The tree; a leaf's `child` is its first slot (a multiple of 4), its `count` the number
    /// of triangles, which fill its packets from the first lane.
    pub(super) tree: Wide,
    /// The leaf-ordered triangles, four per packet (slot `k` is lane `k % 4` of packet `k / 4`).
    pub(super) tris: Vec<Tri4>,
    /// `ids[k]`: which triangle slot `k` holds, numbered across the parts in order;
    /// `NO_TRIANGLE` for the padding after a leaf's last triangle.
    pub(super) ids: Vec<u32>,
    /// Where each part's numbering starts (one entry per part, ascending).
    pub(super) part_starts: Vec<u32>,
    /// Triangles held (slots that are not padding).
    pub(super) triangle_count: usize,
}

/// The vertices of triangle `t`, or `None` if an index is out of range or a vertex not finite.
pub fn triangle_vertices(mesh: &MeshRef<'_>, t: &[u32; 3]) -> Option<[Vec3; 3]> {
    let v = |k: usize| {
        mesh.positions
            .get(t[k] as usize)
            .copied()
            .filter(|p| p.is_finite())
    };
    Some([v(0)?, v(1)?, v(2)?])
}

/// The vertices of a triangle the builder ordered: [`MeshBvh::build`] gave the builder only
/// triangles whose [`triangle_vertices`] is `Some`, and the mesh has not changed since.
#[allow(
    clippy::expect_used,
    reason = "build() hands the builder only triangles whose triangle_vertices is Some, and \
              the builder's order holds only those ids"
)]
fn builder_vertices(mesh: &MeshRef<'_>, t: &[u32; 3]) -> [Vec3; 3] {
    triangle_vertices(mesh, t)
        .expect("only triangles with valid vertices were given to the builder")
}

impl MeshBvh {
    /// One BVH over the triangles of `parts` (usually one mesh; several meshes when identity
    /// instances are merged, each placed once, so nothing is duplicated).
    ///
    /// Temporaries are dropped as soon as the next step no longer needs them, so that the peak
    /// during the build (32-byte primitive references and 32-byte binary nodes, about 60 bytes per triangle)
    /// stays below the size of the result (about 90).
    pub fn build(parts: &[MeshRef<'_>]) -> MeshBvh {
        let total: usize = parts.iter().map(|m| m.triangles.len()).sum();
        let mut refs = Vec::with_capacity(total);
        let mut part_starts = Vec::with_capacity(parts.len());
        let mut id = 0u32;
        for mesh in parts {
            part_starts.push(id);
            for t in mesh.triangles {
                if let Some(tri) = triangle_vertices(mesh, t) {
                    let [a, b, c] = tri.map(Vec3A::from);
                    let bounds = PrimBox {
                        min: a.min(b).min(c),
                        max: a.max(b).max(c),
                    };
                    refs.push(PrimRef::new(bounds, id));
                }
                id += 1;
            }
        }
        let Built { nodes, order } = build(refs, TRI_BLOCK);
        let mut tree = collapse(&nodes);
        drop(nodes);
        let triangle_count = order.len();
        let ids = pack_leaves(&mut tree, &order);
        drop(order);
        let mut bvh = MeshBvh {
            tree,
            tris: Vec::new(),
            ids,
            part_starts,
            triangle_count,
        };
        bvh.tris = bvh
            .ids
            .par_chunks(LANES)
            .map(|lanes| {
                let mut packet = Tri4::EMPTY;
                for (lane, &id) in lanes.iter().enumerate() {
                    if id != NO_TRIANGLE {
                        let (part, prim) = bvh.locate(id);
                        let mesh = &parts[part as usize];
                        let tri = builder_vertices(mesh, &mesh.triangles[prim as usize]);
                        packet.set(lane, tri.map(Vec3A::from));
                    }
                }
                packet
            })
            .collect();
        bvh
    }

    /// The triangle in slot `k`, `None` for padding.
    pub(super) fn slot_triangle(&self, k: usize) -> Option<Tri> {
        self.tris.get(k / LANES)?.get(k % LANES)
    }

    /// Triangles it holds.
    pub fn triangle_count(&self) -> usize {
        self.triangle_count
    }

    /// The part and the triangle within it of global id `id`.
    pub(super) fn locate(&self, id: u32) -> (u32, u32) {
        let part = self
            .part_starts
            .partition_point(|&s| s <= id)
            .saturating_sub(1);
        (part as u32, id - self.part_starts[part])
    }

    /// Whether it holds no triangle (there were none, or none was valid).
    pub fn is_empty(&self) -> bool {
        self.triangle_count == 0
    }

    /// Bounds of its triangles, object space; empty when it holds none.
    pub fn bounds(&self) -> Aabb {
        self.tree.root_bounds.unwrap_or(Aabb::EMPTY)
    }

    /// Memory it holds, in bytes, for `--stats`.
    pub fn bytes(&self) -> usize {
        self.tree.nodes.len() * std::mem::size_of::<WideNode>()
            + self.tris.len() * std::mem::size_of::<Tri4>()
            + self.ids.len() * 4
            + self.part_starts.len() * 4
    }

    /// Closest hit with `t < *t_max` (in units of `ray.dir`); shrinks `*t_max` when found.
    /// `stack`: at least `STACK_MAX` entries of scratch space.
    #[inline(always)]
    pub fn closest<T: TriTest, I: Isa>(
        &self,
        isa: I,
        ray: &Ray,
        t_max: &mut f32,
        stack: &mut [Entry],
    ) -> Option<MeshHit> {
        let h = self.closest_slot::<T, I>(isa, ray, t_max, stack);
        self.mesh_hit(h)
    }

    /// [`Self::closest`] as the kernel leaves it: the hit's slot, not yet its triangle (the
    /// `ids` read and the part's binary search are left to [`Self::mesh_hit`], after the
    /// kernel has returned).
    #[inline(always)]
    pub fn closest_slot<T: TriTest, I: Isa>(
        &self,
        isa: I,
        ray: &Ray,
        t_max: &mut f32,
        stack: &mut [Entry],
    ) -> SlotHit {
        let wr = WideRay::new(ray);
        // Prepared in place and borrowed: moving it into the visitor was a copy of wide loads
        // over narrow stores just made (a failed store forward, ~5% of a primary ray's time
        // in `perf` on the Xeon).
        let pre = T::prepare(ray);
        let query = ClosestQuery::<T> {
            bvh: self,
            ray: &wr,
            pre: &pre,
            t_max,
            stack,
        };
        match isa.per_octant(wr.octant(), query) {
            Some((slot, u, v)) => SlotHit {
                t: *t_max,
                u,
                v,
                slot,
            },
            None => SlotHit::MISS,
        }
    }

    /// The triangle of a [`SlotHit`]; `None` for [`SlotHit::MISS`].
    #[inline(always)]
    pub fn mesh_hit(&self, h: SlotHit) -> Option<MeshHit> {
        let id = *self.ids.get(h.slot as usize)?;
        let (part, prim) = self.locate(id);
        Some(MeshHit {
            part,
            prim,
            u: h.u,
            v: h.v,
        })
    }

    /// Whether anything is hit with `t < t_max`; stops at the first hit found. `stack`: at
    /// least `STACK_MAX` entries of scratch space.
    #[inline(always)]
    pub fn any<T: TriTest, I: Isa>(
        &self,
        isa: I,
        ray: &Ray,
        t_max: f32,
        stack: &mut [Entry],
    ) -> bool {
        let wr = WideRay::new(ray);
        let pre = T::prepare(ray);
        let query = AnyQuery::<T> {
            bvh: self,
            ray: &wr,
            pre: &pre,
            t_max,
            stack,
        };
        isa.per_octant(wr.octant(), query)
    }

    /// The packets of the leaf whose slots are `first..first + count` (`first` a multiple of 4),
    /// counted as tested (`bvh-counters`).
    #[inline(always)]
    fn leaf_packets(&self, first: u32, count: u32) -> &[Tri4] {
        #[cfg(feature = "bvh-counters")]
        super::tally::counters::add(2, (count as usize).div_ceil(LANES) as u64);
        self.packets(first, count)
    }

    /// The packets of the leaf whose slots are `first..first + count`.
    #[inline(always)]
    fn packets(&self, first: u32, count: u32) -> &[Tri4] {
        let p = first as usize / LANES;
        &self.tris[p..p + (count as usize).div_ceil(LANES)]
    }
}

/// A closest-hit traversal of one bottom level, to run on an instruction set specialised per
/// octant: the nearest hit as (slot, u, v).
struct ClosestQuery<'a, T: TriTest> {
    bvh: &'a MeshBvh,
    ray: &'a WideRay,
    pre: &'a T::Prepared,
    t_max: &'a mut f32,
    stack: &'a mut [Entry],
}

impl<T: TriTest> OctantQuery for ClosestQuery<'_, T> {
    type Output = Option<(u32, f32, f32)>;
    #[inline(always)]
    fn run<I: Isa>(self, isa: I) -> Self::Output {
        let mut leaf = ClosestInLeaf::<T, I> {
            isa,
            bvh: self.bvh,
            pre: self.pre,
            best: None,
        };
        traverse(
            isa,
            &self.bvh.tree,
            self.ray,
            self.t_max,
            &mut leaf,
            self.stack,
        );
        leaf.best
    }
}

/// An any-hit traversal of one bottom level, as [`ClosestQuery`].
struct AnyQuery<'a, T: TriTest> {
    bvh: &'a MeshBvh,
    ray: &'a WideRay,
    pre: &'a T::Prepared,
    t_max: f32,
    stack: &'a mut [Entry],
}

impl<T: TriTest> OctantQuery for AnyQuery<'_, T> {
    type Output = bool;
    #[inline(always)]
    fn run<I: Isa>(self, isa: I) -> bool {
        let leaf = AnyInLeaf::<T, I> {
            isa,
            bvh: self.bvh,
            pre: self.pre,
        };
        let mut t = self.t_max;
        traverse(isa, &self.bvh.tree, self.ray, &mut t, leaf, self.stack)
    }
}

/// The closest-hit leaf test: the nearest hit so far as (slot, u, v).
struct ClosestInLeaf<'a, T: TriTest, I: Isa> {
    isa: I,
    bvh: &'a MeshBvh,
    pre: &'a T::Prepared,
    best: Option<(u32, f32, f32)>,
}

impl<T: TriTest, I: Isa> LeafVisitor for &mut ClosestInLeaf<'_, T, I> {
    #[inline(always)]
    fn visit(&mut self, first: u32, count: u32, t_max: &mut f32) -> bool {
        let tris = self.bvh.leaf_packets(first, count);
        if let Some((k, h)) = T::closest(self.isa, self.pre, t_max, tris) {
            // The slot, not the id: `ids` is read once, for the final hit only.
            self.best = Some((first + k as u32, h.u, h.v));
        }
        false
    }
    #[inline(always)]
    fn prefetch(&self, first: u32, count: u32) {
        self.isa.prefetch(self.bvh.packets(first, count));
    }
}

/// The any-hit leaf test.
struct AnyInLeaf<'a, T: TriTest, I: Isa> {
    isa: I,
    bvh: &'a MeshBvh,
    pre: &'a T::Prepared,
}

impl<T: TriTest, I: Isa> LeafVisitor for AnyInLeaf<'_, T, I> {
    #[inline(always)]
    fn visit(&mut self, first: u32, count: u32, t_max: &mut f32) -> bool {
        T::any(
            self.isa,
            self.pre,
            *t_max,
            self.bvh.leaf_packets(first, count),
        )
    }
    #[inline(always)]
    fn prefetch(&self, first: u32, count: u32) {
        self.isa.prefetch(self.bvh.packets(first, count));
    }
}

/// Gives every leaf of `tree` its own packets: the leaf's triangles (from the build's `order`)
/// at the next multiple-of-four slot, padded with [`NO_TRIANGLE`] to the packet's end, and the
/// leaf's `child` re-pointed there. Returns the ids of all slots.
fn pack_leaves(tree: &mut Wide, order: &[u32]) -> Vec<u32> {
    let mut ids = Vec::with_capacity(order.len() + order.len() / 2);
    let mut place = |first: &mut u32, count: u32| {
        let start = ids.len();
        let range = *first as usize..(*first + count) as usize;
        ids.extend_from_slice(&order[range]);
        ids.resize(
            start + (count as usize).div_ceil(LANES) * LANES,
            NO_TRIANGLE,
        );
        *first = start as u32;
    };
    if tree.nodes.is_empty() {
        if tree.root_count > 0 {
            place(&mut tree.root_first, tree.root_count);
        }
    } else {
        for node in &mut tree.nodes {
            for k in 0..WIDTH {
                if node.count[k] > 0 {
                    place(&mut node.child[k], node.count[k]);
                }
            }
        }
    }
    ids
}
