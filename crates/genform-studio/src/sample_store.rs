//! The samples a studio has made, by number: the models `POST /api/sample`
//! answered with, kept for download until newer ones push them out.

use genform_app::Sample;
use genform_export::ExportOptions;
use std::path::PathBuf;
use std::sync::{Arc, Mutex};

use super::api::Table;

/// Samples kept for download; older ones are forgotten (their files stay).
pub(crate) const KEEP_SAMPLES: usize = 64;

/// A sampled model and the formats it can be downloaded in.
pub struct SampleEntry {
    pub(crate) sample: Box<dyn Sample>,
    pub(crate) formats: Vec<String>,
    pub(crate) export: ExportOptions,
    /// Its folder under `--out/.samples/`.
    pub(crate) dir: PathBuf,
    /// For download names.
    pub(crate) stem: String,
    pub(crate) seed: u64,
    /// One writer at a time.
    pub(crate) writing: Mutex<()>,
}

/// The samples of this server, by number.
#[derive(Default)]
pub struct Samples {
    entries: Table<SampleEntry>,
}

impl Samples {
    pub(crate) fn insert(&self, make: impl FnOnce(u64) -> SampleEntry) -> (u64, Arc<SampleEntry>) {
        let mut guard = self.entries.lock().unwrap_or_else(|p| p.into_inner());
        guard.0 += 1;
        let id = guard.0;
        let entry = Arc::new(make(id));
        guard.1.insert(id, entry.clone());
        while guard.1.len() > KEEP_SAMPLES {
            guard.1.pop_first();
        }
        (id, entry)
    }

    pub(crate) fn get(&self, id: u64) -> Option<Arc<SampleEntry>> {
        self.entries.lock().unwrap_or_else(|p| p.into_inner()).1.get(&id).cloned()
    }
}
