//! Closed triangle meshes as volumes: the closedness check made at load,
//! the crossings of a ray with the surface, and point containment.
//!
//! A mesh bounds a volume when it is closed and consistently oriented:
//! every edge (vertices welded by exact position) is shared by exactly two
//! triangles that traverse it in opposite directions. Then, along any ray,
//! crossings alternate between entering and leaving, and the facing of a
//! crossing (its geometric normal against the ray, signed by the mesh's
//! orientation) says which. The orientation is found from the signed
//! volume, so inward-wound meshes work too. The mesh must not intersect
//! itself (two overlapping closed pieces in one file do not make a union).

use super::{Geometry, Primitive};
use crate::math::{Ray, Vec3};
use std::collections::HashMap;

/// Most crossings of one ray with a closed mesh kept per query (see [`Crossings`]).
pub const MAX_CROSSINGS: usize = 32;

/// A closed, consistently oriented triangle mesh with its own BVH.
pub struct ClosedMesh {
    geometry: Geometry,
    /// +1 when the triangles' winding normals point outward, -1 when inward.
    orientation: f32,
}

impl std::fmt::Debug for ClosedMesh {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ClosedMesh")
            .field("triangles", &self.geometry.primitives().len())
            .field("orientation", &self.orientation)
            .finish()
    }
}

/// The nearest crossings of a ray with a closed mesh, sorted by t and, at
/// equal t, leaving before entering: the same list whatever order the BVH
/// finds them in.
#[derive(Clone, Copy, Debug)]
pub struct Crossings {
    /// Ray parameters, increasing; the first `len` are valid.
    pub t: [f32; MAX_CROSSINGS],
    /// Whether each crossing enters the volume.
    pub entering: [bool; MAX_CROSSINGS],
    /// Number of crossings kept.
    pub len: usize,
    /// True when the ray crossed the surface more than [`MAX_CROSSINGS`] times:
    /// only the nearest ones were kept.
    pub overflow: bool,
}

impl Crossings {
    /// The crossings as groups of equal t, each `(t, enters, leaves)`: a
    /// group with both passes along the surface (a silhouette edge, a
    /// crease) and changes nothing, whichever triangle was found first.
    pub fn groups(&self) -> impl Iterator<Item = (f32, bool, bool)> + '_ {
        let mut i = 0;
        std::iter::from_fn(move || {
            let t = *self.t[..self.len].get(i)?;
            let (mut enters, mut leaves) = (false, false);
            while i < self.len && self.t[i] == t {
                enters |= self.entering[i];
                leaves |= !self.entering[i];
                i += 1;
            }
            Some((t, enters, leaves))
        })
    }

    /// True when the ray starts inside: its first group of crossings that
    /// changes the state leaves the volume.
    pub fn starts_inside(&self) -> bool {
        self.groups()
            .find(|&(_, enters, leaves)| enters != leaves)
            .is_some_and(|(_, _, leaves)| leaves)
    }

    const EMPTY: Crossings = Crossings {
        t: [0.0; MAX_CROSSINGS],
        entering: [false; MAX_CROSSINGS],
        len: 0,
        overflow: false,
    };

    /// True when kept crossing `i` comes after `crossing` in the order of (t, entering).
    fn after(&self, i: usize, crossing: (f32, bool)) -> bool {
        (self.t[i], self.entering[i]) > crossing
    }

    /// Inserts a crossing, keeping the first [`MAX_CROSSINGS`] in the order
    /// of (t, entering), so that ties are kept and dropped by that order too.
    fn insert(&mut self, t: f32, entering: bool) {
        if self.len == MAX_CROSSINGS {
            self.overflow = true;
            if !self.after(MAX_CROSSINGS - 1, (t, entering)) {
                return;
            }
            self.len -= 1;
        }
        let mut i = self.len;
        while i > 0 && self.after(i - 1, (t, entering)) {
            self.t[i] = self.t[i - 1];
            self.entering[i] = self.entering[i - 1];
            i -= 1;
        }
        self.t[i] = t;
        self.entering[i] = entering;
        self.len += 1;
    }
}

impl ClosedMesh {
    /// Checks that `triangles` bound a volume and builds the mesh; the error says why not.
    pub fn new(triangles: Vec<Primitive>) -> Result<ClosedMesh, String> {
        check_closed(&triangles)?;
        let volume: f32 = triangles
            .iter()
            .map(|t| match t {
                Primitive::Triangle { p, .. } => p[0].dot(p[1].cross(p[2])) / 6.0,
                _ => 0.0,
            })
            .sum();
        if volume == 0.0 || !volume.is_finite() {
            return Err("the closed mesh encloses no volume".into());
        }
        Ok(ClosedMesh {
            geometry: Geometry::new(triangles.into_iter().map(|t| (t, 0)).collect()),
            orientation: volume.signum(),
        })
    }

    /// All crossings of `ray` with the surface at t > 0 (the nearest [`MAX_CROSSINGS`]).
    pub fn crossings(&self, ray: &Ray) -> Crossings {
        let mut out = Crossings::EMPTY;
        self.geometry.for_each_hit(ray, f32::INFINITY, |t, n| {
            out.insert(t, n.dot(ray.direction) * self.orientation < 0.0);
        });
        out
    }

