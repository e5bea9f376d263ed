//! Shapes, intersection records and the BVH (obvhs) over all primitives.

pub mod closed;
mod flat;
pub mod moving;
pub mod shapes;
pub mod slab;
mod ties;

pub use moving::MovingShape;
pub use shapes::{sphere_uv, AreaSample, Primitive, PrimitiveHit, QuadTest};

use crate::math::{Bounds3, Ray, Vec2, Vec3};
use obvhs::aabb::Aabb;
use obvhs::bvh2::{builder::build_bvh2, node::Bvh2Node, Bvh2};
use obvhs::faststack::{HeapStack, StackStack};
use obvhs::ray::{Ray as BvhRay, RayHit};
use obvhs::BvhBuildParams;
use slab::lookup::SlabCrossing;
use slab::SlabShape;

/// Smallest ray parameter accepted as a hit, relative to the scene scale.
const T_MIN: f32 = 0.0;

/// Up to this many primitives a scene has no BVH: a ray tests each one, as
/// a walk's root and child box tests would cost more.
const BRUTE_FORCE_PRIMITIVES: usize = 4;

/// At most this many primitives spanning half the scene or more (a ground
/// plane) stay out of the BVH and are tested by every ray first.
const MAX_LOOSE_PRIMITIVES: usize = 2;

/// The closest surface point found along a ray.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceHit {
    /// Ray parameter.
    pub t: f32,
    /// Position.
    pub p: Vec3,
    /// Unit geometric normal, as stored (not flipped).
    pub geometric_normal: Vec3,
    /// Unit shading normal, on the geometric normal's side.
    pub shading_normal: Vec3,
    /// Index of the primitive in `Geometry::primitives`.
    pub primitive: u32,
    /// Index of the scene shape the primitive belongs to.
    pub shape: u32,
    /// The primitive's surface parameters there (see [`PrimitiveHit::st`]).
    pub st: Vec2,
}

/// All primitives of a scene with their BVH.
pub struct Geometry {
    primitives: Vec<Primitive>,
    primitive_shape: Vec<u32>,
    /// Index of each primitive in the items it was built from: the order of
    /// the input, which the BVH's order must not show through (ties).
    source: Vec<u32>,
    /// Per-corner texture coordinates of each primitive (same order), or empty when no mesh has any.
    texcoords: Vec<[Vec2; 3]>,
    /// The BVH over `primitives[..in_bvh]`, unless `flat` holds them.
    bvh: Option<Bvh2>,
    /// A small scene's runs of `primitives[..in_bvh]`, tested in turn instead of a BVH (module `flat`).
    flat: flat::FlatRuns,
    /// Primitives in the BVH or the flat runs; those after them are tested by every ray (see `split_loose`).
    in_bvh: usize,
    /// Levels of the BVH, which bounds the traversal stack.
    depth: usize,
    /// Per primitive: its index in `quads` if it is a parallelogram, else `u32::MAX`.
    quad_index: Vec<u32>,
    /// The prepared ray tests of the parallelograms.
    quads: Vec<QuadTest>,
    bounds: Bounds3,
    /// Shapes moved by keyframes (none in a still scene).
    moving: Option<moving::MovingShapes>,
    /// Baked light slabs (`type = "slab"`): boxes answered from a record, not traced.
    slabs: Vec<SlabShape>,
    /// Per shape: the axes a sphere's texture coordinates are taken about
    /// (`[seam, pole, seam × pole]`), or `None` for the world's (X, Y, Z);
    /// empty when no sphere has its own.
    sphere_axes: Vec<Option<[Vec3; 3]>>,
}

/// Corner texture coordinates of a triangle without any: its barycentric parameters.
pub const BARYCENTRIC_UV: [Vec2; 3] = [Vec2::ZERO, Vec2::X, Vec2::Y];

struct Boxed(Bounds3);

impl obvhs::Boundable for Boxed {
    fn aabb(&self) -> Aabb {
        Aabb::new(self.0.min.into(), self.0.max.into())
    }
}

impl Geometry {
    /// Builds the BVH over `(primitive, shape index)` pairs; primitives are reordered for traversal.
    pub fn new(items: Vec<(Primitive, u32)>) -> Geometry {
        Geometry::with_texcoords(items, Vec::new())
    }

