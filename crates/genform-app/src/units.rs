//! Durations as people write them (`30s`, `2m`, `1.5h`): run budgets on
//! the command line, in scene files, from the studio and from Python.

use anyhow::{Context, Result, bail};
use std::time::Duration;

/// Parses "30s", "2m", "1.5h", "500ms" or a bare number of seconds.
pub fn parse_duration(s: &str) -> Result<Duration> {
    let s = s.trim();
    let split = s.find(|c: char| c.is_ascii_alphabetic()).unwrap_or(s.len());
    let (num, unit) = s.split_at(split);
    let v: f64 = num.trim().parse().with_context(|| format!("`{s}` is not a duration such as 30s, 5m or 1h"))?;
    let secs = match unit.trim() {
        "" | "s" | "sec" => v,
        "ms" => v / 1000.0,
        "m" | "min" => v * 60.0,
        "h" => v * 3600.0,
        u => bail!("unknown time unit `{u}` in `{s}`; use ms, s, m or h"),
    };
    if !(secs.is_finite() && secs > 0.0) {
        bail!("duration `{s}` must be positive");
    }
    if secs >= 1e9 {
        bail!("duration `{s}` is too long: at most 999,999,999 s (about 31 years)");
    }
    Ok(Duration::from_secs_f64(secs))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn durations() {
        assert_eq!(parse_duration("30s").unwrap(), Duration::from_secs(30));
        assert_eq!(parse_duration("2m").unwrap(), Duration::from_secs(120));
        assert_eq!(parse_duration("1.5h").unwrap(), Duration::from_secs(5400));
        assert_eq!(parse_duration("250ms").unwrap(), Duration::from_millis(250));
        assert_eq!(parse_duration("12").unwrap(), Duration::from_secs(12));
        assert!(parse_duration("-3s").unwrap_err().to_string().contains("positive"));
        let err = parse_duration("99999999999999999999h").unwrap_err().to_string();
        assert!(err.contains("too long"), "{err}");
        assert!(parse_duration("3 fortnights").is_err());
        assert!(parse_duration("fast").is_err());
    }
}
