//! The memory budget: one number of bytes that every size a user sets
//! (optimizer populations, chains, particles, archives, voxel grids,
//! target pictures) is checked against *before* anything is allocated, so
//! a scene asking for more than the machine has stops with a message
//! naming the setting, its `line:col` and how to raise the budget, instead
//! of an allocation failure or the machine swapping.
//!
//! The budget defaults to half of the smallest of: the machine's memory
//! (`MemTotal` in `/proc/meminfo`), the cgroup's memory limit
//! (`/sys/fs/cgroup/memory.max`) and the process's address-space limit
//! (`ulimit -v`). Doors change it with [`set_budget`] (the CLI's
//! `--max-memory`). The sizes checked are estimates of what an optimizer
//! holds at its start (see [`estimate`]); they are deliberately on the
//! generous side of the real footprint only by constant factors, so a
//! setting refused here would not have fitted anyway.
//!
//! Those checks are per scene. The budget is also one for the whole
//! process: every run, comparison, sweep and breeding session holds a
//! [`Reservation`] of its scene's estimated bytes in the process's ledger
//! ([`reserve`]) for as long as it lives, and one that would take the
//! bytes held together past the budget is refused, naming what holds them
//! — so several runs of one server (the studio, Python threads), each
//! inside the budget alone, cannot together exhaust the machine.

use anyhow::{Result, bail};

use crate::toml_doc::Doc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Mutex, MutexGuard};

/// The budget set by a door (0: not set, use [`machine_default`]).
static BUDGET: AtomicU64 = AtomicU64::new(0);

/// Used when the machine's memory cannot be read (not Linux): 4 GiB.
const FALLBACK_BYTES: u64 = 4 << 30;

/// A memory budget and where it came from (shown in refusals).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Budget {
    /// Bytes that the sizes of one command may take together.
    pub bytes: u64,
    /// How it was chosen, e.g. "--max-memory 2G" or "half of this machine's 23.4 GB".
    pub origin: String,
}

/// Sets the budget of this process (the CLI's `--max-memory SIZE`);
/// refusals then name `--max-memory` as its origin.
pub fn set_budget(bytes: u64) {
    BUDGET.store(bytes.max(1), Ordering::Relaxed);
}

/// The budget in force: the one set with [`set_budget`], or
/// [`machine_default`].
pub fn budget() -> Budget {
    match BUDGET.load(Ordering::Relaxed) {
        0 => machine_default(),
        bytes => Budget { bytes, origin: format!("--max-memory {}", human(bytes as f64)) },
    }
}

/// Half of the smallest of the machine's memory, the cgroup limit and the
/// address-space limit (4 GiB if none can be read).
pub fn machine_default() -> Budget {
    let read = |p: &str| std::fs::read_to_string(p).ok();
    let mut limits: Vec<(u64, &str)> = Vec::new();
    if let Some(b) = read("/proc/meminfo").as_deref().and_then(meminfo_total) {
        limits.push((b, "this machine's memory"));
    }
    if let Some(b) = read("/sys/fs/cgroup/memory.max").and_then(|t| t.trim().parse::<u64>().ok()) {
        limits.push((b, "the cgroup's memory limit"));
    }
    if let Some(b) = read("/proc/self/limits").as_deref().and_then(address_space_limit) {
        limits.push((b, "the address-space limit (ulimit -v)"));
    }
    match limits.into_iter().min_by_key(|&(b, _)| b) {
        Some((b, what)) => Budget { bytes: b / 2, origin: format!("half of {what}, {}", human(b as f64)) },
        None => Budget {
            bytes: FALLBACK_BYTES,
            origin: format!("{} (the machine's memory is unknown)", human(FALLBACK_BYTES as f64)),
        },
    }
}

/// `MemTotal` of `/proc/meminfo`, in bytes.
fn meminfo_total(text: &str) -> Option<u64> {
    let line = text.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kib.checked_mul(1024)
}

/// The soft "Max address space" of `/proc/self/limits`, in bytes (`None`
/// when unlimited).
fn address_space_limit(text: &str) -> Option<u64> {
    let line = text.lines().find(|l| l.starts_with("Max address space"))?;
    line["Max address space".len()..].split_whitespace().next()?.parse().ok()
}

