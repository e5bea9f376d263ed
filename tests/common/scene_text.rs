//! Scene text for the tests, written block by block: the camera, integrator,
//! light and ground blocks that many tests need, so that each test spells
//! out only what makes its scene special. The result is plain TOML, read by
//! `scene_from_str` or written to a file for the command line.
//!
//! Values (numbers and arrays of them, f32 or f64) are written as Rust's
//! `{:?}` writes them (`1.0`, `[0.0, 1.0, 4.0]`, `[6, 6]`), which TOML reads
//! as the same numbers; a table gets exactly the keys given, so every other
//! key keeps its documented default.

use std::fmt::{self, Debug, Display, Write};

/// A scene's TOML text, one table after another.
#[derive(Clone, Debug, Default)]
pub struct SceneText {
    text: String,
}

impl SceneText {
    /// A scene whose `[camera]` stands at `position`, looks at `look_at` and has `resolution` pixels.
    pub fn camera(position: impl Debug, look_at: impl Debug, resolution: [u32; 2]) -> Self {
        Self::default().table(
            "[camera]",
            &format!("position = {position:?}\nlook_at = {look_at:?}\nresolution = {resolution:?}"),
        )
    }

    /// A scene whose `[camera]` stands at `position` and looks at `look_at`,
    /// at the default resolution: for tests that trace their own rays.
    pub fn view(position: impl Debug, look_at: impl Debug) -> Self {
        Self::default().table(
            "[camera]",
            &format!("position = {position:?}\nlook_at = {look_at:?}"),
        )
    }

    /// The furnaces' view: a camera 4 units up +z looking at the origin
    /// through 35°, over `pixels` × `pixels`, filled by a unit sphere there.
    pub fn furnace_view(pixels: u32) -> Self {
        Self::camera([0.0, 0.0, 4.0], [0.0; 3], [pixels, pixels]).fov(35.0)
    }

    /// Adds `lines` (TOML keys) to the table written last: `.camera(..).with("shutter = [0.0, 1.0]")`.
    pub fn with(mut self, lines: &str) -> Self {
        for line in lines.lines().map(str::trim).filter(|l| !l.is_empty()) {
            writeln!(self.text, "{line}").unwrap();
        }
        self
    }

    /// The camera's field of view in degrees (right after `camera`).
    pub fn fov(self, degrees: impl Debug) -> Self {
        self.with(&format!("fov = {degrees:?}"))
    }

    /// A table `header` (`[integrator]`, `[[shape]]`, ...) holding `lines`.
    pub fn table(mut self, header: &str, lines: &str) -> Self {
        writeln!(self.text, "{header}").unwrap();
        self.with(lines)
    }

    /// An `[integrator]` table holding `lines`.
    pub fn integrator(self, lines: &str) -> Self {
        self.table("[integrator]", lines)
    }

    /// An `[integrator]` with these depth limits (a furnace's are far beyond any path it traces).
    pub fn depths(self, max_depth: u32, rr_depth: u32) -> Self {
        self.integrator(&format!("max_depth = {max_depth}\nrr_depth = {rr_depth}"))
    }

    /// A `[[light]]` table holding `lines`.
    pub fn light(self, lines: &str) -> Self {
        self.table("[[light]]", lines)
    }

    /// A uniform environment light of `radiance` (a number or an RGB triple).
    pub fn environment(self, radiance: impl Debug) -> Self {
        self.light(&format!("type = \"environment\"\nradiance = {radiance:?}"))
    }

    /// A point light at `position` of `intensity` (a number or an RGB triple).
    pub fn point_light(self, position: impl Debug, intensity: impl Debug) -> Self {
        self.light(&format!(
            "type = \"point\"\nposition = {position:?}\nintensity = {intensity:?}"
        ))
    }

    /// A sun shining along `direction` with `irradiance` (a number or an RGB triple).
    pub fn sun(self, direction: impl Debug, irradiance: impl Debug) -> Self {
        self.light(&format!(
            "type = \"sun\"\ndirection = {direction:?}\nirradiance = {irradiance:?}"
        ))
    }

