//! Single-spike property test of the majorant grid (`medium::majorant_grid`).
//!
//! A grid that is zero but for one voxel of value 1 (a spike), or one but for
//! one voxel of value 0 (a hole), placed at every position relative to the
//! majorant cell boundaries (first, second, last voxel of a cell, the voxel
//! just past it). A trilinear lookup at p reads voxels ⌊p⌋ and ⌊p⌋ + 1 per
//! axis, so the spike reaches every cell within one voxel of it, including
//! the cell whose far face (the "+1 corner" of its support) touches it. For
//! every cell, every lookup in it must lie within [cell min, cell max].
//!
//! The spike's trilinear footprint is a product of one tent per axis, so its
//! largest value in a cell is at the cell's point nearest the spike (and the
//! hole's smallest value likewise): checking that one point per cell, plus a
//! lattice of others, checks every lookup in the cell.

use brume::medium::majorant_grid::MajorantGrid;
use brume::volume::{FloatGrid, GridTransform};
use glam::{DVec3, IVec3, Vec3};

/// Cell size in voxels (the medium's default is 8..=32).
const CELL: i32 = 8;
/// Grid origin: unaligned with the cells and with VDB bricks, negative.
const ORIGIN: IVec3 = IVec3::new(-5, 3, -11);
/// Three cells along each axis, plus the one-voxel margins.
const DIMS: IVec3 = IVec3::new(3 * CELL + 2, 3 * CELL + 2, 3 * CELL + 2);

/// A grid of `fill` everywhere but `value` on the voxel box [b0, b1].
fn box_grid(b0: IVec3, b1: IVec3, fill: f32, value: f32) -> FloatGrid {
    let mut values = Vec::with_capacity((DIMS.x * DIMS.y * DIMS.z) as usize);
    for z in 0..DIMS.z {
        for y in 0..DIMS.y {
            for x in 0..DIMS.x {
                let ijk = ORIGIN + IVec3::new(x, y, z);
                let inside = b0.cmple(ijk).all() && ijk.cmple(b1).all();
                values.push(if inside { value } else { fill });
            }
        }
    }
    let t = GridTransform::scale_translate("ScaleMap", DVec3::ONE, DVec3::ZERO).unwrap();
    FloatGrid::from_dense("spike", ORIGIN, DIMS, &values, t).unwrap()
}

/// The index range [a, b) of cell `c` in a grid built from `lo`.
fn cell_range(lo: Vec3, c: IVec3) -> (Vec3, Vec3) {
    let a = lo + c.as_vec3() * CELL as f32;
    (a, a + Vec3::splat(CELL as f32))
}

/// The point of cell `c` nearest the box [t0, t1] (just inside the cell's open
/// far faces), where a box's tensor-product footprint is largest, and a lattice.
fn probe_points(lo: Vec3, c: IVec3, t0: Vec3, t1: Vec3) -> Vec<Vec3> {
    let (a, b) = cell_range(lo, c);
    // just below the far face: a few f32 steps, so the point stays in this cell
    let inside_b = b - b.abs().max(Vec3::ONE) * 4.0 * f32::EPSILON;
    let mut points = vec![t0.max(a).min(t1).clamp(a, inside_b)];
    // A DDA's f32 segment ends put lookups a few ulps outside the cell: the
    // support's extra voxel on each side covers them (module doc).
    let slack = a.abs().max(b.abs()).max(Vec3::ONE) * 4.0 * f32::EPSILON;
    points.push(t0.max(a - slack).min(t1).clamp(a - slack, b + slack));
    points.push(t1.min(b + slack).max(t0).clamp(a - slack, b + slack));
    for i in 0..=4 {
        for j in 0..=4 {
            for k in 0..=4 {
                let u = Vec3::new(i as f32, j as f32, k as f32) / 4.0;
                points.push((a + (b - a) * u).min(inside_b));
            }
        }
    }
    points
}

/// Checks every cell of the majorants of `grid` built from `lo`, where the
/// grid differs from its fill on [b0, b1]; returns the violations.
fn violations(grid: &FloatGrid, lo: Vec3, b0: IVec3, b1: IVec3) -> Vec<String> {
    let hi = lo + (3 * CELL) as f32;
    let m = MajorantGrid::build(grid, lo, hi, Vec3::splat(CELL as f32));
    assert_eq!(m.dims(), IVec3::splat(3));
    let mut bad = Vec::new();
    for z in 0..3 {
        for y in 0..3 {
            for x in 0..3 {
                let c = IVec3::new(x, y, z);
                let (min, max) = m.bounds(c);
                for p in probe_points(lo, c, b0.as_vec3(), b1.as_vec3()) {
                    let v = grid.trilinear_index(p).max(0.0);
                    if v > max || v < min {
                        bad.push(format!(
                            "box {b0}..{b1} lo {lo}: cell {c} [{min}, {max}] but lookup {v} at {p}"
                        ));
                    }
                }
            }
        }
    }
    bad
}