    /// True when `p` lies inside: the nearest crossings along a fixed
    /// direction that all leave or all enter (see [`Crossings::starts_inside`]) leave.
    pub fn contains(&self, p: Vec3) -> bool {
        // Off every axis and diagonal, so that it rarely runs along an edge of a modelled mesh.
        const DIR: Vec3 = Vec3::new(0.485_071_2, 0.727_606_8, 0.485_071_2);
        self.crossings(&Ray::new(p, DIR)).starts_inside()
    }

    /// True when the triangles are wound counter-clockwise seen from outside (normals outward).
    pub fn is_outward(&self) -> bool {
        self.orientation > 0.0
    }

    /// Bounds of the mesh.
    pub fn bounds(&self) -> crate::math::Bounds3 {
        self.geometry.bounds()
    }
}

/// Every edge (vertices welded by exact position) must be used by exactly
/// two triangles, once in each direction.
fn check_closed(triangles: &[Primitive]) -> Result<(), String> {
    let key = |v: Vec3| [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()];
    let mut ids: HashMap<[u32; 3], u32> = HashMap::new();
    let mut id = |v: Vec3| {
        let n = ids.len() as u32;
        *ids.entry(key(v)).or_insert(n)
    };
    // Directed edge (a, b) -> number of times it is used.
    let mut edges: HashMap<(u32, u32), u32> = HashMap::new();
    let mut positions: HashMap<u32, Vec3> = HashMap::new();
    for tri in triangles {
        let Primitive::Triangle { p, .. } = tri else {
            return Err("only triangle meshes can be checked for closedness".into());
        };
        let v = [id(p[0]), id(p[1]), id(p[2])];
        for k in 0..3 {
            positions.insert(v[k], p[k]);
            *edges.entry((v[k], v[(k + 1) % 3])).or_insert(0) += 1;
        }
    }
    for (&(a, b), &count) in &edges {
        let back = edges.get(&(b, a)).copied().unwrap_or(0);
        if count != 1 || back != 1 {
            let (pa, pb) = (positions[&a], positions[&b]);
            let what = if back == 0 && count == 1 {
                "is used by only one triangle (the mesh has a hole)"
            } else if back == 0 || count > 1 {
                "is traversed twice in the same direction (inconsistent winding, or more than two triangles meet there)"
            } else {
                "is shared by more than two triangles"
            };
            return Err(format!(
                "not a closed mesh: the edge from {pa:?} to {pb:?} {what}; a shape with an \
                 interior needs every edge shared by exactly two consistently wound triangles"
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// The 12 triangles of the cube [-1, 1]³, wound outward when `outward`.
    pub(crate) fn cube(outward: bool) -> Vec<Primitive> {
        let c = |i: usize| {
            Vec3::new(
                if i & 1 == 0 { -1.0 } else { 1.0 },
                if i & 2 == 0 { -1.0 } else { 1.0 },
                if i & 4 == 0 { -1.0 } else { 1.0 },
            )
        };
        // Quads counter-clockwise seen from outside.
        let quads = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        let mut tris = Vec::new();
        for q in quads {
            for t in [[q[0], q[1], q[2]], [q[0], q[2], q[3]]] {
                let mut p = [c(t[0]), c(t[1]), c(t[2])];
                if !outward {
                    p.swap(1, 2);
                }
                tris.push(Primitive::Triangle {
                    p,
                    n: [Vec3::ZERO; 3],
                });
            }
        }
        tris
    }

    #[test]
    fn cube_crossings_alternate_and_contain_either_winding() {
        for outward in [true, false] {
            let mesh = ClosedMesh::new(cube(outward)).unwrap();
            let ray = Ray::new(Vec3::new(-3.0, 0.1, 0.2), Vec3::X);
            let c = mesh.crossings(&ray);
            assert_eq!(c.len, 2);
            assert!((c.t[0] - 2.0).abs() < 1e-6 && (c.t[1] - 4.0).abs() < 1e-6);
            assert!(c.entering[0] && !c.entering[1]);
            assert!(mesh.contains(Vec3::new(0.3, -0.2, 0.9)));
            assert!(!mesh.contains(Vec3::new(1.3, -0.2, 0.9)));
        }
    }

    #[test]
    fn open_or_badly_wound_meshes_are_refused() {
        let mut open = cube(true);
        open.pop();
        let e = ClosedMesh::new(open).unwrap_err();
        assert!(e.contains("only one triangle"), "{e}");
        let mut flipped = cube(true);
        if let Primitive::Triangle { p, .. } = &mut flipped[0] {
            p.swap(1, 2);
        }
        let e = ClosedMesh::new(flipped).unwrap_err();
        assert!(e.contains("same direction"), "{e}");
    }

    #[test]
    fn crossings_keep_the_nearest_when_full() {
        let mut c = Crossings::EMPTY;
        for i in (0..MAX_CROSSINGS + 5).rev() {
            c.insert(i as f32, i % 2 == 0);
        }
        assert!(c.overflow);
        assert_eq!(c.len, MAX_CROSSINGS);
        assert!((0..MAX_CROSSINGS).all(|i| c.t[i] == i as f32 && c.entering[i] == (i % 2 == 0)));
    }
}
