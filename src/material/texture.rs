//! Textures: colours that vary over a surface, looked up by texture
//! coordinates (u, v).
//!
//! Conventions (see docs/textures.md):
//! - (u, v) = (0, 0) is the bottom-left corner of an image and (1, 1) its
//!   top-right corner: v grows upward, so image row 0 (the top row of the
//!   file) covers v ∈ [1 − 1/h, 1].
//! - texel (i, j) (column i, row j from the top) has its centre at
//!   u = (i + ½)/w, v = 1 − (j + ½)/h; between centres the value is
//!   bilinear in (u, v).
//! - outside [0, 1] the wrap mode applies: `Repeat` tiles the image,
//!   `Mirror` tiles it mirrored every other time, `Clamp` extends its edge
//!   texels; `Nearest` filtering takes the texel the point falls in.
//! - texels are linear RGB f32, decoded once at scene load (8- and 16-bit
//!   PNG through the sRGB curve unless declared linear; EXR as stored).

use crate::math::color::Rgb;
use crate::math::Vec2;
use std::sync::Arc;

/// What an image lookup does outside [0, 1].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Wrap {
    /// Tile the image: u and u + 1 look up the same texel.
    Repeat,
    /// Tile the image mirrored every other time: u and 2 − u look up the same texel.
    Mirror,
    /// Extend the edge texels.
    Clamp,
}

/// How an image lookup between texel centres is answered.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Filter {
    /// Bilinear between the four nearest texel centres.
    Bilinear,
    /// The texel the point falls in.
    Nearest,
}

/// An image of linear RGB texels, row 0 at the top.
#[derive(Clone, Debug)]
pub struct Image {
    width: usize,
    height: usize,
    texels: Vec<Rgb>,
    wrap: Wrap,
}

impl Image {
    /// An image of `width` × `height` row-major texels; `None` when the sizes disagree or it is empty.
    pub fn new(width: usize, height: usize, texels: Vec<Rgb>, wrap: Wrap) -> Option<Image> {
        (width > 0 && height > 0 && texels.len() == width * height).then_some(Image {
            width,
            height,
            texels,
            wrap,
        })
    }

    /// Width in texels.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Height in texels.
    pub fn height(&self) -> usize {
        self.height
    }

    /// The texel in column `i`, row `j` (row 0 at the top).
    pub fn texel(&self, i: usize, j: usize) -> Rgb {
        self.texels[j * self.width + i]
    }

    /// Mean of the texels.
    pub fn average(&self) -> Rgb {
        let sum = self.texels.iter().fold([0.0f64; 3], |a, t| {
            [a[0] + t.r as f64, a[1] + t.g as f64, a[2] + t.b as f64]
        });
        let n = self.texels.len().max(1) as f64;
        Rgb::new(
            (sum[0] / n) as f32,
            (sum[1] / n) as f32,
            (sum[2] / n) as f32,
        )
    }

    /// Largest channel value of any texel.
    pub fn max_channel(&self) -> f32 {
        self.texels
            .iter()
            .fold(0.0f32, |m, t| m.max(t.max_channel()))
    }

    /// Index of texel `k` (any integer) along an axis of `n` texels, after wrapping.
    #[inline]
    fn wrap_index(&self, k: i64, n: usize) -> usize {
        match self.wrap {
            Wrap::Repeat => k.rem_euclid(n as i64) as usize,
            Wrap::Mirror => {
                let (n, k) = (n as i64, k.rem_euclid(2 * n as i64));
                (if k < n { k } else { 2 * n - 1 - k }) as usize
            }
            Wrap::Clamp => k.clamp(0, n as i64 - 1) as usize,
        }
    }

    /// The texel `uv` falls in.
    #[inline]
    pub fn nearest(&self, uv: Vec2) -> Rgb {
        let x = (uv.x * self.width as f32).floor();
        let y = ((1.0 - uv.y) * self.height as f32).floor();
        if !(x.is_finite() && y.is_finite()) {
            return Rgb::BLACK;
        }
        self.texel(
            self.wrap_index(texel_index(x), self.width),
            self.wrap_index(texel_index(y), self.height),
        )
    }

    /// Bilinear lookup at `uv`.
    #[inline]
    pub fn bilinear(&self, uv: Vec2) -> Rgb {
        // Continuous texel coordinates with texel centres on integers.
        let x = uv.x * self.width as f32 - 0.5;
        let y = (1.0 - uv.y) * self.height as f32 - 0.5;
        if !(x.is_finite() && y.is_finite()) {
            return Rgb::BLACK;
        }
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let (x0, y0) = (texel_index(x0), texel_index(y0));
        let (i0, i1) = (
            self.wrap_index(x0, self.width),
            self.wrap_index(x0 + 1, self.width),
        );
        let (j0, j1) = (
            self.wrap_index(y0, self.height),
            self.wrap_index(y0 + 1, self.height),
        );
        let top = self.texel(i0, j0) * (1.0 - fx) + self.texel(i1, j0) * fx;
        let bottom = self.texel(i0, j1) * (1.0 - fx) + self.texel(i1, j1) * fx;
        top * (1.0 - fy) + bottom * fy
    }
}

