//! The BVH invariant checker: run after every build in debug builds and callable from tests.
//!
//! For every level: each node is reached exactly once from the root and has at least two
//! children, each child box lies in its parent's and contains its subtree's (interior) or its
//! primitives' (leaf) bounds, leaves hold 1..=MAX_LEAF primitives,
//! every primitive slot is referenced by exactly one leaf, the depth is within the traversal
//! stack, and the leaf order is a permutation without repeats.

use glam::Vec3;

use super::mesh_bvh::{triangle_vertices, MeshBvh};
use super::node::{MAX_DEPTH, MAX_LEAF};
use super::traverse::STACK_MAX;
use super::two_level::TwoLevel;
use super::wide::{Wide, WIDTH};
use super::MeshRef;
use crate::geom::triangle4::LANES;
use crate::geom::Aabb;

/// Checks one wide hierarchy whose leaves refer to `slots` primitive slots; `prim_bounds(k)`
/// gives the bounds of the primitive in slot `k`, `None` for a padding slot, which no leaf may
/// hold.
fn check_nodes(
    what: &str,
    w: &Wide,
    slots: usize,
    prim_bounds: impl Fn(usize) -> Option<Aabb>,
) -> Result<(), String> {
    let mut slot_seen: Vec<bool> = (0..slots).map(|k| prim_bounds(k).is_none()).collect();
    let mut leaf = |first: usize, count: usize, b: &Aabb| -> Result<(), String> {
        if count == 0 || count > MAX_LEAF as usize || first + count > slots {
            return Err(format!("{what}: leaf holds {first}+{count} of {slots}"));
        }
        for (k, seen) in slot_seen.iter_mut().enumerate().skip(first).take(count) {
            if std::mem::replace(seen, true) {
                return Err(format!(
                    "{what}: primitive slot {k} in two leaves, or a padding slot in one"
                ));
            }
            if !prim_bounds(k).is_some_and(|p| b.contains(&p)) {
                return Err(format!("{what}: a leaf does not contain primitive {k}"));
            }
        }
        Ok(())
    };
    match (w.nodes.is_empty(), w.root_count, w.root_bounds) {
        (true, 0, None) => {}
        (true, n, Some(b)) if n > 0 => leaf(w.root_first as usize, n as usize, &b)?,
        (false, 0, Some(_)) => {
            let mut reached = vec![false; w.nodes.len()];
            let mut stack = vec![(0usize, 1usize, w.root_bounds)];
            while let Some((i, depth, parent)) = stack.pop() {
                let n = w
                    .nodes
                    .get(i)
                    .ok_or_else(|| format!("{what}: link to node {i} past the end"))?;
                if std::mem::replace(&mut reached[i], true) {
                    return Err(format!("{what}: node {i} reached twice"));
                }
                if depth > MAX_DEPTH {
                    return Err(format!("{what}: depth {depth} exceeds {MAX_DEPTH}"));
                }
                let used = (0..WIDTH).filter(|&k| n.used(k)).count();
                if used < 2 {
                    return Err(format!("{what}: node {i} has {used} children"));
                }
                for k in (0..WIDTH).filter(|&k| n.used(k)) {
                    let b = n.child_bounds(k);
                    if !parent.is_some_and(|p| p.contains(&b)) {
                        return Err(format!("{what}: node {i} child {k} outside its parent"));
                    }
                    match n.count[k] {
                        0 => stack.push((n.child[k] as usize, depth + 1, Some(b))),
                        c => leaf(n.child[k] as usize, c as usize, &b)?,
                    }
                }
            }
            if let Some(i) = reached.iter().position(|r| !r) {
                return Err(format!("{what}: node {i} unreachable"));
            }
            if w.stack_need > STACK_MAX {
                return Err(format!("{what}: needs a stack of {}", w.stack_need));
            }
        }
        _ => return Err(format!("{what}: inconsistent root")),
    }
    if let Some(k) = slot_seen.iter().position(|s| !s) {
        return Err(format!("{what}: primitive slot {k} in no leaf"));
    }
    Ok(())
}