/// Parses a size such as `512M`, `3G`, `1.5GB`, `2GiB`, `800k` or a bare
/// number of bytes (K, M, G, T are powers of 1024).
pub fn parse_size(text: &str) -> std::result::Result<u64, String> {
    let t = text.trim();
    let split = t.find(|c: char| c.is_ascii_alphabetic()).unwrap_or(t.len());
    let (num, unit) = t.split_at(split);
    let value: f64 = num.trim().parse().map_err(|_| format!("`{text}` is not a size such as 512M, 3G or 1.5GB"))?;
    let scale: f64 = match unit.trim().to_ascii_lowercase().as_str() {
        "" | "b" => 1.0,
        "k" | "kb" | "kib" => 1024.0,
        "m" | "mb" | "mib" => 1024.0 * 1024.0,
        "g" | "gb" | "gib" => 1024.0 * 1024.0 * 1024.0,
        "t" | "tb" | "tib" => 1024.0 * 1024.0 * 1024.0 * 1024.0,
        u => return Err(format!("unknown size unit `{u}` in `{text}`; use K, M, G or T")),
    };
    let bytes = value * scale;
    if !(bytes.is_finite() && bytes >= 1.0) {
        return Err(format!("size `{text}` must be at least one byte"));
    }
    if bytes >= u64::MAX as f64 {
        return Err(format!("size `{text}` is too large"));
    }
    Ok(bytes as u64)
}

/// `bytes` as people read it, in powers of 1024 like [`parse_size`]:
/// "512 B", "3.2 KiB", "1.5 GiB", "4.8e20 B".
pub fn human(bytes: f64) -> String {
    const UNITS: [&str; 6] = ["B", "KiB", "MiB", "GiB", "TiB", "PiB"];
    let mut v = bytes;
    for u in UNITS {
        if v < 1024.0 {
            return if u == "B" { format!("{v:.0} {u}") } else { format!("{v:.1} {u}") };
        }
        v /= 1024.0;
    }
    format!("{bytes:.1e} B")
}

/// Rough bytes of one gene of a derivation-tree genome (2 header words,
/// a few parameters and links, 8 bytes each).
pub const GENE_BYTES: u64 = 64;
/// Rough bytes an optimizer keeps per individual besides its genes
/// (the genome's header, its fitness, selection and statistics entries).
pub const INDIVIDUAL_BYTES: u64 = 128;

/// `count` items of `each` bytes, saturating.
pub fn estimate(count: u64, each: u64) -> u128 {
    u128::from(count) * u128::from(each)
}

/// One size setting to check.
#[derive(Clone, Debug)]
pub struct Size<'a> {
    /// The TOML section, e.g. "ga" (empty for a top-level key).
    pub section: &'a str,
    /// The key, e.g. "population".
    pub key: &'a str,
    /// The value as written.
    pub value: u128,
    /// Bytes it needs (an estimate).
    pub bytes: u128,
    /// What the bytes are, e.g. "2 × 100000000 genomes of about 3.3 kB".
    pub what: String,
}

/// Refuses the first of `sizes` (settings of the scene `doc`) that needs
/// more than the [`budget`], and any whose total does: the error names the
/// setting's `file:line:col`, the bytes it needs and how to raise the
/// budget.
pub(crate) fn check_sizes(doc: &Doc, sizes: &[Size]) -> Result<()> {
    let budget = budget();
    let limit = u128::from(budget.bytes);
    let over = sizes.iter().find(|s| s.bytes > limit).or_else(|| {
        // Each fits alone; the largest is named when together they do not.
        let total: u128 = sizes.iter().map(|s| s.bytes).sum();
        (total > limit).then(|| sizes.iter().max_by_key(|s| s.bytes)).flatten()
    });
    let Some(s) = over else { return Ok(()) };
    let name = if s.section.is_empty() { s.key.to_string() } else { format!("[{}] {}", s.section, s.key) };
    let total: u128 = sizes.iter().map(|s| s.bytes).sum();
    let alone = if s.bytes > limit {
        String::new()
    } else {
        format!(" (with the scene's other sizes, {})", human(total as f64))
    };
    // Past 1 PiB no machine has the memory: only lowering the setting helps.
    let raise = match total.max(s.bytes).div_ceil(1 << 30) {
        gib if gib > 1 << 20 => " (no machine has that much memory)".to_string(),
        gib => format!(", or raise the budget with --max-memory {}G if the machine has the memory", gib.max(1)),
    };
    let path: Vec<&str> = [s.section, s.key].into_iter().filter(|p| !p.is_empty()).collect();
    Err(doc.refuse(
        &path,
        format!(
            "{name} = {} needs about {}{alone} ({}), more than the memory budget of {} ({}); lower `{}`{raise}",
            s.value,
            human(s.bytes as f64),
            s.what,
            human(budget.bytes as f64),
            budget.origin,
            s.key,
        ),
    ))
}

