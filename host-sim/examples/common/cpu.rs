//! What the examples measure their rate with: the process's CPU time, and
//! the load average they print beside it (included with `#[path =
//! "common/cpu.rs"] mod cpu;`).

/// CPU seconds of the process so far (user + system, `/proc/self/stat`).
pub fn cpu_s() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    let after = stat.rsplit_once(") ").map_or("", |(_, rest)| rest);
    let fields: Vec<f64> = after
        .split_whitespace()
        .map(|f| f.parse().unwrap_or(0.0))
        .collect();
    // Fields 14 and 15 of stat(5), in clock ticks (100 per second).
    (fields.get(11).unwrap_or(&0.0) + fields.get(12).unwrap_or(&0.0)) / 100.0
}

/// The load average now, three figures (`/proc/loadavg`).
#[allow(dead_code)] // the examples' that print it
pub fn load_average() -> String {
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    load.split_whitespace()
        .take(3)
        .collect::<Vec<_>>()
        .join(", ")
}
