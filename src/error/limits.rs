//! The memory limit: one budget for every allocation whose size comes from a
//! file or a flag, checked against the declared size before allocating.
//!
//! A header is cheap to forge: a few hundred bytes of EXR can declare a
//! 60000×60000 image, a velocity grid can move a medium across the world.
//! Allocating what they declare aborts the process (a failed allocation is
//! not an error in Rust) or, with overcommit, gets it killed later. So every
//! such size goes through checked arithmetic (u128: no header overflows it)
//! and [`check`] before the allocation, and a refusal is an error (exit 2)
//! naming the file or key, the declared size and the limit.
//!
//! The limit is, in this order: `--memory-limit GB` (any command), the
//! environment variable `BRUME_MEMORY_LIMIT` (GB), or half of this machine's
//! memory (the smaller of physical memory and a cgroup limit; 8 GB when it
//! cannot be read). It applies to each image, grid, file held whole or
//! render on its own, not to their sum.

use crate::error::Error;
use std::fmt;
use std::sync::atomic::{AtomicU64, Ordering};

/// The environment variable that sets the limit in GB when `--memory-limit` is not given.
pub const ENV_VAR: &str = "BRUME_MEMORY_LIMIT";

/// The command-line flag that sets the limit in GB.
pub const FLAG: &str = "--memory-limit";

/// The default limit when the machine's memory cannot be read (8 GB).
pub const UNKNOWN_MACHINE_DEFAULT: u64 = 8_000_000_000;

/// Largest accepted limit: a billion GB, far beyond any machine, still exact in u64.
const MAX_GB: f64 = 1e9;

/// The limit given on the command line (0: not given).
static FLAG_BYTES: AtomicU64 = AtomicU64::new(0);

/// Where the limit in force comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Source {
    /// `--memory-limit`.
    Flag,
    /// `BRUME_MEMORY_LIMIT`.
    Env,
    /// Half of the machine's memory (`Some(total)`), or the fixed default when it is unknown.
    Default(Option<u64>),
}

/// The limit in force, in bytes, and where it comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MemoryLimit {
    /// Largest size allowed for one image, grid, file or render.
    pub bytes: u64,
    /// Who set it.
    pub source: Source,
}

/// Why an allocation was refused.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Refusal {
    /// More than the limit (or than the machine can reserve).
    Exceeded {
        /// The limit in force.
        limit: MemoryLimit,
        /// True when within the limit but the machine could not reserve it.
        machine: bool,
    },
    /// `BRUME_MEMORY_LIMIT` is not a valid number of GB.
    BadSetting(String),
}

impl fmt::Display for Refusal {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        let (limit, machine) = match self {
            Refusal::BadSetting(message) => return write!(f, "{ENV_VAR}: {message}"),
            Refusal::Exceeded { limit, machine } => (limit, *machine),
        };
        if machine {
            return write!(
                f,
                "more than this machine can give (the memory limit is {})",
                format_bytes(limit.bytes as u128)
            );
        }
        let from = match limit.source {
            Source::Flag => format!("set by {FLAG}"),
            Source::Env => format!("set by {ENV_VAR}"),
            Source::Default(Some(total)) => {
                format!("half of this machine's {}", format_bytes(total as u128))
            }
            Source::Default(None) => "the default when the machine's memory is unknown".into(),
        };
        write!(
            f,
            "more than the memory limit of {} ({from}); raise it with {FLAG} GB or {ENV_VAR}=GB",
            format_bytes(limit.bytes as u128)
        )
    }
}

/// Parses a limit in GB (10⁹ bytes): a number above 0 and at most a billion.
pub fn parse_gb(text: &str) -> Result<u64, String> {
    let bad = || {
        format!("`{text}` is not a memory size: give a number of gigabytes above 0 (1 GB = 10^9 bytes), e.g. 16 or 0.5")
    };
    let gb: f64 = text.trim().parse().map_err(|_| bad())?;
    if !(gb.is_finite() && gb > 0.0) {
        return Err(bad());
    }
    if gb > MAX_GB {
        return Err(format!(
            "{text} GB is more than any machine has (at most {MAX_GB:e} GB)"
        ));
    }
    // At least one byte, so that a tiny value still means "refuse".
    Ok(((gb * 1e9).round() as u64).max(1))
}

/// Sets the limit for this process, as `--memory-limit` does (it wins over the environment).
pub fn set_memory_limit(bytes: u64) {
    FLAG_BYTES.store(bytes.max(1), Ordering::Relaxed);
}

/// The limit in force: the flag, else `BRUME_MEMORY_LIMIT`, else the default.
pub fn memory_limit() -> Result<MemoryLimit, Refusal> {
    limit_setting().map_err(Refusal::BadSetting)
}