/// Refuses command-line limits (`(flag, value, bytes per item, what)`)
/// whose items alone would take more than the [`budget`]: a limit is what
/// a derivation may grow to before it is stopped, so one past the budget
/// would let it exhaust memory first.
pub fn check_flags(flags: &[(&str, Option<usize>, u64, &str)]) -> Result<()> {
    for &(flag, value, each, what) in flags {
        if let Some(n) = value {
            check_limit(&format!("{flag} {n}"), flag, n, each, what)?;
        }
    }
    Ok(())
}

/// Refuses a limit a grammar file sets (`setting`, e.g. ``"`max_modules:
/// 99999999999` (plant.ls:3:14)"``) whose items alone would take more than
/// the [`budget`], as [`check_flags`] does for flags; `lower` says what to
/// lower (e.g. "`max_modules:` in the file, or --max-modules").
pub fn check_limit(setting: &str, lower: &str, n: usize, each: u64, what: &str) -> Result<()> {
    let budget = budget();
    let bytes = estimate(n as u64, each);
    if bytes > u128::from(budget.bytes) {
        bail!(
            "{setting} lets a derivation grow to about {} ({n} {what} of about {} each), more than the memory \
             budget of {} ({}); lower {lower}, or raise the budget with --max-memory {}G if the machine has the memory",
            human(bytes as f64),
            human(each as f64),
            human(budget.bytes as f64),
            budget.origin,
            bytes.div_ceil(1 << 30).max(1),
        );
    }
    Ok(())
}

/// The sizes of a `[limits]` section: each limit bounds what one
/// derivation may grow to, per worker thread, so a limit whose items
/// alone exceed the budget is refused (`item_bytes` per item).
pub fn limit_sizes(limits: &[(&'static str, Option<usize>, u64, &'static str)]) -> Vec<Size<'static>> {
    limits
        .iter()
        .filter_map(|&(key, value, each, what)| {
            let n = value? as u64;
            Some(Size {
                section: "limits",
                key,
                value: u128::from(n),
                bytes: estimate(n, each),
                what: format!("{n} {what} of about {} each in one derivation", human(each as f64)),
            })
        })
        .collect()
}

/// What a reservation is refused with: the message names what is asked,
/// what is held and by whom, the budget and its origin. Doors tell it from
/// other errors (the studio answers 503) with `downcast_ref`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct OverBudget {
    /// Bytes asked for.
    pub asked: u64,
    /// Bytes held by others when it was asked.
    pub in_use: u64,
    /// The budget then.
    pub budget: u64,
    /// The whole refusal.
    pub message: String,
}

impl std::fmt::Display for OverBudget {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for OverBudget {}

/// The process's ledger of reservations.
pub(crate) struct Ledger {
    held: Mutex<Held>,
}

/// The reservations held: (id, bytes, what holds them).
struct Held {
    next: u64,
    holders: Vec<(u64, u64, String)>,
}

/// The ledger of this process.
static LEDGER: Ledger = Ledger::new();

impl Ledger {
    const fn new() -> Ledger {
        Ledger { held: Mutex::new(Held { next: 0, holders: Vec::new() }) }
    }

    fn lock(&self) -> MutexGuard<'_, Held> {
        // The ledger is consistent after every statement: a panic elsewhere leaves it usable.
        self.held.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Reserves `bytes` for `what` unless the bytes held with them would
    /// pass `budget`; `lower` names the setting that makes them (for the
    /// refusal).
    fn reserve(&'static self, bytes: u128, what: &str, lower: Option<&str>, budget: &Budget) -> Result<Reservation> {
        let mut held = self.lock();
        let in_use: u64 = held.holders.iter().map(|h| h.1).fold(0, u64::saturating_add);
        let fits = u64::try_from(bytes).ok().filter(|b| b.checked_add(in_use).is_some_and(|t| t <= budget.bytes));
        let Some(bytes) = fits else {
            let others: Vec<&str> = held.holders.iter().map(|h| h.2.as_str()).collect();
            let message = refusal(what, bytes, in_use, &others, budget, lower);
            let asked = u64::try_from(bytes).unwrap_or(u64::MAX);
            return Err(anyhow::Error::new(OverBudget { asked, in_use, budget: budget.bytes, message }));
        };
        held.next += 1;
        let id = held.next;
        held.holders.push((id, bytes, what.to_string()));
        Ok(Reservation { ledger: self, id, bytes })
    }