/// The texel index of a floored, finite texel coordinate. Clamping
/// far-away coordinates keeps the i64 conversion exact; the wrap modes
/// give the same texel for them as for the exact value.
#[inline]
fn texel_index(floor: f32) -> i64 {
    const FAR: i64 = 1 << 24;
    (floor as i64).clamp(-FAR, FAR)
}

/// A colour parameter: constant, an image or a procedural pattern.
#[derive(Clone, Debug)]
pub enum Texture {
    /// The same colour everywhere (no texture coordinates needed).
    Constant(Rgb),
    /// An image, bilinearly filtered or nearest.
    Image {
        /// The texels.
        image: Arc<Image>,
        /// Factor on every texel.
        scale: Rgb,
        /// Texture coordinates are multiplied by this before the lookup (tiling).
        uv_scale: Vec2,
        /// Then this is added.
        uv_offset: Vec2,
        /// Bilinear or nearest.
        filter: Filter,
    },
    /// Squares of two colours: over [0, 1]² a 2 × 2 board, `a` at the bottom-left.
    Checkerboard {
        /// Colour of the squares with an even index sum (the one containing (0, 0)).
        a: Rgb,
        /// Colour of the other squares.
        b: Rgb,
        /// Texture coordinates are multiplied by this (uv_scale 4: an 8 × 8 board over [0, 1]²).
        uv_scale: Vec2,
        /// Then this is added.
        uv_offset: Vec2,
    },
}

impl Texture {
    /// The value at texture coordinates `uv`.
    #[inline]
    pub fn eval(&self, uv: Vec2) -> Rgb {
        match self {
            Texture::Constant(c) => *c,
            Texture::Image {
                image,
                scale,
                uv_scale,
                uv_offset,
                filter,
            } => {
                let at = uv * *uv_scale + *uv_offset;
                match filter {
                    Filter::Bilinear => image.bilinear(at) * *scale,
                    Filter::Nearest => image.nearest(at) * *scale,
                }
            }
            Texture::Checkerboard {
                a,
                b,
                uv_scale,
                uv_offset,
            } => {
                let s = (uv * *uv_scale + *uv_offset) * 2.0;
                let (i, j) = (s.x.floor(), s.y.floor());
                if (i + j).rem_euclid(2.0) == 0.0 {
                    *a
                } else {
                    *b
                }
            }
        }
    }

    /// True when the value depends on texture coordinates.
    pub fn needs_uv(&self) -> bool {
        !matches!(self, Texture::Constant(_))
    }

    /// The constant value, if the texture is one.
    pub fn constant(&self) -> Option<Rgb> {
        match self {
            Texture::Constant(c) => Some(*c),
            _ => None,
        }
    }

    /// The value averaged over [0, 1]² of texture coordinates (a repeating
    /// image's mean; a clamped one's mean too, as a light's power estimate).
    pub fn average(&self) -> Rgb {
        match self {
            Texture::Constant(c) => *c,
            Texture::Image { image, scale, .. } => image.average() * *scale,
            Texture::Checkerboard { a, b, .. } => (*a + *b) * 0.5,
        }
    }