    /// [`Geometry::new`] with per-corner texture coordinates of each item
    /// (used by triangles; empty for none, else one entry per item).
    pub fn with_texcoords(items: Vec<(Primitive, u32)>, texcoords: Vec<[Vec2; 3]>) -> Geometry {
        assert!(texcoords.is_empty() || texcoords.len() == items.len());
        let bounds = items
            .iter()
            .fold(Bounds3::EMPTY, |acc, (p, _)| acc.union(&p.bounds()));
        let (tree, loose) = split_loose(&items, &bounds);
        let pad = ties::tie_breaking_pad(&bounds);
        let flat = flat_runs_of(&items, &tree, pad);
        let (bvh, order) = if tree.is_empty() || flat.is_some() {
            (None, tree.iter().copied().chain(loose).collect())
        } else {
            let boxes: Vec<Boxed> = tree
                .iter()
                .enumerate()
                .map(|(k, &i)| Boxed(ties::padded(items[i].0.bounds(), k, pad)))
                .collect();
            let mut build_time = std::time::Duration::ZERO;
            let bvh = build_bvh2(&boxes, BvhBuildParams::medium_build(), &mut build_time);
            // BVH leaf ranges index the primitives directly; the loose ones follow.
            let order = bvh.primitive_indices.iter().map(|&i| tree[i as usize]);
            let order: Vec<usize> = order.chain(loose).collect();
            (Some(bvh), order)
        };
        let (primitives, primitive_shape): (Vec<Primitive>, Vec<u32>) =
            order.iter().map(|&i| items[i]).unzip();
        let mut quads = Vec::new();
        let quad_index = primitives
            .iter()
            .map(|p| match *p {
                Primitive::Parallelogram {
                    corner,
                    edge_u,
                    edge_v,
                } => {
                    quads.push(QuadTest::new(corner, edge_u, edge_v));
                    quads.len() as u32 - 1
                }
                _ => u32::MAX,
            })
            .collect();
        let texcoords = if texcoords.is_empty() {
            texcoords
        } else {
            order.iter().map(|&i| texcoords[i]).collect()
        };
        Geometry {
            primitives,
            primitive_shape,
            source: order.iter().map(|&i| i as u32).collect(),
            texcoords,
            in_bvh: tree.len(),
            flat: flat.unwrap_or_default(),
            depth: bvh.as_ref().map_or(0, tree_depth),
            quad_index,
            quads,
            bvh,
            bounds,
            moving: None,
            slabs: Vec::new(),
            sphere_axes: Vec::new(),
        }
    }

    /// The same geometry with spheres' texture axes, indexed by shape.
    pub fn with_sphere_axes(mut self, axes: Vec<Option<[Vec3; 3]>>) -> Geometry {
        self.sphere_axes = match axes.iter().any(Option::is_some) {
            true => axes,
            false => Vec::new(),
        };
        self
    }

    /// The same geometry with baked light slabs beside the primitives.
    pub fn with_slabs(mut self, slabs: Vec<SlabShape>) -> Geometry {
        for s in &slabs {
            self.bounds = self.bounds.union(&s.bounds());
        }
        self.slabs = slabs;
        self
    }

    /// The baked light slabs.
    pub fn slabs(&self) -> &[SlabShape] {
        &self.slabs
    }

    /// The first slab box `ray` enters from outside before `t_max`, with the
    /// recorded light of its line (`None` in a scene without slabs).
    #[inline]
    pub fn slab_crossing(&self, ray: &Ray, t_max: f32) -> Option<SlabCrossing> {
        let mut best: Option<SlabCrossing> = None;
        for s in &self.slabs {
            let bound = best.map_or(t_max, |b| b.t_enter);
            if let Some(c) = s.crossing(ray, bound) {
                best = Some(c);
            }
        }
        best
    }

    /// The same geometry with `shapes` moved by keyframes beside the still primitives.
    pub fn with_moving(mut self, shapes: Vec<MovingShape>) -> Geometry {
        self.moving = moving::MovingShapes::new(shapes);
        if let Some(m) = &self.moving {
            self.bounds = self.bounds.union(&m.bounds());
        }
        self
    }

    /// The moving shape with scene index `shape`, if that shape moves.
    #[inline]
    pub fn moving_shape(&self, shape: u32) -> Option<&MovingShape> {
        self.moving.as_ref()?.get(shape)
    }

    /// Primitives in traversal order.
    pub fn primitives(&self) -> &[Primitive] {
        &self.primitives
    }

