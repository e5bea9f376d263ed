//! Which part of a render one process fills: `--crop`, `--samples` and
//! `--task-index I --task-count N` (or `JOB_COMPLETION_INDEX`) turned into a
//! [`Part`].
//!
//! Task I of N takes the I-th of N near-equal shares, boundaries at
//! floor(I·L/N): of the sample range (`--split samples`, the default) or of
//! the crop's rows (`--split tiles`). The shares tile the range exactly, so the
//! N pieces merge into the single render.

use crate::error::{Error, Result};
use crate::film::{parse_range, Rect, SampleRange};
use crate::render::Part;

/// What `--task-index`/`--task-count` divide among the tasks.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum SplitBy {
    /// Every task renders all pixels, a share of the sample range.
    Samples,
    /// Every task renders all samples of a band of rows.
    Tiles,
}

/// The `brume render` options that choose a piece of the render.
#[derive(clap::Args, Clone, Debug)]
pub struct SplitArgs {
    /// Render only the pixels x0..x1 by y0..y1 (x1, y1 excluded): the EXR's data window; the display window stays the full frame.
    #[arg(long, value_name = "X0,X1,Y0,Y1")]
    pub crop: Option<String>,
    /// Render only sample indices START..END (END excluded) of every pixel, to be merged with `brume merge`.
    #[arg(long, value_name = "START..END")]
    pub samples: Option<String>,
    /// This task's index, 0-based (default: JOB_COMPLETION_INDEX, as Kubernetes Indexed Jobs set it).
    #[arg(long, value_name = "I", requires = "task_count")]
    pub task_index: Option<u32>,
    /// Split the render into this many tasks and render task I's share (see --split).
    #[arg(long, value_name = "N")]
    pub task_count: Option<u32>,
    /// What the tasks share: the sample range (every task renders every pixel) or tiles (bands of rows).
    #[arg(long, value_enum, default_value_t = SplitBy::Samples)]
    pub split: SplitBy,
}

impl SplitArgs {
    /// True when any option asks for a piece rather than the whole render.
    pub fn is_piece(&self) -> bool {
        self.crop.is_some() || self.samples.is_some() || self.task_count.is_some()
    }

    /// The request, with the task index taken from `JOB_COMPLETION_INDEX` when not given.
    pub fn request(&self) -> Result<SplitRequest> {
        let task = match self.task_count {
            None => None,
            Some(count) => {
                let env = std::env::var("JOB_COMPLETION_INDEX").ok();
                let index = task_index(self.task_index, env)?.ok_or_else(|| {
                    argument(
                        "--task-count",
                        "needs --task-index I or the JOB_COMPLETION_INDEX variable".into(),
                    )
                })?;
                Some((index, count))
            }
        };
        Ok(SplitRequest {
            crop: self.crop.clone(),
            samples: self.samples.clone(),
            task,
            by: self.split,
        })
    }
}

/// The split options with the task index resolved.
#[derive(Clone, Debug)]
pub struct SplitRequest {
    /// `--crop x0,x1,y0,y1`.
    pub crop: Option<String>,
    /// `--samples START..END`.
    pub samples: Option<String>,
    /// (task index, task count).
    pub task: Option<(u32, u32)>,
    /// `--split`.
    pub by: SplitBy,
}

fn argument(name: &str, message: String) -> Error {
    Error::Argument {
        argument: name.into(),
        message,
    }
}

/// The task index: `--task-index` if given, else `JOB_COMPLETION_INDEX` (`env`).
pub fn task_index(flag: Option<u32>, env: Option<String>) -> Result<Option<u32>> {
    match (flag, env) {
        (Some(i), _) => Ok(Some(i)),
        (None, Some(text)) => text.trim().parse().map(Some).map_err(|_| {
            argument(
                "JOB_COMPLETION_INDEX",
                format!("expected a task index (0, 1, 2, ...), got `{text}`"),
            )
        }),
        (None, None) => Ok(None),
    }
}