    /// An upper bound of every channel of every value.
    pub fn max_channel(&self) -> f32 {
        match self {
            Texture::Constant(c) => c.max_channel(),
            Texture::Image { image, scale, .. } => image.max_channel() * scale.max_channel(),
            Texture::Checkerboard { a, b, .. } => a.max_channel().max(b.max_channel()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 3 × 2 image with distinct texels: value 10·row + column (+ offsets per channel).
    fn image(wrap: Wrap) -> Image {
        let texels = (0..2)
            .flat_map(|j| (0..3).map(move |i| (i, j)))
            .map(|(i, j)| {
                let v = 10.0 * j as f32 + i as f32;
                Rgb::new(v, v + 100.0, v + 200.0)
            })
            .collect();
        Image::new(3, 2, texels, wrap).unwrap()
    }

    /// The UV of texel (i, j)'s centre.
    fn centre(i: f32, j: f32) -> Vec2 {
        Vec2::new((i + 0.5) / 3.0, 1.0 - (j + 0.5) / 2.0)
    }

    fn close(a: Rgb, b: Rgb) -> bool {
        (a - b).to_array().iter().all(|d| d.abs() < 1e-4)
    }

    #[test]
    fn bilinear_is_exact_at_texel_centres() {
        for wrap in [Wrap::Repeat, Wrap::Clamp] {
            let img = image(wrap);
            for j in 0..2 {
                for i in 0..3 {
                    let got = img.bilinear(centre(i as f32, j as f32));
                    assert!(close(got, img.texel(i, j)), "{wrap:?} ({i},{j}): {got:?}");
                }
            }
        }
    }

    #[test]
    fn bilinear_is_linear_between_centres() {
        let img = image(Wrap::Clamp);
        // A quarter of the way from texel (0,0) to (1,0): 0.75·t00 + 0.25·t10.
        let uv = centre(0.25, 0.0);
        let want = img.texel(0, 0) * 0.75 + img.texel(1, 0) * 0.25;
        assert!(close(img.bilinear(uv), want), "{:?}", img.bilinear(uv));
        // Between rows: v going down from row 0 toward row 1 (v grows upward).
        let uv = centre(1.0, 0.6);
        let want = img.texel(1, 0) * 0.4 + img.texel(1, 1) * 0.6;
        assert!(close(img.bilinear(uv), want), "{:?}", img.bilinear(uv));
        // Both at once: the product weights.
        let uv = centre(1.3, 0.2);
        let want = (img.texel(1, 0) * 0.7 + img.texel(2, 0) * 0.3) * 0.8
            + (img.texel(1, 1) * 0.7 + img.texel(2, 1) * 0.3) * 0.2;
        assert!(close(img.bilinear(uv), want), "{:?}", img.bilinear(uv));
    }

    #[test]
    fn top_row_of_the_file_is_at_v_one() {
        let img = image(Wrap::Clamp);
        assert!(close(img.bilinear(Vec2::new(0.0, 1.0)), img.texel(0, 0)));
        assert!(close(img.bilinear(Vec2::new(0.0, 0.0)), img.texel(0, 1)));
        assert!(close(img.bilinear(Vec2::new(1.0, 0.0)), img.texel(2, 1)));
    }

    #[test]
    fn wrap_modes_outside_the_unit_square() {
        let rep = image(Wrap::Repeat);
        let clamp = image(Wrap::Clamp);
        // Repeat: shifting by whole periods changes nothing.
        for uv in [centre(0.3, 0.2), centre(2.0, 1.0), Vec2::new(0.01, 0.99)] {
            for shift in [Vec2::new(1.0, 0.0), Vec2::new(-2.0, 3.0)] {
                assert!(close(rep.bilinear(uv + shift), rep.bilinear(uv)));
            }
        }
        // Repeat: left of the first centre mixes with the last column.
        let uv = Vec2::new(0.0, centre(0.0, 0.0).y);
        let want = (rep.texel(2, 0) + rep.texel(0, 0)) * 0.5;
        assert!(close(rep.bilinear(uv), want), "{:?}", rep.bilinear(uv));
        // Clamp: there (and far away) the edge texel.
        assert!(close(clamp.bilinear(uv), clamp.texel(0, 0)));
        assert!(close(
            clamp.bilinear(Vec2::new(-5.0, 7.0)),
            clamp.texel(0, 0)
        ));
        assert!(close(
            clamp.bilinear(Vec2::new(5.0, -7.0)),
            clamp.texel(2, 1)
        ));
        assert!(close(
            clamp.bilinear(Vec2::new(1e30, 0.5)),
            clamp.bilinear(Vec2::new(1.0, 0.5))
        ));
        assert_eq!(rep.bilinear(Vec2::new(f32::NAN, 0.5)), Rgb::BLACK);
    }

    #[test]
    fn checkerboard_pattern() {
        let (a, b) = (Rgb::splat(0.1), Rgb::splat(0.9));
        let t = Texture::Checkerboard {
            a,
            b,
            uv_scale: Vec2::ONE,
            uv_offset: Vec2::ZERO,
        };
        assert_eq!(t.eval(Vec2::new(0.25, 0.25)), a);
        assert_eq!(t.eval(Vec2::new(0.75, 0.25)), b);
        assert_eq!(t.eval(Vec2::new(0.25, 0.75)), b);
        assert_eq!(t.eval(Vec2::new(0.75, 0.75)), a);
        assert_eq!(t.eval(Vec2::new(-0.25, 0.25)), b);
        assert_eq!(t.eval(Vec2::new(-0.25, -0.25)), a);
        let fine = Texture::Checkerboard {
            a,
            b,
            uv_scale: Vec2::new(4.0, 1.0),
            uv_offset: Vec2::ZERO,
        };
        // 8 squares across u, 2 across v.
        let row: Vec<bool> = (0..8)
            .map(|i| fine.eval(Vec2::new((i as f32 + 0.5) / 8.0, 0.25)) == a)
            .collect();
        assert_eq!(row, [true, false, true, false, true, false, true, false]);
        assert_eq!(fine.eval(Vec2::new(0.5 / 8.0, 0.75)), b);
        assert!(t.needs_uv() && !Texture::Constant(a).needs_uv());
        assert_eq!(t.max_channel(), 0.9);
    }

    #[test]
    fn image_texture_scales_and_tiles() {
        let t = Texture::Image {
            image: Arc::new(image(Wrap::Repeat)),
            scale: Rgb::new(2.0, 1.0, 0.5),
            uv_scale: Vec2::new(2.0, 1.0),
            uv_offset: Vec2::ZERO,
            filter: Filter::Bilinear,
        };
        let img = image(Wrap::Repeat);
        let got = t.eval(Vec2::new(centre(1.0, 0.0).x / 2.0, centre(1.0, 0.0).y));
        let want = img.texel(1, 0) * Rgb::new(2.0, 1.0, 0.5);
        assert!(close(got, want), "{got:?}");
        // Largest channel: blue of texel (2, 1), 212, times 2.
        assert_eq!(t.max_channel(), 424.0);
    }
}
