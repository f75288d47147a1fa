//! Resource limits: the memory a single operation may plan to use.
//!
//! Sizes that an input or an option implies (refined vertices, stencil weights, spline
//! cells) are checked against a [`MemoryBudget`] before anything that large is allocated,
//! so a hostile or merely ambitious input gets a clear error instead of an allocation abort.
//! The CLI's `--max-memory` (and the C door's `surfkit_set_max_memory`) sets the process's
//! budget; the default is half of the machine's memory.

use std::fmt;
use std::sync::atomic::{AtomicU64, Ordering};

/// An upper bound, in bytes, for what one operation may allocate.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MemoryBudget {
    bytes: u64,
}

impl MemoryBudget {
    /// A budget of `bytes`.
    pub const fn bytes(bytes: u64) -> Self {
        MemoryBudget { bytes }
    }

    /// The smallest budget a caller may set: below it not even a small mesh's work fits.
    pub const SMALLEST: u64 = 1 << 20;

    /// A budget of `bytes` set by a caller (`--max-memory`, the C and Python doors), refused
    /// below [`MemoryBudget::SMALLEST`] with the message those callers show.
    pub fn checked(bytes: u64) -> Result<Self, String> {
        if bytes < Self::SMALLEST {
            return Err(format!(
                "a memory limit of {bytes} bytes: it must be at least 1 MiB"
            ));
        }
        Ok(MemoryBudget::bytes(bytes))
    }

    /// The budget in bytes.
    pub const fn get(self) -> u64 {
        self.bytes
    }

    /// How many items of `item_bytes` each fit in the budget.
    pub fn items(self, item_bytes: u64) -> u64 {
        self.bytes / item_bytes.max(1)
    }

    /// Half of the machine's physical memory (`MemTotal` of /proc/meminfo), or 4 GiB where
    /// that cannot be read: what one command may take without pushing the machine to swap.
    pub fn from_machine() -> Self {
        let total = std::fs::read_to_string("/proc/meminfo")
            .ok()
            .and_then(|text| parse_mem_total_kib(&text))
            .map(|kib| kib.saturating_mul(1024));
        MemoryBudget::bytes(total.map_or(4 << 30, |b| b / 2))
    }

    /// Parses a size such as `512M`, `12G`, `2.5GiB` or `1000000` (bytes); suffixes are
    /// binary (K = 1024).
    pub fn parse(text: &str) -> Result<Self, String> {
        let t = text.trim();
        let split = t
            .find(|c: char| !(c.is_ascii_digit() || c == '.'))
            .unwrap_or(t.len());
        let (number, unit) = t.split_at(split);
        let value: f64 = number
            .parse()
            .map_err(|_| format!("{text:?} is not a size (e.g. 512M, 12G)"))?;
        let scale: u64 = match unit.trim().to_ascii_lowercase().as_str() {
            "" | "b" => 1,
            "k" | "kb" | "kib" => 1 << 10,
            "m" | "mb" | "mib" => 1 << 20,
            "g" | "gb" | "gib" => 1 << 30,
            "t" | "tb" | "tib" => 1 << 40,
            other => {
                return Err(format!(
                    "{text:?}: unknown unit {other:?} (use K, M, G or T)"
                ))
            }
        };
        let bytes = value * scale as f64;
        if !(bytes.is_finite() && bytes < u64::MAX as f64) {
            return Err(format!("{text:?}: not a size a machine can have"));
        }
        MemoryBudget::checked(bytes as u64).map_err(|e| format!("{text:?}: {e}"))
    }
}

/// The budget [`set_process_budget`] chose, in bytes; 0 when none was chosen.
static PROCESS_BUDGET: AtomicU64 = AtomicU64::new(0);

/// Sets the budget every operation of this process uses when its caller gives none
/// ([`MemoryBudget::default`]): the CLI's `--max-memory`, the C door's
/// `surfkit_set_max_memory`. `None` goes back to half of the machine's memory.
pub fn set_process_budget(budget: Option<MemoryBudget>) {
    PROCESS_BUDGET.store(budget.map_or(0, MemoryBudget::get), Ordering::Relaxed);
}

impl Default for MemoryBudget {
    /// The process's budget ([`set_process_budget`]), or half of the machine's memory.
    fn default() -> Self {
        match PROCESS_BUDGET.load(Ordering::Relaxed) {
            0 => MemoryBudget::from_machine(),
            bytes => MemoryBudget::bytes(bytes),
        }
    }
}

impl fmt::Display for MemoryBudget {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&human_bytes(self.bytes))
    }
}

/// `bytes` as `1.5 GiB`, `320 MiB`, `12 KiB`.
pub fn human_bytes(bytes: u64) -> String {
    const UNITS: [&str; 5] = ["B", "KiB", "MiB", "GiB", "TiB"];
    let mut value = bytes as f64;
    let mut unit = 0;
    while value >= 1024.0 && unit + 1 < UNITS.len() {
        value /= 1024.0;
        unit += 1;
    }
    if unit == 0 || value >= 10.0 {
        format!("{value:.0} {}", UNITS[unit])
    } else {
        format!("{value:.1} {}", UNITS[unit])
    }
}

fn parse_mem_total_kib(meminfo: &str) -> Option<u64> {
    let line = meminfo.lines().find(|l| l.starts_with("MemTotal:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse_with_binary_suffixes_and_refuse_nonsense() {
        assert_eq!(MemoryBudget::parse("512M").unwrap().get(), 512 << 20);
        assert_eq!(MemoryBudget::parse("12G").unwrap().get(), 12 << 30);
        assert_eq!(MemoryBudget::parse("2.5GiB").unwrap().get(), 5 << 29);
        assert_eq!(MemoryBudget::parse("1048576").unwrap().get(), 1 << 20);
        for bad in ["", "G", "12Q", "-1G", "nanG", "1K", "1e400"] {
            assert!(MemoryBudget::parse(bad).is_err(), "{bad:?} accepted");
        }
        // The same floor for sizes given in bytes (the C and Python doors).
        assert!(MemoryBudget::checked((1 << 20) - 1)
            .unwrap_err()
            .contains("1048575 bytes: it must be at least 1 MiB"));
        assert_eq!(MemoryBudget::checked(1 << 20).unwrap().get(), 1 << 20);
    }

    #[test]
    fn machine_memory_is_read_from_meminfo() {
        let text = "MemTotal:       24576000 kB\nMemFree: 1 kB\n";
        assert_eq!(parse_mem_total_kib(text), Some(24_576_000));
        assert_eq!(human_bytes(3 << 29), "1.5 GiB");
        assert_eq!(human_bytes(320 << 20), "320 MiB");
    }
}