    fn in_use(&self) -> u64 {
        self.lock().holders.iter().map(|h| h.1).fold(0, u64::saturating_add)
    }

    fn holders(&self) -> usize {
        self.lock().holders.len()
    }

    fn release(&self, id: u64) {
        self.lock().holders.retain(|h| h.0 != id);
    }
}

/// Bytes of the memory budget held by a run, comparison, sweep or breeding
/// session for as long as it lives: dropping it gives them back.
pub struct Reservation {
    ledger: &'static Ledger,
    id: u64,
    bytes: u64,
}

impl Reservation {
    /// The bytes held.
    pub fn bytes(&self) -> u64 {
        self.bytes
    }
}

impl std::fmt::Debug for Reservation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Reservation").field("id", &self.id).field("bytes", &self.bytes).finish()
    }
}

impl Drop for Reservation {
    fn drop(&mut self) {
        self.ledger.release(self.id);
    }
}

/// Reserves `bytes` of the process's [`budget`] for `what` (a noun such as
/// "run" or "breeding session", as refusals name holders: "this run needs
/// about …, held by 2 other runs"), until the [`Reservation`] is dropped.
/// Refused (with an [`OverBudget`] error) when the bytes held with them
/// would pass the budget.
pub fn reserve(bytes: u128, what: String) -> Result<Reservation> {
    LEDGER.reserve(bytes, &what, None, &budget())
}

/// Reserves the total of `sizes` (a scene's, as [`check_sizes`] checks
/// them) for `what`, as [`reserve`]; a refusal suggests lowering the
/// largest of them.
pub(crate) fn reserve_sizes(sizes: &[Size], what: &str) -> Result<Reservation> {
    let total: u128 = sizes.iter().map(|s| s.bytes).fold(0, u128::saturating_add);
    let largest = sizes.iter().max_by_key(|s| s.bytes).map(setting_name);
    LEDGER.reserve(total, what, largest.as_deref(), &budget())
}

/// Bytes held by every [`Reservation`] of this process now.
pub fn in_use() -> u64 {
    LEDGER.in_use()
}

/// The budget and what is held of it, for a door to show (the studio's
/// `/api/status`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MemoryUse {
    /// The budget in force.
    pub budget: Budget,
    /// Bytes held by reservations.
    pub in_use: u64,
    /// Reservations held.
    pub holders: usize,
}

/// The budget and what is held of it now.
pub fn usage() -> MemoryUse {
    MemoryUse { budget: budget(), in_use: LEDGER.in_use(), holders: LEDGER.holders() }
}

/// `[section] key` (or the bare key) of a size.
fn setting_name(s: &Size) -> String {
    if s.section.is_empty() { s.key.to_string() } else { format!("[{}] {}", s.section, s.key) }
}

