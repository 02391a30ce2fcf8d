//! Where a grammar's mesh, texture and footprint files come from: the door that
//! compiles a grammar knows where its files lie, the compiler does not.

use crate::footprint::{FootprintLot, FootprintSet};
use genform_core::Mesh;

/// Loads the mesh assets a grammar declares with `mesh name = "path";`.
pub trait AssetResolver {
    /// Loads the mesh at `path`, exactly as written in the `.sg` file (the
    /// CLI resolves it relative to the grammar file). The error message is
    /// shown to the user next to the path.
    fn load_mesh(&self, path: &str) -> Result<Mesh, String>;

    /// Reads the image file at `path` of `texture("…")`, exactly as written
    /// in the `.sg` file (the CLI resolves it relative to the grammar file,
    /// like meshes): its bytes, which the compiler checks are a PNG file.
    /// The error message is shown to the user next to the path.
    fn load_texture(&self, path: &str) -> Result<Vec<u8>, String> {
        Err(format!("no texture files are available here (asked for \"{path}\")"))
    }

    /// Loads the footprints at `path` (`footprints "…";`): one list of
    /// world `(x, z)` corners per polygon.
    fn load_footprints(&self, path: &str) -> Result<Vec<Vec<[f64; 2]>>, String> {
        Err(format!("no footprint files are available here (asked for \"{path}\")"))
    }

    /// Loads the footprints at `path` with what the file says of each lot
    /// (its properties, its name in messages), where the origin of the
    /// local frame lies, and which lots were skipped and why. By default,
    /// [`AssetResolver::load_footprints`] without properties.
    fn load_footprint_set(&self, path: &str) -> Result<FootprintSet, String> {
        let lots = self.load_footprints(path)?;
        Ok(FootprintSet {
            lots: lots
                .into_iter()
                .enumerate()
                .map(|(k, corners)| FootprintLot::numbered(k, "footprint", corners))
                .collect(),
            origin: None,
            skipped: Vec::new(),
        })
    }
}

/// A resolver without assets: every `mesh` declaration is an error.
#[derive(Clone, Copy, Debug, Default)]
pub struct NoAssets;

impl AssetResolver for NoAssets {
    fn load_mesh(&self, path: &str) -> Result<Mesh, String> {
        Err(format!("no mesh assets are available here (asked for \"{path}\")"))
    }
}