    /// A `[[shape]]` table holding `lines`.
    pub fn shape(self, lines: &str) -> Self {
        self.table("[[shape]]", lines)
    }

    /// A sphere of `radius` at `center`.
    pub fn sphere(self, center: impl Debug, radius: impl Debug) -> Self {
        self.shape(&format!(
            "type = \"sphere\"\ncenter = {center:?}\nradius = {radius:?}"
        ))
    }

    /// A sphere of radius 1 at the origin made of `material` (a TOML inline table).
    pub fn unit_sphere(self, material: &str) -> Self {
        self.shape(&format!(
            "type = \"sphere\"\nradius = 1.0\nmaterial = {material}"
        ))
    }

    /// A quad at `center` facing `normal`, `size` across.
    pub fn quad(self, center: impl Debug, normal: impl Debug, size: impl Debug) -> Self {
        self.shape(&format!(
            "type = \"quad\"\ncenter = {center:?}\nnormal = {normal:?}\nsize = {size:?}"
        ))
    }

    /// A `[[medium]]` table holding `lines`.
    pub fn medium(self, lines: &str) -> Self {
        self.table("[[medium]]", lines)
    }

    /// The test plume (`tests/data/volumes/smoke_plume.vdb`, 1.4 × 1.9 × 1.4 m
    /// of fbm smoke) at `density_scale`, standing on a 6 m diffuse ground.
    pub fn smoke_plume_on_ground(self, density_scale: f32) -> Self {
        self.quad([0.0; 3], [0.0, 1.0, 0.0], [6.0, 6.0])
            .with("material = { type = \"diffuse\", albedo = [0.5, 0.45, 0.4] }")
            .medium(&format!(
                "type = \"vdb\"\nfile = \"tests/data/volumes/smoke_plume.vdb\"\n\
                 density_scale = {density_scale:?}\nalbedo = [0.9, 0.85, 0.8]\n\
                 phase = {{ type = \"hg\", g = 0.3 }}\n\
                 transform = {{ translate = [1.2, 0.35, 0.35] }}"
            ))
    }

    /// The plume's view: from 4.5 m in front, over `pixels` × `pixels`.
    pub fn plume_view(pixels: u32) -> Self {
        Self::camera([0.0, 1.0, 4.5], [0.0, 0.8, 0.0], [pixels, pixels]).fov(38.0)
    }

    /// `text` as it is (blocks the builder has no words for, or several tables at once).
    pub fn raw(mut self, text: &str) -> Self {
        writeln!(self.text, "{text}").unwrap();
        self
    }

    /// The TOML text.
    pub fn build(&self) -> String {
        self.text.clone()
    }
}

impl Display for SceneText {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.text)
    }
}

/// A `[[medium]]` of the unit VDB box (`tests/data/volumes/homogeneous_box.vdb`)
/// with `fields`, centred on the origin, scaled by 1.6 and turned.
pub fn vdb_box_medium(fields: &str) -> String {
    SceneText::default()
        .medium(&format!(
            "type = \"vdb\"\nfile = \"tests/data/volumes/homogeneous_box.vdb\"\n{fields}\n\
             transform = {{ translate = [-0.8, -0.8, -0.8], scale = 1.6, rotate = [15.0, 25.0, 0.0] }}"
        ))
        .build()
}

/// The albedo-1 VDB box furnaces every estimator is checked on: thin with
/// HG, thick under a global majorant, chromatic σt with backward HG.
pub const VDB_BOX_FURNACES: [&str; 4] = [
    "density_scale = 0.5\nphase = { type = \"hg\", g = 0.6 }",
    "density_scale = 8.0\nmajorant = \"global\"",
    "density_scale = 8.0\nmajorant_cell = 1",
    "density_scale = 2.0\nsigma_t_scale = [1.0, 0.25, 3.0]\nphase = { type = \"hg\", g = -0.4 }",
];