/// The part of a `width`×`height`, `spp`-sample render that `request` selects.
pub fn resolve_part(width: u32, height: u32, spp: u32, request: &SplitRequest) -> Result<Part> {
    let mut crop = match &request.crop {
        Some(text) => parse_crop(text, width, height)?,
        None => Rect::full(width, height),
    };
    let mut samples = match &request.samples {
        Some(text) => parse_range(text).filter(|r| r.end <= spp).ok_or_else(|| {
            argument(
                "--samples",
                format!(
                    "expected START..END with 0 <= START < END <= {spp} (the render's spp; \
                         raise it with --spp), got `{text}`"
                ),
            )
        })?,
        None => SampleRange::new(0, spp),
    };
    if let Some((index, count)) = request.task {
        let total = match request.by {
            SplitBy::Samples => samples.len(),
            SplitBy::Tiles => crop.height(),
        };
        let what = match request.by {
            SplitBy::Samples => "samples",
            SplitBy::Tiles => "rows",
        };
        if count == 0 || count > total {
            return Err(argument(
                "--task-count",
                format!("must be between 1 and {total} (the {what} to share), got {count}"),
            ));
        }
        if index >= count {
            return Err(argument(
                "--task-index",
                format!("must be below --task-count {count}, got {index}"),
            ));
        }
        let (a, b) = share(index, count, total);
        match request.by {
            SplitBy::Samples => samples = SampleRange::new(samples.start + a, samples.start + b),
            SplitBy::Tiles => {
                let y0 = crop.y0;
                crop.y0 = y0 + a;
                crop.y1 = y0 + b;
            }
        }
    }
    Ok(Part { crop, samples })
}

/// Task `index`'s share [a, b) of `total` items split `count` ways.
fn share(index: u32, count: u32, total: u32) -> (u32, u32) {
    let at = |i: u32| (i as u64 * total as u64 / count as u64) as u32;
    (at(index), at(index + 1))
}

/// `x0,x1,y0,y1`, half-open pixel bounds inside the frame.
fn parse_crop(text: &str, width: u32, height: u32) -> Result<Rect> {
    let bad = || {
        argument(
            "--crop",
            format!(
                "expected x0,x1,y0,y1 with 0 <= x0 < x1 <= {width} and 0 <= y0 < y1 <= {height} \
                 (pixel bounds, x1 and y1 excluded), got `{text}`"
            ),
        )
    };
    let values: Vec<u32> = text
        .split(',')
        .map(|v| v.trim().parse().map_err(|_| bad()))
        .collect::<Result<_>>()?;
    let [x0, x1, y0, y1] = values[..] else {
        return Err(bad());
    };
    if x0 >= x1 || x1 > width || y0 >= y1 || y1 > height {
        return Err(bad());
    }
    Ok(Rect { x0, x1, y0, y1 })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn request(
        crop: Option<&str>,
        samples: Option<&str>,
        task: Option<(u32, u32)>,
    ) -> SplitRequest {
        SplitRequest {
            crop: crop.map(String::from),
            samples: samples.map(String::from),
            task,
            by: SplitBy::Samples,
        }
    }

    #[test]
    fn task_shares_tile_the_range_exactly() {
        for (count, total) in [(1, 7), (3, 7), (7, 7), (4, 64), (5, 1000)] {
            let mut next = 0;
            for i in 0..count {
                let (a, b) = share(i, count, total);
                assert_eq!(a, next);
                assert!(b > a);
                next = b;
            }
            assert_eq!(next, total);
        }
    }

    #[test]
    fn tasks_share_samples_or_rows_inside_the_crop_and_range() {
        let part = resolve_part(8, 6, 64, &request(None, Some("16..48"), Some((1, 4)))).unwrap();
        assert_eq!(part.samples, SampleRange::new(24, 32));
        assert_eq!(part.crop, Rect::full(8, 6));
        let mut tiles = request(Some("1,7,2,6"), None, Some((3, 4)));
        tiles.by = SplitBy::Tiles;
        let part = resolve_part(8, 6, 64, &tiles).unwrap();
        assert_eq!(
            part.crop,
            Rect {
                x0: 1,
                x1: 7,
                y0: 5,
                y1: 6
            }
        );
        assert_eq!(part.samples, SampleRange::new(0, 64));
    }

    #[test]
    fn bad_splits_name_the_flag() {
        let err = |r: SplitRequest| resolve_part(8, 6, 64, &r).unwrap_err().to_string();
        assert!(err(request(Some("0,9,0,6"), None, None)).contains("--crop"));
        assert!(err(request(Some("3,3,0,6"), None, None)).contains("--crop"));
        assert!(err(request(Some("0,1,0"), None, None)).contains("--crop"));
        assert!(err(request(None, Some("0..65"), None)).contains("--samples"));
        assert!(err(request(None, Some("8..4"), None)).contains("--samples"));
        assert!(err(request(None, None, Some((4, 4)))).contains("--task-index"));
        assert!(err(request(None, Some("0..2"), Some((0, 3)))).contains("--task-count"));
        assert!(task_index(None, Some("x".into())).is_err());
        assert_eq!(task_index(None, Some("3".into())).unwrap(), Some(3));
        assert_eq!(task_index(Some(1), Some("3".into())).unwrap(), Some(1));
    }
}
