//! Light slabs: the plenoptic function of a box as a cache (Levoy and
//! Hanrahan's light fields).
//!
//! `brume slab bake` records, for a grid of lines through an axis-aligned box,
//! the radiance leaving the box along each line and the transmittance across
//! it; a `type = "slab"` shape then answers a ray entering the box from that
//! record instead of tracing it. This room holds what needs no tracing: the
//! parametrisation of lines ([`param`]), the file format ([`format`]) and the
//! lookup ([`lookup`]). The per-line estimate is in `integrator::slab_record`,
//! the parallel bake in `render::slab_bake` (rayon and progress live there).

pub mod format;
pub mod lookup;
pub mod param;

pub use format::{LightSlab, SlabHeader};
pub use lookup::{Filter, SlabShape};
pub use param::{Grid, Param};
