//! How much memory a job may use, so that a render too large for the machine is refused before
//! it starts instead of being killed half-way.
//!
//! The available memory is the smallest of: `MemAvailable` of `/proc/meminfo` (Linux), the
//! room left under the cgroup v2 limit (`/sys/fs/cgroup/memory.max` − `memory.current`, when a
//! limit is set), and the environment variable `FRINGE_MEMORY_BYTES` (an explicit budget, e.g.
//! to share a machine; tests use it to simulate a small one). When none can be read, nothing
//! is refused.

use std::path::Path;

/// The environment variable that sets an explicit memory budget (bytes).
pub const BUDGET_VAR: &str = "FRINGE_MEMORY_BYTES";

/// Reads the first number (kB) after `key` in a `/proc/meminfo`-style text, in bytes.
pub fn meminfo_bytes(text: &str, key: &str) -> Option<u64> {
    text.lines()
        .find_map(|l| l.strip_prefix(key)?.strip_prefix(':'))
        .and_then(|rest| rest.split_whitespace().next()?.parse::<u64>().ok())
        .map(|kb| kb.saturating_mul(1024))
}

fn read(path: &str) -> Option<String> {
    std::fs::read_to_string(Path::new(path)).ok()
}

/// The room under a cgroup v2 limit: `max` − `current` (`None` for "max", i.e. no limit).
pub fn cgroup_room(max: &str, current: &str) -> Option<u64> {
    let max: u64 = max.trim().parse().ok()?;
    let current: u64 = current.trim().parse().unwrap_or(0);
    Some(max.saturating_sub(current))
}

/// The memory this process may still use (bytes), or `None` when it cannot be told. An
/// unparsable `FRINGE_MEMORY_BYTES` is an error.
pub fn available_bytes() -> Result<Option<u64>, String> {
    let mut limits = Vec::new();
    if let Ok(v) = std::env::var(BUDGET_VAR) {
        let bytes = v.trim().parse::<u64>().map_err(|_| {
            format!("{BUDGET_VAR}={v:?}: expected a whole number of bytes, e.g. 8000000000")
        })?;
        limits.push(bytes);
    }
    if let Some(b) = read("/proc/meminfo").and_then(|t| meminfo_bytes(&t, "MemAvailable")) {
        limits.push(b);
    }
    if let (Some(max), Some(cur)) = (
        read("/sys/fs/cgroup/memory.max"),
        read("/sys/fs/cgroup/memory.current"),
    ) && let Some(b) = cgroup_room(&max, &cur)
    {
        limits.push(b);
    }
    Ok(limits.into_iter().min())
}

/// Human-readable bytes (MiB or GiB).
pub fn format_bytes(b: u64) -> String {
    let mib = b as f64 / (1024.0 * 1024.0);
    if mib >= 1024.0 {
        format!("{:.1} GiB", mib / 1024.0)
    } else {
        format!("{mib:.1} MiB")
    }
}

/// `Ok` when `needed` bytes fit in `available` (`None`: unknown, accepted); otherwise an error
/// naming `what`, both amounts and the knob.
pub fn check_fits(what: &str, needed: u64, available: Option<u64>) -> Result<(), String> {
    match available {
        Some(a) if needed > a => Err(format!(
            "{what} needs about {} of memory, but only {} is available \
             (MemAvailable, the cgroup limit or {BUDGET_VAR}); make it smaller",
            format_bytes(needed),
            format_bytes(a)
        )),
        _ => Ok(()),
    }
}