/// Spike positions: every voxel from one before a cell boundary to one after the next.
fn spike_positions(lo: Vec3) -> Vec<IVec3> {
    // voxels near the boundary between cells 0 and 1, and 1 and 2, per axis
    let b1 = (lo + Vec3::splat(CELL as f32)).floor().as_ivec3();
    let offsets = [-2, -1, 0, 1, CELL - 1, CELL, CELL + 1];
    let mut out = Vec::new();
    for &ox in &offsets {
        for &oy in &offsets {
            for &oz in &offsets {
                out.push(b1 + IVec3::new(ox, oy, oz));
            }
        }
    }
    out
}

fn check(fill: f32, value: f32) {
    // integer corner (as GridMedium builds it: the active box widened by a voxel)
    // and a fractional one (the build accepts any index box)
    let base = (ORIGIN - IVec3::ONE).as_vec3();
    let mut bad = Vec::new();
    for lo in [base, base + Vec3::new(0.375, 0.5, 0.875)] {
        for spike in spike_positions(lo) {
            let grid = box_grid(spike, spike, fill, value);
            bad.extend(violations(&grid, lo, spike, spike));
        }
    }
    assert_none(&bad);
}

fn assert_none(bad: &[String]) {
    assert!(
        bad.is_empty(),
        "{} violations, first:\n{}",
        bad.len(),
        bad.iter().take(8).cloned().collect::<Vec<_>>().join("\n")
    );
}

/// Every lookup in a cell is at most the cell's majorant, wherever the spike is.
#[test]
fn a_single_spike_stays_under_every_cell_majorant() {
    check(0.0, 1.0);
}

/// Every lookup in a cell is at least the cell's minimum, wherever the hole is.
#[test]
fn a_single_hole_stays_over_every_cell_minimum() {
    check(1.0, 0.0);
}

/// A uniform 8³ brick (bounded per block, not per voxel) at every offset of the
/// cell lattice: every lookup in a cell is at most the cell's majorant.
#[test]
fn a_single_uniform_brick_stays_under_every_cell_majorant() {
    // the brick at the grid's middle brick [0, 7] × [8, 15] × [0, 7]; shift the cells across it
    let (b0, b1) = (IVec3::new(0, 8, 0), IVec3::new(7, 15, 7));
    let grid = box_grid(b0, b1, 0.0, 1.0);
    let mut bad = Vec::new();
    for d in -(CELL + 1)..=1 {
        for frac in [0.0, 0.5] {
            // cell 1 starts at b0 + d (+ frac): the brick crosses each of its faces in turn
            let lo = (b0 + IVec3::splat(d - CELL)).as_vec3() + frac;
            bad.extend(violations(&grid, lo, b0, b1));
        }
    }
    assert_none(&bad);
}

/// The bounds are tight enough to matter: cells the spike cannot reach keep majorant 0.
#[test]
fn cells_beyond_the_spike_reach_keep_a_zero_majorant() {
    let lo = (ORIGIN - IVec3::ONE).as_vec3();
    // the middle of cell (0, 0, 0): two voxels or more from every other cell
    let spike = (lo + Vec3::splat(CELL as f32 / 2.0)).as_ivec3();
    let grid = box_grid(spike, spike, 0.0, 1.0);
    let m = MajorantGrid::build(&grid, lo, lo + (3 * CELL) as f32, Vec3::splat(CELL as f32));
    assert!(m.bounds(IVec3::ZERO).1 >= 1.0);
    assert_eq!(m.bounds(IVec3::new(2, 2, 2)), (0.0, 0.0));
}

/// The same from the other end: a spike in the last cell leaves the first at 0
/// (the cells a brick voxel reaches are found from both sides of the voxel).
#[test]
fn cells_before_the_spike_reach_keep_a_zero_majorant() {
    let lo = (ORIGIN - IVec3::ONE).as_vec3();
    let spike = (lo + Vec3::splat(2.5 * CELL as f32)).as_ivec3();
    let grid = box_grid(spike, spike, 0.0, 1.0);
    let m = MajorantGrid::build(&grid, lo, lo + (3 * CELL) as f32, Vec3::splat(CELL as f32));
    assert!(m.bounds(IVec3::splat(2)).1 >= 1.0);
    assert_eq!(m.bounds(IVec3::ZERO), (0.0, 0.0));
}