    /// Index of each primitive (same order as `primitives`) in the items the
    /// geometry was built from: a canonical order, whatever the BVH's.
    pub fn primitive_sources(&self) -> &[u32] {
        &self.source
    }

    /// Shape index of each primitive (same order as `primitives`).
    pub fn primitive_shapes(&self) -> &[u32] {
        &self.primitive_shape
    }

    /// Texture coordinates of the point `p` with surface parameters `st` on primitive `primitive`.
    ///
    /// A sphere is mapped lat-long ([`sphere_uv`]), a parallelogram [0, 1]²
    /// along its edges, a disk by (r / radius, φ / 2π), a triangle by interpolating its corners' coordinates
    /// with the barycentrics.
    #[inline]
    pub fn uv(&self, primitive: u32, st: Vec2, p: Vec3) -> Vec2 {
        let i = primitive as usize;
        match self.primitives[i] {
            Primitive::Sphere { center, radius } => {
                let n = (p - center) / radius;
                let shape = self.primitive_shape[i] as usize;
                match self.sphere_axes.get(shape).copied().flatten() {
                    Some([seam, pole, third]) => {
                        sphere_uv(Vec3::new(seam.dot(n), pole.dot(n), third.dot(n)))
                    }
                    None => sphere_uv(n),
                }
            }
            Primitive::Parallelogram { .. } | Primitive::Disk { .. } => st,
            Primitive::Triangle { .. } => {
                let t = self.texcoords.get(i).unwrap_or(&BARYCENTRIC_UV);
                t[0] * (1.0 - st.x - st.y) + t[1] * st.x + t[2] * st.y
            }
        }
    }

    /// Bounds of all primitives (moving ones over all times).
    pub fn bounds(&self) -> Bounds3 {
        self.bounds
    }

    /// Closest hit with `t < t_max` (moving shapes at the ray's time).
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<SurfaceHit> {
        count_ray();
        let still = self.intersect_still(ray, t_max);
        let Some(moving) = &self.moving else {
            return still;
        };
        moving
            .intersect(ray, still.map_or(t_max, |h| h.t))
            .or(still)
    }

    fn intersect_still(&self, ray: &Ray, t_max: f32) -> Option<SurfaceHit> {
        let mut best: Option<(PrimitiveHit, u32)> = None;
        // Hits at the same t (a ray through an edge) go to the primitive
        // first in the input, so the BVH's order cannot change the image:
        // the search bound stays just above the best t so that tied
        // primitives (and boxes entered exactly there) are still tested.
        let mut offer = |h: PrimitiveHit, id: u32| {
            let better = match &best {
                None => true,
                Some((b, bid)) => {
                    h.t < b.t
                        || (h.t == b.t && self.source[id as usize] < self.source[*bid as usize])
                }
            };
            if better {
                best = Some((h, id));
            }
            best.as_ref().map_or(t_max, |(b, _)| b.t.next_up())
        };
        let mut t_bound = t_max;
        // Loose primitives first: a hit on the ground prunes the walk.
        for id in self.in_bvh..self.primitives.len() {
            if let Some(h) = self.hit_primitive(id, ray, t_bound) {
                t_bound = offer(h, id as u32);
            }
        }
        if !self.flat.is_empty() {
            let lanes = flat::RayLanes::new(ray);
            self.flat.visit(&lanes, t_bound, |run, mut bound| {
                for id in run {
                    if let Some(h) = self.hit_primitive(id, ray, bound) {
                        bound = offer(h, id as u32);
                    }
                }
                Some(bound)
            });
        }
        if let Some(bvh) = &self.bvh {
            let bvh_ray = BvhRay::new(ray.origin.into(), ray.direction.into(), T_MIN, t_bound);
            self.traverse(bvh, bvh_ray, &mut RayHit::none(), |node, r, _| {
                for id in node.first_index..node.first_index + node.prim_count {
                    if let Some(h) = self.hit_primitive(id as usize, ray, r.tmax) {
                        r.tmax = offer(h, id);
                    }
                }
                true
            });
        }
        let (h, id) = best?;
        Some(SurfaceHit {
            t: h.t,
            p: ray.at(h.t),
            geometric_normal: h.geometric_normal,
            shading_normal: h.shading_normal,
            primitive: id,
            shape: self.primitive_shape[id as usize],
            st: h.st,
        })
    }