/// The limit in force, or why `BRUME_MEMORY_LIMIT` is not a size.
fn limit_setting() -> Result<MemoryLimit, String> {
    let flag = FLAG_BYTES.load(Ordering::Relaxed);
    if flag > 0 {
        return Ok(MemoryLimit {
            bytes: flag,
            source: Source::Flag,
        });
    }
    if let Some(value) = std::env::var_os(ENV_VAR) {
        let text = value.to_string_lossy();
        let bytes = parse_gb(&text)?;
        return Ok(MemoryLimit {
            bytes,
            source: Source::Env,
        });
    }
    let total = machine_memory();
    Ok(MemoryLimit {
        bytes: total.map_or(UNKNOWN_MACHINE_DEFAULT, |t| t / 2),
        source: Source::Default(total),
    })
}

/// Checks the limit setting itself (for the command line: a bad `BRUME_MEMORY_LIMIT` is exit 2 at once).
pub fn check_setting() -> Result<MemoryLimit, Error> {
    limit_setting().map_err(|message| Error::Argument {
        argument: ENV_VAR.into(),
        message,
    })
}

/// Whether `bytes` may be allocated: within the limit, and reservable on this
/// machine (reserving touches no page, so the probe costs nothing).
pub fn check(bytes: u128) -> Result<(), Refusal> {
    let limit = memory_limit()?;
    if bytes > limit.bytes as u128 {
        return Err(Refusal::Exceeded {
            limit,
            machine: false,
        });
    }
    let fits = usize::try_from(bytes)
        .ok()
        .is_some_and(|b| Vec::<u8>::new().try_reserve_exact(b).is_ok());
    if fits {
        Ok(())
    } else {
        Err(Refusal::Exceeded {
            limit,
            machine: true,
        })
    }
}

/// `bytes` for people: `312 bytes`, `1.5 MB`, `43.2 GB`, `3.1e7 TB` (powers of 1000).
pub fn format_bytes(bytes: u128) -> String {
    let b = bytes as f64;
    match b {
        _ if b < 1e3 => format!("{bytes} bytes"),
        _ if b < 1e6 => format!("{:.1} kB", b / 1e3),
        _ if b < 1e9 => format!("{:.1} MB", b / 1e6),
        _ if b < 1e12 => format!("{:.1} GB", b / 1e9),
        _ if b < 1e18 => format!("{:.1} TB", b / 1e12),
        _ => format!("{:.1e} TB", b / 1e12),
    }
}

/// The memory this process may use: physical memory, or a smaller cgroup limit.
fn machine_memory() -> Option<u64> {
    let physical = physical_memory();
    let cgroup = [
        "/sys/fs/cgroup/memory.max",
        "/sys/fs/cgroup/memory/memory.limit_in_bytes",
    ]
    .iter()
    .filter_map(|p| std::fs::read_to_string(p).ok())
    .filter_map(|s| s.trim().parse::<u64>().ok())
    .min();
    match (physical, cgroup) {
        (Some(p), Some(c)) => Some(p.min(c)),
        (p, c) => p.or(c),
    }
}

#[cfg(unix)]
fn physical_memory() -> Option<u64> {
    // SAFETY: sysconf only reads system constants; it has no preconditions.
    let (pages, page) = unsafe {
        (
            libc::sysconf(libc::_SC_PHYS_PAGES),
            libc::sysconf(libc::_SC_PAGESIZE),
        )
    };
    match (u64::try_from(pages), u64::try_from(page)) {
        (Ok(n), Ok(s)) if n > 0 && s > 0 => n.checked_mul(s),
        _ => None,
    }
}

#[cfg(not(unix))]
fn physical_memory() -> Option<u64> {
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn limits_parse_in_gigabytes_and_refuse_what_is_not_a_size() {
        assert_eq!(parse_gb("16"), Ok(16_000_000_000));
        assert_eq!(parse_gb(" 0.5 "), Ok(500_000_000));
        assert_eq!(parse_gb("1e-12"), Ok(1));
        for bad in ["0", "-1", "nan", "inf", "", "12GB", "1e300"] {
            let e = parse_gb(bad).unwrap_err();
            assert!(e.contains(bad), "{bad}: {e}");
        }
    }

    #[test]
    fn sizes_print_in_powers_of_a_thousand() {
        assert_eq!(format_bytes(312), "312 bytes");
        assert_eq!(format_bytes(43_200_000_000), "43.2 GB");
        assert_eq!(format_bytes(1_500_000), "1.5 MB");
        assert_eq!(format_bytes(u128::MAX), "3.4e26 TB");
    }

    #[test]
    fn the_default_is_half_the_machine() {
        let total = machine_memory();
        let limit = MemoryLimit {
            bytes: total.map_or(UNKNOWN_MACHINE_DEFAULT, |t| t / 2),
            source: Source::Default(total),
        };
        if std::env::var_os(ENV_VAR).is_none() && FLAG_BYTES.load(Ordering::Relaxed) == 0 {
            assert_eq!(memory_limit(), Ok(limit));
        }
        let refusal = Refusal::Exceeded {
            limit,
            machine: false,
        };
        let text = refusal.to_string();
        assert!(text.contains("--memory-limit GB"), "{text}");
    }
}