/// Over a constant density the bounds are that constant, widened only by the
/// documented rounding pad (2⁻²⁰ relative), not by a loose factor.
#[test]
fn a_constant_density_is_bounded_within_the_rounding_pad() {
    let lo = (ORIGIN - IVec3::ONE).as_vec3();
    let c = 0.75f32;
    // one voxel in a far corner differs, so the voxels are stored per voxel, not as a tile
    let corner = ORIGIN + DIMS - IVec3::ONE;
    let grid = box_grid(corner, corner, c, 0.5);
    let m = MajorantGrid::build(&grid, lo, lo + (3 * CELL) as f32, Vec3::splat(CELL as f32));
    // the middle cell's support lies inside the constant part of the grid
    let (min, max) = m.bounds(IVec3::ONE);
    let pad = 2.0f32.powi(-20);
    assert!(
        max >= c && max <= c * (1.0 + 2.0 * pad),
        "max {max} is not {c} widened by at most the pad"
    );
    assert!(
        min <= c && min >= c * (1.0 - 2.0 * pad),
        "min {min} is not {c} narrowed by at most the pad"
    );
}

/// A uniform brick (bounded per block) leaves the cells it cannot reach at 0.
#[test]
fn cells_beyond_a_uniform_brick_keep_a_zero_majorant() {
    let (b0, b1) = (IVec3::new(0, 8, 0), IVec3::new(7, 15, 7));
    let grid = box_grid(b0, b1, 0.0, 1.0);
    // cell 1 = [1, 9) per axis from the brick's corner: cell 2 starts two voxels
    // past the brick's last one, beyond the one-voxel guard of its support
    let lo = (b0 - IVec3::splat(CELL - 1)).as_vec3();
    let m = MajorantGrid::build(&grid, lo, lo + (3 * CELL) as f32, Vec3::splat(CELL as f32));
    assert!(m.bounds(IVec3::ONE).1 >= 1.0);
    assert_eq!(m.bounds(IVec3::splat(2)), (0.0, 0.0));
}

/// A varying brick is bounded voxel by voxel: a cell that overlaps the
/// spike's 8³ brick but lies beyond the spike's reach keeps majorant 0 (a
/// bound per brick would give it the spike's value).
#[test]
fn a_varying_brick_is_bounded_per_voxel() {
    let lo = (ORIGIN - IVec3::ONE).as_vec3();
    // lo = (-6, 2, -12): cell faces at x = 2, y = 10, z = 4 cut the bricks
    // [0, 7] × [8, 15] × [0, 7] that hold the spike (7, 14, 0), inside cell (1, 1, 1)
    let spike = IVec3::new(7, 14, 0);
    let grid = box_grid(spike, spike, 0.0, 1.0);
    let m = MajorantGrid::build(&grid, lo, lo + (3 * CELL) as f32, Vec3::splat(CELL as f32));
    assert!(m.bounds(IVec3::ONE).1 >= 1.0);
    // cell (0, 1, 1) spans x ∈ [-6, 2), so its support ends at voxel 3, four short of the spike;
    // cell (1, 1, 2) spans z ∈ [4, 12), its support starts at voxel 3
    for c in [IVec3::new(0, 1, 1), IVec3::new(1, 1, 2)] {
        assert_eq!(m.bounds(c), (0.0, 0.0), "cell {c}");
    }
}

/// A uniform brick ending one voxel below the grid's corner along x is still
/// seen by the first cells (through their guard voxel, for lookups a few
/// ulps below the corner), however the block range is computed.
#[test]
fn a_brick_just_below_the_grid_corner_reaches_the_first_cells() {
    let (b0, b1) = (IVec3::new(0, 8, 0), IVec3::new(7, 15, 7));
    let grid = box_grid(b0, b1, 0.0, 1.0);
    let lo = Vec3::new(b1.x as f32 + 1.0, 0.0, -(CELL as f32));
    assert_none(&violations(&grid, lo, b0, b1));
}