fn check_permutation(what: &str, order: &[u32], n: usize) -> Result<(), String> {
    let mut seen = vec![false; n];
    for &p in order {
        let s = seen
            .get_mut(p as usize)
            .ok_or_else(|| format!("{what}: primitive {p} out of range"))?;
        if std::mem::replace(s, true) {
            return Err(format!("{what}: primitive {p} referenced twice"));
        }
    }
    Ok(())
}

/// Checks a bottom-level BVH against the meshes (parts) it was built from.
pub fn check_mesh(bvh: &MeshBvh, parts: &[MeshRef<'_>], what: &str) -> Result<(), String> {
    let total: usize = parts.iter().map(|m| m.triangles.len()).sum();
    let held: Vec<u32> = bvh
        .ids
        .iter()
        .copied()
        .filter(|&id| id != u32::MAX)
        .collect();
    check_permutation(what, &held, total)?;
    if bvh.ids.len() != bvh.tris.len() * LANES
        || held.len() != bvh.triangle_count()
        || bvh.part_starts.len() != parts.len()
    {
        return Err(format!("{what}: array lengths disagree"));
    }
    let mut valid = 0;
    let mut start = 0;
    for (k, mesh) in parts.iter().enumerate() {
        if bvh.part_starts[k] as usize != start {
            return Err(format!("{what}: part {k} starts at {}", bvh.part_starts[k]));
        }
        start += mesh.triangles.len();
        valid += mesh
            .triangles
            .iter()
            .filter(|t| triangle_vertices(mesh, t).is_some())
            .count();
    }
    // Every triangle with valid vertices must be in the tree, and only those.
    if valid != held.len() {
        return Err(format!("{what}: {} of {valid} valid triangles", held.len()));
    }
    for (k, &id) in bvh.ids.iter().enumerate() {
        let stored = bvh.slot_triangle(k).map(|t| t.map(Vec3::from));
        if id == u32::MAX {
            if stored.is_some() {
                return Err(format!("{what}: padding slot {k} holds a triangle"));
            }
            continue;
        }
        let (part, prim) = bvh.locate(id);
        let mesh = &parts[part as usize];
        let t = &mesh.triangles[prim as usize];
        if triangle_vertices(mesh, t) != stored {
            return Err(format!(
                "{what}: slot {k} does not hold triangle {prim} of part {part}"
            ));
        }
    }
    check_nodes(what, &bvh.tree, bvh.ids.len(), |k| {
        bvh.slot_triangle(k)
            .map(|t| Aabb::from_points(&t.map(Vec3::from)))
    })
}

/// Checks every bottom-level BVH against its meshes and the top level against the instances;
/// the first broken invariant, described, if any.
pub fn check_two_level(t: &TwoLevel, meshes: &[MeshRef<'_>]) -> Result<(), String> {
    for p in &t.placed {
        let bvh = &t.meshes[p.group as usize];
        let parts: Vec<MeshRef<'_>> = if p.merged {
            t.merged_meshes
                .iter()
                .map(|&i| meshes.get(i as usize).copied())
                .collect::<Option<_>>()
                .ok_or("merged group names a missing mesh")?
        } else {
            vec![*meshes
                .get(p.group as usize)
                .ok_or_else(|| format!("instance {} names a missing mesh", p.index))?]
        };
        check_mesh(bvh, &parts, &format!("group {}", p.group))?;
    }
    check_permutation("top level", &t.top_order, t.placed.len())?;
    if t.top_order.len() != t.placed.len() {
        return Err("top level: not every instance is in the tree".to_string());
    }
    check_nodes("top level", &t.top, t.top_order.len(), |k| {
        Some(t.placed[t.top_order[k] as usize].world_bounds)
    })
}