    /// Calls `hit(t, geometric_normal)` for every primitive the ray meets in `(0, t_max)`, in no order.
    pub fn for_each_hit(&self, ray: &Ray, t_max: f32, mut hit: impl FnMut(f32, Vec3)) {
        let mut each = |id: usize| {
            if let Some(h) = self.hit_primitive(id, ray, t_max) {
                hit(h.t, h.geometric_normal);
            }
        };
        self.flat.visit(&flat::RayLanes::new(ray), t_max, |run, t| {
            run.for_each(&mut each);
            Some(t)
        });
        (self.in_bvh..self.primitives.len()).for_each(each);
        let Some(bvh) = self.bvh.as_ref() else {
            return;
        };
        let bvh_ray = BvhRay::new(ray.origin.into(), ray.direction.into(), T_MIN, t_max);
        bvh.ray_traverse_anyhit(bvh_ray, |_, id| {
            if let Some(h) = self.hit_primitive(id, ray, t_max) {
                hit(h.t, h.geometric_normal);
            }
        });
    }

    /// True when anything blocks the ray before `t_max` (moving shapes at the ray's time).
    pub fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        count_ray();
        self.occluded_still(ray, t_max)
            || self.moving.as_ref().is_some_and(|m| m.occluded(ray, t_max))
    }

    fn occluded_still(&self, ray: &Ray, t_max: f32) -> bool {
        let blocks = |id: usize| {
            self.hit_primitive(id, ray, t_max)
                .is_some_and(|h| h.t < t_max)
        };
        if (self.in_bvh..self.primitives.len()).any(blocks) {
            return true;
        }
        if !self.flat.is_empty() {
            let mut blocked = false;
            self.flat
                .visit(&flat::RayLanes::new(ray), t_max, |mut run, t| {
                    blocked = run.any(blocks);
                    (!blocked).then_some(t)
                });
            return blocked;
        }
        let Some(bvh) = self.bvh.as_ref() else {
            return false;
        };
        let bvh_ray = BvhRay::new(ray.origin.into(), ray.direction.into(), T_MIN, t_max);
        let mut blocked = false;
        self.traverse(bvh, bvh_ray, &mut RayHit::none(), |node, r, _| {
            let ids = node.first_index..node.first_index + node.prim_count;
            blocked = ids.into_iter().any(|id| {
                self.hit_primitive(id as usize, ray, r.tmax)
                    .is_some_and(|h| h.t < r.tmax)
            });
            // Any blocker ends the traversal.
            !blocked
        });
        blocked
    }

    /// The hit of primitive `id` with parameter in `(T_MIN, t_max)`, by its prepared test.
    #[inline]
    fn hit_primitive(&self, id: usize, ray: &Ray, t_max: f32) -> Option<PrimitiveHit> {
        match self.quad_index[id] {
            u32::MAX => self.primitives[id].intersect(ray, T_MIN, t_max),
            q => self.quads[q as usize].intersect(ray, T_MIN, t_max),
        }
    }

    /// Walks the BVH with a stack of just the tree's depth: obvhs's own
    /// traversal zeroes a 96-slot stack for every ray (a `memset` per ray,
    /// 3% of a small scene's render).
    fn traverse<F>(&self, bvh: &Bvh2, ray: BvhRay, hit: &mut RayHit, leaf: F)
    where
        F: FnMut(&Bvh2Node, &mut BvhRay, &mut RayHit) -> bool,
    {
        match self.depth {
            0..=16 => {
                bvh.ray_traverse_dynamic(&mut StackStack::<u32, 16>::default(), ray, hit, leaf)
            }
            17..=32 => {
                bvh.ray_traverse_dynamic(&mut StackStack::<u32, 32>::default(), ray, hit, leaf)
            }
            33..=64 => {
                bvh.ray_traverse_dynamic(&mut StackStack::<u32, 64>::default(), ray, hit, leaf)
            }
            d => bvh.ray_traverse_dynamic(
                &mut HeapStack::<u32>::new_with_capacity(d),
                ray,
                hit,
                leaf,
            ),
        }
    }
}

thread_local! {
    // Per thread, so counting costs no shared cache line (see `thread_rays`).
    static RAYS: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
}

/// Rays this thread has traced through the geometry (closest hits and
/// occlusion tests), never reset: the adaptive pilot's count of a pixel's
/// work is the difference across its samples.
pub fn thread_rays() -> u64 {
    RAYS.with(|r| r.get())
}