/// Dilation for motion blur zeroes the minimum of exactly the cells that reach
/// past `inside`, then filters along each axis: over a constant density, the
/// cells whose whole neighbourhood lies inside keep the constant as their minimum.
/// `inside` cuts a different side along y and z, so that a cell's y and z,
/// recovered from its linear index, cannot stand in for each other.
#[test]
fn dilation_zeroes_the_minimum_of_exactly_the_cells_outside() {
    // 4-voxel cells two voxels into the grid: every cell's support is constant
    let cell = 4.0;
    let lo = (ORIGIN + IVec3::splat(2)).as_vec3();
    let hi = lo + 3.0 * cell;
    let c = 0.75f32;
    let corner = ORIGIN + DIMS - IVec3::ONE;
    let grid = box_grid(corner, corner, c, 0.5);
    let m = MajorantGrid::build(&grid, lo, hi, Vec3::splat(cell));
    assert_eq!(m.dims(), IVec3::splat(3));
    let still = m.bounds(IVec3::ONE).0;
    assert!(still > 0.5 * c);
    // the top layer in y and the bottom layer in z reach past `inside`; dilate
    // by one cell along x only
    let inside = (
        Vec3::new(lo.x, lo.y, lo.z + cell),
        Vec3::new(hi.x, hi.y - cell, hi.z),
    );
    let d = m.dilated(IVec3::new(1, 0, 0), inside);
    for x in 0..3 {
        for y in 0..3 {
            for z in 0..3 {
                let cell = IVec3::new(x, y, z);
                // x = 0 and 2 see a neighbour beyond the grid (density 0 for the minimum)
                let want = if x == 1 && y < 2 && z > 0 { still } else { 0.0 };
                assert_eq!(d.bounds(cell).0, want, "cell {cell}");
                assert!(d.bounds(cell).1 >= c, "cell {cell}");
            }
        }
    }
}

/// A uniform brick that the grid's corner cuts, with the corner at positive
/// coordinates: the first cells still see it (the range of cells a block
/// reaches is taken relative to the corner, whatever its sign).
#[test]
fn a_brick_above_a_positive_grid_corner_reaches_its_cells() {
    let (b0, b1) = (IVec3::new(0, 8, 0), IVec3::new(7, 15, 7));
    let grid = box_grid(b0, b1, 0.0, 1.0);
    // cell (·, 0, ·) spans y ∈ [10, 18): the brick's upper part [10, 15]
    let lo = Vec3::new(-(CELL as f32), 10.0, -(CELL as f32));
    assert_none(&violations(&grid, lo, b0, b1));
}

/// With cell faces half-way between voxel centres a cell's support is
/// cell + 2 voxels, one beyond each face and no more: a spike on the first or
/// last voxel of it raises the cell, a spike one voxel further leaves it at 0.
#[test]
fn half_voxel_cells_reach_exactly_one_voxel_beyond_each_face() {
    let base = ORIGIN + IVec3::splat(4);
    let lo = base.as_vec3() + 0.5;
    // cell (0, 1, 1) spans x ∈ [base + 0.5, base + 8.5): support x ∈ [base, base + 9]
    let mid = base + IVec3::new(0, CELL + 3, CELL + 3);
    for (dx, reaches) in [(-1, false), (0, true), (CELL + 1, true), (CELL + 2, false)] {
        let spike = mid + IVec3::new(dx, 0, 0);
        let grid = box_grid(spike, spike, 0.0, 1.0);
        let m = MajorantGrid::build(&grid, lo, lo + (3 * CELL) as f32, Vec3::splat(CELL as f32));
        let (_, max) = m.bounds(IVec3::new(0, 1, 1));
        assert_eq!(
            max > 0.0,
            reaches,
            "spike at x = base {dx:+}: cell max {max}"
        );
    }
}

/// Grid media put their majorant cells' faces half-way between voxel centres.
#[test]
fn grid_media_align_cells_to_half_voxels() {
    use brume::math::color::Rgb;
    use brume::math::Affine3A;
    use brume::medium::{GridEmission, GridMedium, GridMediumParams, PhaseFunction};
    let grid = box_grid(ORIGIN + 3, ORIGIN + 9, 0.0, 1.0);
    let params = GridMediumParams {
        to_world: Affine3A::IDENTITY,
        density_scale: 1.0,
        sigma_t_scale: Rgb::WHITE,
        albedo: Rgb::splat(0.8),
        phase: PhaseFunction::Isotropic,
        emission: GridEmission::None,
        majorant: Default::default(),
        cell_size: Some(4),
    };
    let medium = GridMedium::new(grid, params);
    let (lo, _) = medium.majorant_grid().extent();
    assert_eq!(lo - lo.floor(), Vec3::splat(0.5), "grid corner {lo}");
}