/// The refusal of `bytes` for `what` while `in_use` bytes are held by
/// `others` (each holder's noun).
fn refusal(what: &str, bytes: u128, in_use: u64, others: &[&str], budget: &Budget, lower: Option<&str>) -> String {
    let asked = human(bytes as f64);
    let of_budget = format!("the memory budget of {} ({})", human(budget.bytes as f64), budget.origin);
    if bytes > u128::from(budget.bytes) || others.is_empty() {
        let fix = match lower {
            Some(l) => format!("lower {l}"),
            None => "ask for less".to_string(),
        };
        return format!(
            "this {what} needs about {asked}, more than {of_budget}; {fix}, or raise the budget with --max-memory {}G \
             if the machine has the memory",
            bytes.div_ceil(1 << 30).max(1)
        );
    }
    // Holders by kind, in the order they came.
    let mut kinds: Vec<(&str, usize)> = Vec::new();
    for o in others {
        match kinds.iter_mut().find(|k| k.0 == *o) {
            Some(k) => k.1 += 1,
            None => kinds.push((o, 1)),
        }
    }
    let count = |(kind, n): (&str, usize)| if n == 1 { format!("1 {kind}") } else { format!("{n} {kind}s") };
    let holders = match kinds.as_slice() {
        [(kind, 1)] => format!("1 other {kind}"),
        [(kind, n)] => format!("{n} other {kind}s"),
        _ => format!("{} others ({})", others.len(), kinds.iter().map(|k| count(*k)).collect::<Vec<_>>().join(", ")),
    };
    let or_lower = lower.map(|l| format!(" or lower {l}")).unwrap_or_default();
    format!(
        "this {what} needs about {asked}, and {} of {of_budget} is held by {holders}; wait for one to finish{or_lower}",
        human(in_use as f64)
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    #[test]
    fn sizes_parse_with_units() {
        assert_eq!(parse_size("512"), Ok(512));
        assert_eq!(parse_size("2k"), Ok(2048));
        assert_eq!(parse_size("3G"), Ok(3 << 30));
        assert_eq!(parse_size("1.5GB"), Ok(3 << 29));
        assert_eq!(parse_size(" 2 GiB "), Ok(2 << 30));
        assert!(parse_size("lots").unwrap_err().contains("not a size"));
        assert!(parse_size("3Q").unwrap_err().contains("unknown size unit"));
        assert!(parse_size("0").unwrap_err().contains("at least one byte"));
        assert!(parse_size("99999999999999999999T").unwrap_err().contains("too large"));
    }

    #[test]
    fn proc_files_are_read() {
        assert_eq!(meminfo_total("MemTotal:       24500000 kB\nMemFree: 1 kB\n"), Some(24_500_000 * 1024));
        let limits = "Limit                     Soft Limit           Hard Limit           Units\n\
                      Max address space         3072000000           unlimited            bytes\n";
        assert_eq!(address_space_limit(limits), Some(3_072_000_000));
        assert_eq!(address_space_limit(&limits.replace("3072000000", "unlimited")), None);
    }

    #[test]
    fn refusals_name_setting_position_and_flag() {
        let text = "[ga]\npopulation = 99999999999999999\n";
        let huge = Size {
            section: "ga",
            key: "population",
            value: 99999999999999999,
            bytes: estimate(99999999999999999, 1000),
            what: "genomes".into(),
        };
        let doc = Doc::parse(Path::new("s.toml"), text).unwrap();
        let msg = check_sizes(&doc, &[huge]).unwrap_err().to_string();
        assert!(msg.starts_with("s.toml:2:14: [ga] population = 99999999999999999 needs about"), "{msg}");
        assert!(
            msg.contains("more than the memory budget") && msg.ends_with("no machine has that much memory)"),
            "{msg}"
        );
        // Just over the budget: a machine could have that much.
        let big = Size { bytes: u128::from(budget().bytes) + 1, ..huge_like() };
        let msg = check_sizes(&doc, &[big]).unwrap_err().to_string();
        assert!(
            msg.contains(", or raise the budget with --max-memory ")
                && msg.ends_with("G if the machine has the memory"),
            "{msg}"
        );
        let small = Size { bytes: 10_000, ..huge_like() };
        check_sizes(&doc, &[small]).unwrap();
    }

    fn huge_like() -> Size<'static> {
        Size { section: "ga", key: "population", value: 10, bytes: 0, what: "genomes".into() }
    }

    /// A ledger of its own (the process's is shared with every other test).
    fn ledger() -> &'static Ledger {
        Box::leak(Box::new(Ledger::new()))
    }

    fn thousand() -> Budget {
        Budget { bytes: 1000, origin: "--max-memory 1000 B".into() }
    }

    #[test]
    fn reservations_are_held_refused_and_given_back_on_drop() {
        let (l, b) = (ledger(), thousand());
        let first = l.reserve(600, "run", Some("[ga] population"), &b).unwrap();
        assert_eq!((first.bytes(), l.in_use(), l.holders()), (600, 600, 1));
        let e = l.reserve(500, "run", Some("[ga] population"), &b).unwrap_err();
        let over = e.downcast_ref::<OverBudget>().expect("an OverBudget refusal");
        assert_eq!((over.asked, over.in_use, over.budget), (500, 600, 1000));
        assert_eq!(
            e.to_string(),
            "this run needs about 500 B, and 600 B of the memory budget of 1000 B (--max-memory 1000 B) is held by \
             1 other run; wait for one to finish or lower [ga] population"
        );
        // A refusal holds nothing; what fits beside the first is admitted.
        assert_eq!(l.in_use(), 600);
        let second = l.reserve(400, "breeding session", None, &b).unwrap();
        assert_eq!(l.in_use(), 1000);
        let e = l.reserve(1, "run", None, &b).unwrap_err().to_string();
        assert!(e.contains("is held by 2 others (1 run, 1 breeding session); wait for one to finish"), "{e}");
        drop(first);
        assert_eq!((l.in_use(), l.holders()), (400, 1));
        let third = l.reserve(600, "run", None, &b).unwrap();
        drop((second, third));
        assert_eq!((l.in_use(), l.holders()), (0, 0));
        // Several of one kind are counted in the plural.
        let runs: Vec<Reservation> = (0..3).map(|_| l.reserve(300, "run", None, &b).unwrap()).collect();
        let e = l.reserve(200, "run", Some("[ge] population"), &b).unwrap_err().to_string();
        assert!(e.contains("900 B of the memory budget") && e.contains("held by 3 other runs;"), "{e}");
        drop(runs);
        assert_eq!(l.in_use(), 0);
    }

    #[test]
    fn more_than_the_whole_budget_is_refused_even_alone() {
        let (l, b) = (ledger(), thousand());
        let e = l.reserve(1001, "run", Some("[ga] population"), &b).unwrap_err().to_string();
        assert_eq!(
            e,
            "this run needs about 1001 B, more than the memory budget of 1000 B (--max-memory 1000 B); lower \
             [ga] population, or raise the budget with --max-memory 1G if the machine has the memory"
        );
        let e = l.reserve(u128::MAX, "sweep", None, &b).unwrap_err();
        assert_eq!(e.downcast_ref::<OverBudget>().unwrap().asked, u64::MAX);
        assert_eq!(l.in_use(), 0);
        // Exactly the budget fits, and nothing more then.
        let all = l.reserve(1000, "run", None, &b).unwrap();
        assert!(l.reserve(1, "run", None, &b).is_err());
        let none = l.reserve(0, "run", None, &b).unwrap();
        drop((all, none));
    }

    #[test]
    fn concurrent_reservations_never_pass_the_budget() {
        let (l, b) = (ledger(), thousand());
        // Eight threads ask for 300 bytes each at once: three fit.
        let start = std::sync::Barrier::new(8);
        let held = std::sync::Barrier::new(8);
        let admitted = std::sync::atomic::AtomicUsize::new(0);
        std::thread::scope(|s| {
            for _ in 0..8 {
                s.spawn(|| {
                    start.wait();
                    let r = l.reserve(300, "run", None, &b);
                    if r.is_ok() {
                        admitted.fetch_add(1, Ordering::SeqCst);
                    }
                    assert!(l.in_use() <= 1000);
                    held.wait();
                    drop(r);
                });
            }
        });
        assert_eq!(admitted.load(Ordering::SeqCst), 3);
        assert_eq!((l.in_use(), l.holders()), (0, 0));
        // Many threads reserving and dropping in a loop: the ledger never
        // holds more than the budget and ends empty.
        let b = &b;
        std::thread::scope(|s| {
            for t in 0..6u128 {
                s.spawn(move || {
                    for i in 0..2000u128 {
                        if let Ok(r) = l.reserve(100 + (t * 37 + i) % 400, "run", None, b) {
                            assert!(l.in_use() <= 1000);
                            drop(r);
                        }
                    }
                });
            }
        });
        assert_eq!((l.in_use(), l.holders()), (0, 0));
    }

    #[test]
    fn the_process_ledger_is_reached_through_reserve() {
        let r = reserve(1, "run".into()).unwrap();
        assert_eq!(r.bytes(), 1);
        assert!(in_use() >= 1 && usage().holders >= 1);
        let e = reserve(u128::from(u64::MAX), "run".into()).unwrap_err();
        assert!(e.downcast_ref::<OverBudget>().is_some(), "{e}");
        drop(r);
    }

    #[test]
    fn reserving_sizes_suggests_the_largest() {
        let sizes = [
            Size { section: "ga", key: "population", value: 1, bytes: u128::from(u64::MAX), what: String::new() },
            Size { section: "volume", key: "voxels", value: 1, bytes: 10, what: String::new() },
        ];
        let e = reserve_sizes(&sizes, "run").unwrap_err().to_string();
        assert!(e.starts_with("this run needs about") && e.contains("lower [ga] population"), "{e}");
    }

    #[test]
    fn human_sizes() {
        assert_eq!(human(512.0), "512 B");
        assert_eq!(human(3379.0), "3.3 KiB");
        assert_eq!(human(1.5 * 1024.0 * 1024.0 * 1024.0), "1.5 GiB");
        assert_eq!(human(4.8e20), "4.8e20 B");
    }
}