#[inline]
fn count_ray() {
    RAYS.with(|r| r.set(r.get().wrapping_add(1)));
}

/// Which items go into the BVH and which are tested by every ray ("loose"),
/// as indices into `items`.
///
/// With at most [`BRUTE_FORCE_PRIMITIVES`] items all are loose. Otherwise the
/// [`MAX_LOOSE_PRIMITIVES`] largest whose box spans half the scene's diagonal
/// or more are: a ground plane's box holds the whole scene, so every ray
/// would enter it and the boxes above it in the tree; tested first, it
/// shortens the ray before the walk instead.
fn split_loose(items: &[(Primitive, u32)], scene: &Bounds3) -> (Vec<usize>, Vec<usize>) {
    if items.len() <= BRUTE_FORCE_PRIMITIVES {
        return (Vec::new(), (0..items.len()).collect());
    }
    let diagonal = |b: &Bounds3| (b.max - b.min).length();
    let half = 0.5 * diagonal(scene);
    let mut large: Vec<(f32, usize)> = items
        .iter()
        .enumerate()
        .map(|(i, (p, _))| (diagonal(&p.bounds()), i))
        .filter(|&(d, _)| d >= half)
        .collect();
    large.sort_by(|a, b| b.0.total_cmp(&a.0));
    large.truncate(MAX_LOOSE_PRIMITIVES);
    let mut loose: Vec<usize> = large.into_iter().map(|(_, i)| i).collect();
    loose.sort_unstable();
    let tree = (0..items.len())
        .filter(|i| loose.binary_search(i).is_err())
        .collect();
    (tree, loose)
}

/// The flat runs (module `flat`) of the items `tree`, in their order, where
/// there are few enough of them to test in turn; `None` for a BVH.
fn flat_runs_of(items: &[(Primitive, u32)], tree: &[usize], pad: f32) -> Option<flat::FlatRuns> {
    if tree.is_empty() {
        return None;
    }
    flat::flat_runs(tree.iter().map(|&i| (items[i].0.bounds(), items[i].1)), pad)
}

