//! Where a film lies and what it holds: its pixel rectangle, its sample
//! ranges (the `--crop` and `--samples` forms) and its provenance.

use std::fmt;

/// A half-open rectangle of pixels, x0..x1 by y0..y1, row 0 at the top.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rect {
    /// First column.
    pub x0: u32,
    /// One past the last column.
    pub x1: u32,
    /// First row.
    pub y0: u32,
    /// One past the last row.
    pub y1: u32,
}

impl Rect {
    /// The whole `width`×`height` frame.
    pub fn full(width: u32, height: u32) -> Rect {
        Rect {
            x0: 0,
            x1: width,
            y0: 0,
            y1: height,
        }
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.x1 - self.x0
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.y1 - self.y0
    }

    /// Number of pixels.
    pub fn area(&self) -> usize {
        self.width() as usize * self.height() as usize
    }

    /// True when `other` lies inside this rectangle.
    pub fn contains(&self, other: &Rect) -> bool {
        other.x0 >= self.x0 && other.x1 <= self.x1 && other.y0 >= self.y0 && other.y1 <= self.y1
    }

    /// True when the two rectangles share a pixel.
    pub fn overlaps(&self, other: &Rect) -> bool {
        self.x0 < other.x1 && other.x0 < self.x1 && self.y0 < other.y1 && other.y0 < self.y1
    }
}

impl fmt::Display for Rect {
    /// The `--crop` form: x0,x1,y0,y1.
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "{},{},{},{}", self.x0, self.x1, self.y0, self.y1)
    }
}

/// A half-open range of sample indices, start..end.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct SampleRange {
    /// First sample index.
    pub start: u32,
    /// One past the last sample index.
    pub end: u32,
}

impl SampleRange {
    /// The range start..end.
    pub fn new(start: u32, end: u32) -> SampleRange {
        SampleRange { start, end }
    }

    /// Number of sample indices.
    pub fn len(&self) -> u32 {
        self.end.saturating_sub(self.start)
    }

    /// True when the range holds no sample.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// True when the two ranges share a sample index.
    pub fn overlaps(&self, other: &SampleRange) -> bool {
        self.start < other.end && other.start < self.end
    }
}

impl fmt::Display for SampleRange {
    /// The `--samples` form: START..END.
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "{}..{}", self.start, self.end)
    }
}

/// Writes ranges as `0..16,32..48` (the header form).
pub fn format_ranges(ranges: &[SampleRange]) -> String {
    let parts: Vec<String> = ranges.iter().map(|r| r.to_string()).collect();
    parts.join(",")
}

/// Parses `START..END`; None unless both are integers with START < END.
pub fn parse_range(text: &str) -> Option<SampleRange> {
    let (a, b) = text.trim().split_once("..")?;
    let range = SampleRange::new(a.trim().parse().ok()?, b.trim().parse().ok()?);
    (range.start < range.end).then_some(range)
}

/// Parses the header form `0..16,32..48` (empty text: no range).
pub fn parse_ranges(text: &str) -> Option<Vec<SampleRange>> {
    if text.trim().is_empty() {
        return Some(Vec::new());
    }
    text.split(',').map(parse_range).collect()
}

/// Sorts ranges and joins the ones that touch: `16..32,0..16` → `0..32`.
pub fn coalesce(ranges: &mut Vec<SampleRange>) {
    ranges.retain(|r| !r.is_empty());
    ranges.sort();
    let mut out: Vec<SampleRange> = Vec::with_capacity(ranges.len());
    for r in ranges.drain(..) {
        match out.last_mut() {
            Some(last) if r.start <= last.end => last.end = last.end.max(r.end),
            _ => out.push(r),
        }
    }
    *ranges = out;
}

/// Where a film comes from: what must agree for two films to be merged.
#[derive(Clone, Debug, PartialEq)]
pub struct Provenance {
    /// Seed of the random streams.
    pub seed: u64,
    /// Hash of the scene file, the files it read and the settings that change samples.
    pub scene_hash: u64,
    /// Samples per pixel of the whole render the film is a piece of.
    pub spp_total: u32,
    /// Sample ranges the film was asked to hold, coalesced.
    pub requested: Vec<SampleRange>,
    /// Sample ranges the film holds (less than `requested` if interrupted), coalesced.
    pub held: Vec<SampleRange>,
}

impl Provenance {
    /// True when the film holds every sample it was asked for.
    pub fn complete(&self) -> bool {
        self.held == self.requested
    }

    /// Samples held per pixel.
    pub fn spp_held(&self) -> u32 {
        self.held.iter().map(SampleRange::len).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_parse_format_and_coalesce() {
        assert_eq!(parse_range("16..32"), Some(SampleRange::new(16, 32)));
        assert_eq!(parse_range("32..16"), None);
        assert_eq!(parse_range("5..5"), None);
        assert_eq!(parse_range("a..4"), None);
        let mut r = parse_ranges("32..48,0..16,16..20").unwrap();
        coalesce(&mut r);
        assert_eq!(format_ranges(&r), "0..20,32..48");
        assert_eq!(parse_ranges("").unwrap(), vec![]);
        assert!(SampleRange::new(0, 16).overlaps(&SampleRange::new(15, 20)));
        assert!(!SampleRange::new(0, 16).overlaps(&SampleRange::new(16, 20)));
    }

    #[test]
    fn rects_overlap_and_contain() {
        let a = Rect::full(4, 4);
        let b = Rect {
            x0: 4,
            x1: 6,
            y0: 0,
            y1: 4,
        };
        assert!(!a.overlaps(&b));
        assert!(Rect::full(8, 8).contains(&b));
        assert!(!a.contains(&b));
    }
}