/// Number of node levels of `bvh` (a lone leaf root is 1): a traversal holds
/// at most one pending node per level.
fn tree_depth(bvh: &Bvh2) -> usize {
    let mut deepest = 0;
    let mut pending = vec![(0usize, 1usize)];
    while let Some((index, depth)) = pending.pop() {
        let Some(node) = bvh.nodes.get(index) else {
            continue;
        };
        deepest = deepest.max(depth);
        if !node.is_leaf() {
            let first = node.first_index as usize;
            pending.push((first, depth + 1));
            pending.push((first + 1, depth + 1));
        }
    }
    deepest
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The prepared parallelogram test finds what the general one finds:
    /// the same hits and misses away from the edges (a rounding's width), the
    /// same t and surface parameters to a few ulps, the same normal.
    #[test]
    fn prepared_parallelogram_test_matches_the_primitive() {
        let (corner, edge_u, edge_v) = (
            Vec3::new(0.3, -1.0, 2.0),
            Vec3::new(2.0, 0.5, -0.3),
            Vec3::new(-0.4, 0.2, 1.5),
        );
        let quad = Primitive::Parallelogram {
            corner,
            edge_u,
            edge_v,
        };
        let test = QuadTest::new(corner, edge_u, edge_v);
        let mut rng = crate::sampling::Sampler::from_seed(21);
        let mut hits = 0;
        for _ in 0..20_000 {
            let o = Vec3::new(rng.next_1d(), rng.next_1d(), rng.next_1d()) * 8.0 - 4.0;
            let target = corner
                + edge_u * (1.4 * rng.next_1d() - 0.2)
                + edge_v * (1.4 * rng.next_1d() - 0.2);
            let ray = Ray::new(o, (target - o).normalize());
            let a = quad.intersect(&ray, 0.0, f32::INFINITY);
            let b = test.intersect(&ray, 0.0, f32::INFINITY);
            match (a, b) {
                (Some(a), Some(b)) => {
                    hits += 1;
                    assert!(
                        (a.t - b.t).abs() <= 1e-5 * a.t.max(1.0),
                        "t {} vs {}",
                        a.t,
                        b.t
                    );
                    assert!(
                        (a.st - b.st).abs().max_element() <= 1e-5,
                        "st {} vs {}",
                        a.st,
                        b.st
                    );
                    assert!((a.geometric_normal - b.geometric_normal).length() <= 1e-6);
                }
                (None, None) => {}
                (a, b) => {
                    // Only a ray through an edge may differ, by rounding.
                    let st = a.or(b).unwrap().st;
                    let edge = st.min_element().min(1.0 - st.max_element());
                    assert!(edge.abs() < 1e-5, "hit {a:?} vs {b:?}");
                }
            }
        }
        assert!(hits > 8_000, "{hits} hits");
    }

    /// A 100 × 100 ground quad at y = 0, about the origin.
    fn ground_quad() -> Primitive {
        Primitive::Parallelogram {
            corner: Vec3::new(-50.0, 0.0, -50.0),
            edge_u: Vec3::new(100.0, 0.0, 0.0),
            edge_v: Vec3::new(0.0, 0.0, 100.0),
        }
    }

    /// Loose primitives (a ground plane), the BVH and the no-BVH path for a
    /// few primitives all find what testing every primitive finds: the same
    /// closest hit (primitive, t) and the same occlusion, for random rays.
    #[test]
    fn loose_and_few_primitives_find_the_closest_hit() {
        let ground = ground_quad();
        // No BVH (3), flat runs (8), a BVH (40).
        for count in [0usize, 3, 8, 40] {
            let mut items = vec![(ground, 0)];
            for i in 0..count {
                let a = i as f32 * 0.7;
                let center = Vec3::new(5.0 * a.cos(), 0.5 + 0.2 * i as f32, 5.0 * a.sin());
                items.push((
                    Primitive::Sphere {
                        center,
                        radius: 0.4,
                    },
                    i as u32 + 1,
                ));
            }
            let geometry = Geometry::new(items.clone());
            assert_eq!(geometry.primitives().len(), items.len());
            let mut rng = crate::sampling::Sampler::from_seed(9);
            for _ in 0..4000 {
                let o = Vec3::new(rng.next_1d(), rng.next_1d(), rng.next_1d()) * 16.0 - 8.0;
                let d = crate::sampling::warp::square_to_uniform_sphere(rng.next_2d());
                let ray = Ray::new(o + Vec3::Y * 8.0, d);
                let t_max = if rng.next_1d() < 0.5 {
                    6.0
                } else {
                    f32::INFINITY
                };
                let brute = items
                    .iter()
                    .filter_map(|(p, shape)| p.intersect(&ray, 0.0, t_max).map(|h| (h.t, *shape)))
                    .min_by(|a, b| a.0.total_cmp(&b.0));
                let found = geometry.intersect(&ray, t_max).map(|h| (h.t, h.shape));
                assert_eq!(found, brute, "{count} spheres, ray {ray:?}");
                assert_eq!(geometry.occluded(&ray, t_max), brute.is_some());
            }
        }
    }

    /// The six faces of an axis-aligned box of centre `c` and half-size `h`.
    fn box_faces(c: Vec3, h: Vec3) -> Vec<Primitive> {
        let mut faces = Vec::new();
        for axis in 0..3 {
            for sign in [-1.0f32, 1.0] {
                let (mut corner, mut edge_u, mut edge_v) = (c - h, Vec3::ZERO, Vec3::ZERO);
                corner[axis] = c[axis] + sign * h[axis];
                edge_u[(axis + 1) % 3] = 2.0 * h[(axis + 1) % 3];
                edge_v[(axis + 2) % 3] = 2.0 * h[(axis + 2) % 3];
                faces.push(Primitive::Parallelogram {
                    corner,
                    edge_u,
                    edge_v,
                });
            }
        }
        faces
    }

    /// A ground and a few boxes (each one shape of six faces: flat runs)
    /// answer as testing every face does, first face in the input winning a
    /// tie, for rays aimed anywhere and at the boxes' edges and corners.
    #[test]
    fn flat_runs_of_boxes_find_what_every_face_finds() {
        let ground = ground_quad();
        let mut items = vec![(ground, 0)];
        let mut corners = Vec::new();
        for i in 0..6 {
            let (c, h) = (
                Vec3::new(3.0 * i as f32 - 7.0, 1.0, -0.7 * i as f32),
                Vec3::splat(0.5 + 0.1 * i as f32),
            );
            items.extend(box_faces(c, h).into_iter().map(|f| (f, i + 1)));
            corners.extend([
                c + h,
                c - h,
                c + Vec3::new(h.x, -h.y, 0.0),
                c + Vec3::new(0.0, h.y, h.z),
            ]);
        }
        let geometry = Geometry::new(items.clone());
        assert!(geometry.bvh.is_none() && !geometry.flat.is_empty());
        let mut rng = crate::sampling::Sampler::from_seed(4);
        for k in 0..6000 {
            let o = Vec3::new(
                rng.next_1d() * 30.0 - 15.0,
                rng.next_1d() * 6.0 + 0.01,
                rng.next_1d() * 20.0 - 10.0,
            );
            let d = match k % 2 {
                0 => crate::sampling::warp::square_to_uniform_sphere(rng.next_2d()),
                _ => (corners[k % corners.len()] - o).normalize(),
            };
            let ray = Ray::new(o, d);
            let t_max = if k % 3 == 0 { 4.0 } else { f32::INFINITY };
            // Every face by the geometry's own test, ties to the first in the input.
            let sources = geometry.primitive_sources();
            let hits: Vec<(f32, u32, usize)> = (0..items.len())
                .filter_map(|id| {
                    let h = geometry.hit_primitive(id, &ray, t_max)?;
                    Some((h.t, geometry.primitive_shapes()[id], sources[id] as usize))
                })
                .collect();
            let brute = hits
                .iter()
                .copied()
                .min_by(|a, b| a.0.total_cmp(&b.0).then(a.2.cmp(&b.2)));
            let found = geometry.intersect(&ray, t_max).map(|h| {
                let id = h.primitive as usize;
                (h.t, h.shape, sources[id] as usize)
            });
            assert_eq!(found, brute, "ray {ray:?} to {t_max}");
            assert_eq!(geometry.occluded(&ray, t_max), brute.is_some());
            let mut all = 0;
            geometry.for_each_hit(&ray, t_max, |_, _| all += 1);
            let every = hits.len();
            assert_eq!(all, every, "ray {ray:?}");
        }
    }

    #[test]
    fn bvh_finds_closest_of_many_spheres() {
        let items: Vec<(Primitive, u32)> = (0..50)
            .map(|i| {
                (
                    Primitive::Sphere {
                        center: Vec3::new(0.0, 0.0, i as f32 * 3.0),
                        radius: 1.0,
                    },
                    i,
                )
            })
            .collect();
        let g = Geometry::new(items);
        let ray = Ray::new(Vec3::new(0.0, 0.0, -10.0), Vec3::Z);
        let hit = g.intersect(&ray, f32::INFINITY).unwrap();
        assert!((hit.t - 9.0).abs() < 1e-4);
        assert_eq!(hit.shape, 0);
        let from_middle = Ray::new(Vec3::new(0.0, 0.0, 31.5), Vec3::Z);
        let hit = g.intersect(&from_middle, f32::INFINITY).unwrap();
        assert_eq!(hit.shape, 11);
        assert!(g.occluded(&ray, 20.0));
        assert!(!g.occluded(&ray, 8.0));
        assert!(!g.occluded(&Ray::new(Vec3::new(5.0, 0.0, 0.0), Vec3::Z), 1e3));
    }

    /// Texture coordinates of the first hit along `ray`.
    fn uv_along(g: &Geometry, ray: Ray) -> Vec2 {
        let h = g.intersect(&ray, f32::INFINITY).unwrap();
        g.uv(h.primitive, h.st, h.p)
    }

    #[test]
    fn parallelogram_uv_spans_the_unit_square_along_its_edges() {
        let q = Primitive::Parallelogram {
            corner: Vec3::new(-1.0, -0.5, 0.0),
            edge_u: Vec3::new(2.0, 0.0, 0.0),
            edge_v: Vec3::new(0.0, 1.0, 0.0),
        };
        let g = Geometry::new(vec![(q, 0)]);
        for (x, y, u, v) in [
            (-0.99, -0.49, 0.005, 0.01),
            (0.98, 0.48, 0.99, 0.98),
            (0.5, -0.25, 0.75, 0.25),
            (-0.6, 0.4, 0.2, 0.9),
        ] {
            let ray = Ray::new(Vec3::new(x, y, 3.0), -Vec3::Z);
            let uv = uv_along(&g, ray);
            assert!((uv - Vec2::new(u, v)).length() < 1e-5, "({x},{y}): {uv}");
        }
        // Area samples carry the same parameters as hits there.
        let a = q.sample_area(Vec2::new(0.3, 0.8));
        assert!((g.uv(0, a.st, a.p) - Vec2::new(0.3, 0.8)).length() < 1e-6);
    }

    #[test]
    fn sphere_uv_is_lat_long() {
        let g = Geometry::new(vec![(
            Primitive::Sphere {
                center: Vec3::new(1.0, 2.0, 3.0),
                radius: 2.0,
            },
            0,
        )]);
        let c = Vec3::new(1.0, 2.0, 3.0);
        // From outside toward the centre: hits the point in direction -dir from it.
        let at = |n: Vec3| uv_along(&g, Ray::new(c + n * 10.0, -n));
        let close = |a: Vec2, b: Vec2| (a - b).length() < 1e-4;
        assert!(close(at(Vec3::X), Vec2::new(0.0, 0.5)) || close(at(Vec3::X), Vec2::new(1.0, 0.5)));
        assert!(close(at(Vec3::Z), Vec2::new(0.25, 0.5)), "{}", at(Vec3::Z));
        assert!(close(at(-Vec3::X), Vec2::new(0.5, 0.5)), "{}", at(-Vec3::X));
        assert!(
            close(at(-Vec3::Z), Vec2::new(0.75, 0.5)),
            "{}",
            at(-Vec3::Z)
        );
        assert!((at(Vec3::Y).y - 1.0).abs() < 1e-4 && at(-Vec3::Y).y.abs() < 1e-4);
        // 45° above the horizon toward +Z: θ = π/4.
        let n = Vec3::new(0.0, 1.0, 1.0).normalize();
        assert!(close(at(n), Vec2::new(0.25, 0.75)), "{}", at(n));
    }

    #[test]
    fn triangle_uv_interpolates_corner_coordinates_barycentrically() {
        let tri = Primitive::Triangle {
            p: [Vec3::ZERO, Vec3::X, Vec3::Y],
            n: [Vec3::ZERO; 3],
        };
        let corners = [
            Vec2::new(0.1, 0.2),
            Vec2::new(0.9, 0.3),
            Vec2::new(0.4, 1.0),
        ];
        // A second triangle without its own coordinates keeps barycentrics.
        let other = Primitive::Triangle {
            p: [
                Vec3::new(5.0, 0.0, 0.0),
                Vec3::new(6.0, 0.0, 0.0),
                Vec3::new(5.0, 1.0, 0.0),
            ],
            n: [Vec3::ZERO; 3],
        };
        let g = Geometry::with_texcoords(vec![(tri, 0), (other, 1)], vec![corners, BARYCENTRIC_UV]);
        for (b1, b2) in [
            (0.01, 0.01),
            (0.98, 0.01),
            (0.01, 0.98),
            (0.2, 0.5),
            (0.6, 0.1),
        ] {
            let p = Vec3::new(b1, b2, 0.0);
            let uv = uv_along(&g, Ray::new(p + Vec3::Z, -Vec3::Z));
            let want = corners[0] * (1.0 - b1 - b2) + corners[1] * b1 + corners[2] * b2;
            assert!((uv - want).length() < 1e-5, "({b1},{b2}): {uv} vs {want}");
            let uv = uv_along(&g, Ray::new(p + Vec3::new(5.0, 0.0, 1.0), -Vec3::Z));
            assert!((uv - Vec2::new(b1, b2)).length() < 1e-5);
        }
        // Area samples land where their parameters say.
        let a = tri.sample_area(Vec2::new(0.3, 0.6));
        assert!((Vec2::new(a.p.x, a.p.y) - a.st).length() < 1e-6);
    }

    #[test]
    fn empty_and_single_primitive_scenes() {
        let empty = Geometry::new(Vec::new());
        let ray = Ray::new(Vec3::ZERO, Vec3::Z);
        assert!(empty.intersect(&ray, f32::INFINITY).is_none());
        assert!(!empty.occluded(&ray, f32::INFINITY));
        let one = Geometry::new(vec![(
            Primitive::Sphere {
                center: Vec3::new(0.0, 0.0, 5.0),
                radius: 1.0,
            },
            7,
        )]);
        assert_eq!(one.intersect(&ray, f32::INFINITY).unwrap().shape, 7);
    }
}
