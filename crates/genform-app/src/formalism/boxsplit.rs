//! Box-split grammars (`.bsg`): derive in a box of a block world
//! (optionally observing real Minecraft terrain) and write blocks, also
//! into a copy of a region file (`.mca`).

use anyhow::{Context, Result, bail};
use genform_boxsplit::{BoxGrammar, DeriveOptions};
use genform_core::{BlockGrid, BlockKind, Scene};
use genform_export::minecraft::{
    RegionFile, SchemVersion, read_terrain, region_coords, region_file_name, regions_for_box, write_region,
};
use genform_export::{BlockOptions, ExportOptions, Format};
use glam::IVec3;
use std::path::{Path, PathBuf};

use super::codons::{CodonDecoder, DecodeScratch, Decoded, Invalid, Phase, Rejection, exhausted, read_from, reject};
use super::options::SampleRequest;
use super::row::{Formalism, Genomes, Loaded, LoadedGrammar, Sample, ends_with_any, no_generator};
use super::scene_keys::{ModelSettings, SceneLimits};
use crate::files::{output_format, write_atomic, write_model_with};
use crate::text::compile_file;
use crate::toml_doc::Doc;

/// Default wraps of box-split and graph codon sources.
pub(crate) const DEFAULT_SOURCE_WRAPS: u32 = 2;

/// The box-split row of the table.
pub struct BoxSplitGrammars;

impl Formalism for BoxSplitGrammars {
    fn name(&self) -> &'static str {
        "box-split grammar"
    }

    fn extensions(&self) -> &'static [&'static str] {
        &[".bsg"]
    }

    fn sample_options(&self) -> &'static [&'static str] {
        &["--box", "--world", "--trace", "--schem-version", "--data-version"]
    }

    fn output_extensions(&self) -> &'static [&'static str] {
        REGION
    }

    fn genomes(&self) -> Genomes {
        Genomes::Codons
    }

    fn load(&self, path: &Path) -> Result<Box<dyn LoadedGrammar>> {
        let grammar = compile_file(path, genform_boxsplit::compile)?;
        Ok(Box::new(BoxFile { path: path.to_path_buf(), grammar }))
    }

    fn scene_keys(&self) -> &'static [&'static str] {
        &["box", "mapper.max_wraps"]
    }

    fn limit_keys(&self, _model: &ModelSettings) -> &'static [&'static str] {
        &[]
    }

    fn check_scene(&self, doc: &Doc, model: &ModelSettings) -> Result<()> {
        if model.box_corners.is_none() {
            return Err(doc.refuse(
                &["grammar"],
                "a box-split scene derives in a box: add `box = [x0, y0, z0, x1, y1, z1]` (two opposite corners, \
                 inclusive)",
            ));
        }
        Ok(())
    }

    fn decoder(
        &self,
        grammar: &Path,
        model: &ModelSettings,
        _limits: &SceneLimits,
        codon_range: u32,
    ) -> Result<Box<dyn CodonDecoder>> {
        let compiled = compile_file(grammar, genform_boxsplit::compile)?;
        let (min, max) = box_bounds(model.box_corners.context("a box-split scene needs `box`")?);
        let wraps = model.mapper.max_wraps.unwrap_or(DEFAULT_SOURCE_WRAPS);
        Ok(Box::new(BoxDecoder { grammar: compiled, min, max, range: codon_range, wraps }))
    }

    fn kind(&self, _model: &ModelSettings) -> &'static str {
        "box-split"
    }
}

/// The flat `.bsg` box `[x0, y0, z0, x1, y1, z1]` as `min..max_exclusive`.
pub(crate) fn box_bounds(c: [i32; 6]) -> (IVec3, IVec3) {
    let a = IVec3::new(c[0], c[1], c[2]);
    let b = IVec3::new(c[3], c[4], c[5]);
    (a.min(b), a.max(b) + IVec3::ONE)
}

/// Codons as the choices of a box-split derivation.
struct BoxDecoder {
    grammar: BoxGrammar,
    min: IVec3,
    max: IVec3,
    range: u32,
    wraps: u32,
}

impl CodonDecoder for BoxDecoder {
    fn scratch(&self) -> DecodeScratch {
        Box::new(())
    }

    fn decode(
        &self,
        codons: &[u32],
        _scratch: &mut DecodeScratch,
        scene: &mut Scene,
        detail: bool,
        lap: &mut dyn FnMut(Phase),
    ) -> Result<Decoded, Rejection> {
        let mut source = genform_core::CodonSource::new(codons, self.range, self.wraps);
        let d = self.grammar.derive(None, self.min, self.max, &mut source, &DeriveOptions::default());
        lap(Phase::Mapping);
        if let Some(r) = exhausted(codons, &source, detail) {
            return Err(r);
        }
        let d = d.map_err(|f| reject(Invalid::Derivation, detail, || f.message.clone()))?;
        scene.blocks.push(d.blocks);
        Ok(read_from(&source))
    }
}

/// The ending of region files, which samples write into a copy of the observed one.
const REGION: &[&str] = &[".mca"];

/// A compiled box-split grammar and the file it came from.
struct BoxFile {
    path: PathBuf,
    grammar: BoxGrammar,
}

impl LoadedGrammar for BoxFile {
    fn sample(&self, request: &SampleRequest) -> Result<Box<dyn Sample>> {
        let grammar = &self.grammar;
        let out = request.out.as_deref();
        let to_region = out.is_some_and(|p| ends_with_any(p, REGION));
        // --world and --box override what the grammar declares; a declared
        // world is relative to the grammar file.
        let world_path = request
            .world
            .clone()
            .or_else(|| grammar.default_world().map(|w| self.path.parent().unwrap_or(Path::new("")).join(w)));
        if to_region && world_path.is_none() {
            bail!("writing a region file (.mca) needs --world: the blocks go into a copy of the observed region");
        }
        let (min, max) = match (&request.box_corners, grammar.default_box()) {
            (Some(text), _) => parse_box(text)?,
            (None, Some(declared)) => declared,
            (None, None) => bail!(
                "box-split grammars derive in a box: give --box x0,y0,z0,x1,y1,z1 (two opposite corners, \
                 inclusive), or declare one in the grammar: `box x0, y0, z0, x1, y1, z1;`"
            ),
        };
        let preview = match out {
            Some(path) if !to_region => is_preview(path)?,
            _ => false,
        };
        // Previews show the ground around and behind the structure too, cut
        // open along the box's front (+z, towards the preview camera): one read
        // of that larger area serves the observers and the picture.
        // Otherwise one cell around the box: the grammar's `support`
        // declarations look at the terrain next to the box (the same cells
        // whatever the output, so every output holds the same structure).
        let margin = IVec3::new(PREVIEW_MARGIN, PREVIEW_MARGIN / 2, PREVIEW_MARGIN);
        let (read_min, read_max) = if preview {
            (min - margin, IVec3::new(max.x + margin.x, max.y + margin.y, max.z + SUPPORT_MARGIN))
        } else {
            (min - IVec3::splat(SUPPORT_MARGIN), max + IVec3::splat(SUPPORT_MARGIN))
        };
        let (regions, world) = match &world_path {
            Some(path) => {
                let World { files: regions, paths, mut missing } = load_world(path, read_min, read_max)?;
                if let Some(out) = out.filter(|_| to_region) {
                    // By the gate's identity, in every door, session or not.
                    if paths.iter().any(|p| crate::gate::same_file(p, out)) {
                        bail!(
                            "--out {} is the observed region itself; write into a copy (another path)",
                            out.display()
                        );
                    }
                }
                // Only regions the derivation box needs matter to the observers.
                let needed = regions_for_box(min, max);
                if let Some(out) = out.filter(|_| to_region) {
                    check_region_name(out, &needed)?;
                }
                missing.retain(|r| needed.contains(r));
                if !missing.is_empty() {
                    crate::notes::warn(&format!(
                        "warning: {} not found; the box's cells there observe as air",
                        missing.iter().map(|&(x, z)| region_file_name(x, z)).collect::<Vec<_>>().join(", ")
                    ));
                }
                let terrain = read_terrain(&regions, read_min, read_max).context("cannot read the terrain")?;
                (regions, Some(terrain))
            }
            None => (Vec::new(), None),
        };
        let options = DeriveOptions { limits: None, trace: request.trace.is_some() };
        let derivation = grammar.derive(world.as_ref(), min, max, &mut request.rng(), &options);
        let trace = match &derivation {
            Ok(d) => d.trace.as_ref(),
            Err(f) => Some(&f.trace),
        };
        if let (Some(path), Some(trace)) = (&request.trace, trace) {
            let json = serde_json::to_string_pretty(trace).context("cannot write the trace")?;
            write_atomic(path, json.as_bytes())?;
        }
        let d = match derivation {
            Ok(d) => d,
            Err(f) => {
                let hint =
                    if request.trace.is_some() { "" } else { " (--trace FILE.json records every choice and failure)" };
                // The file names the grammar in messages: its name may be empty.
                bail!("{}: the derivation failed: {}{hint}", self.path.display(), f.message);
            }
        };
        let summary = format!(
            "{} seed {}: {} applications, {} backtracks, {} blocks placed in {}..{}",
            grammar.name(),
            request.seed,
            d.stats.applications,
            d.stats.backtracks,
            d.blocks.set_count(),
            min,
            max - IVec3::ONE
        );
        let summary = match d.stats.unsupported {
            0 => summary,
            n => format!(
                "{summary} ({n} cells changed by `support`: blocks with nothing to hang from, stand on or lean against)"
            ),
        };
        let summary = match &d.site {
            None => summary,
            Some(site) => format!(
                "{summary}; site: floor at y {}, {} foundation blocks, {} cells cleared",
                site.floor, site.foundation, site.cleared
            ),
        };
        if let Some(site) = &d.site {
            if site.foundation_hanging > 0 {
                crate::notes::warn(&format!(
                    "warning: the site's foundation stands on nothing below the box in {} columns: start the box \
                     lower (at y {} or below), down in the ground",
                    site.foundation_hanging,
                    min.y - 1
                ));
            }
            if let Some([x, y, z]) = site.cut_wood.first() {
                crate::notes::warn(&format!(
                    "warning: the building cut a tree that reaches out of the box: {} of its log blocks outside \
                     the box (e.g. at {x}, {y}, {z}) stay without their trunk; widen the box to take the tree in, \
                     or move it",
                    site.cut_wood.len()
                ));
            }
        }
        let mut scene = Scene::new();
        scene.blocks.push(d.blocks);
        let schem_version = if request.schem_version == 3 { SchemVersion::V3 } else { SchemVersion::V2 };
        let blocks = BlockOptions { schem_version, data_version: request.data_version };
        Ok(Box::new(BoxSample { scene, summary, regions, terrain: world, front_z: max.z, blocks }))
    }

    fn describe(&self) -> String {
        let g = &self.grammar;
        let limits = g.limits();
        let mut out = format!("box-split grammar {}: axiom `{}`\n", g.name(), g.axiom());
        out.push_str(&format!(
            "limits: applications {}, backtracks {}, depth {}\n",
            limits.applications, limits.backtracks, limits.depth
        ));
        if let Some((min, max)) = g.default_box() {
            let max = max - IVec3::ONE;
            out.push_str(&format!("box: {},{},{},{},{},{}\n", min.x, min.y, min.z, max.x, max.y, max.z));
        }
        if let Some(world) = g.default_world() {
            out.push_str(&format!("world: {world}\n"));
        }
        out.push_str(&format!("rules: {}\n", g.rule_names().collect::<Vec<_>>().join(", ")));
        out.push_str(&format!("blocks: {}\n", g.blocks().iter().map(|b| b.to_string()).collect::<Vec<_>>().join(", ")));
        out
    }

    fn into_generator(self: Box<Self>) -> Result<Loaded> {
        Err(no_generator(
            &self.path,
            "box-split grammars have no derivation-tree genome: they derive in a box, choosing rules against \
             the world and backtracking as they go. They are evolved with codons that make those choices: write \
             a codon scene (see examples/scenes/ge_castle_volume.toml) for `genform evolve`, and rebuild a result \
             with `genform derive SCENE.toml --genome best-codons.json`",
        ))
    }
}

/// Whether `out` is a picture or mesh that shows the structure in its
/// surroundings (rather than a block file).
fn is_preview(out: &Path) -> Result<bool> {
    Ok(matches!(output_format(out)?, Format::Png | Format::Glb | Format::Obj))
}

/// A derived structure with what writing it needs: the observed regions
/// (for `.mca` copies) and terrain (for previews).
struct BoxSample {
    /// The placed blocks.
    scene: Scene,
    summary: String,
    regions: Vec<RegionFile>,
    terrain: Option<BlockGrid>,
    /// The box's front (exclusive z), where previews cut the terrain open.
    front_z: i32,
    blocks: BlockOptions,
}

impl Sample for BoxSample {
    fn scene(&self) -> &Scene {
        &self.scene
    }

    fn summary(&self) -> String {
        self.summary.clone()
    }

    fn write(&self, out: &Path, export: &ExportOptions) -> Result<Vec<PathBuf>> {
        let structure = &self.scene.blocks[0];
        if ends_with_any(out, REGION) {
            write_into_region(&self.regions, structure, out)?;
            return Ok(vec![out.to_path_buf()]);
        }
        let options = ExportOptions { blocks: self.blocks, ..*export };
        match &self.terrain {
            Some(terrain) if is_preview(out)? => {
                let mut scene = Scene::new();
                scene.blocks.push(terrain_context(terrain, structure, self.front_z));
                scene.blocks.push(structure.clone());
                write_model_with(&scene, out, &options)
            }
            _ => write_model_with(&self.scene, out, &options),
        }
    }
}

/// Parses `x0,y0,z0,x1,y1,z1` (two opposite corners, both inclusive, in
/// any order) into `min..max_exclusive`.
pub fn parse_box(text: &str) -> Result<(IVec3, IVec3)> {
    let v: Vec<i32> = text
        .split(',')
        .map(|s| s.trim().parse::<i32>())
        .collect::<Result<_, _>>()
        .with_context(|| format!("--box `{text}`: expected six integers x0,y0,z0,x1,y1,z1"))?;
    let [x0, y0, z0, x1, y1, z1] = v[..] else {
        bail!("--box `{text}`: expected six integers x0,y0,z0,x1,y1,z1 (two opposite corners, inclusive)");
    };
    if let Some(v) = v.iter().find(|v| v.unsigned_abs() > MAX_COORDINATE) {
        bail!(
            "--box `{text}`: {v} is past the edge of a Minecraft world; coordinates must lie within ±{MAX_COORDINATE}"
        );
    }
    let (a, b) = (IVec3::new(x0, y0, z0), IVec3::new(x1, y1, z1));
    Ok((a.min(b), a.max(b) + IVec3::ONE))
}

/// Largest `--box` coordinate: a Minecraft world's border (so the exclusive
/// corner and region arithmetic never overflow).
pub const MAX_COORDINATE: u32 = 30_000_000;

/// The region files a box needs and the coordinates of those not found.
struct World {
    files: Vec<RegionFile>,
    /// Where each of `files` was read from.
    paths: Vec<PathBuf>,
    missing: Vec<(i32, i32)>,
}

/// The region files a box needs, from one `.mca` file or a folder of them.
/// Regions the box needs that are not there are reported and left unset
/// (they observe as air).
fn load_world(path: &Path, min: IVec3, max: IVec3) -> Result<World> {
    // Admitted before anything is looked at, so a refused path reads the
    // same whether or not it exists.
    crate::gate::admit_read(path, "world")?;
    let needed = regions_for_box(min, max);
    let mut files = Vec::new();
    let mut paths = Vec::new();
    let mut missing = Vec::new();
    let candidates: Vec<(i32, i32, PathBuf)> = if path.is_dir() {
        // A world folder keeps its regions in `region/`.
        let dir = if path.join("region").is_dir() { path.join("region") } else { path.to_path_buf() };
        needed.iter().map(|&(x, z)| (x, z, dir.join(region_file_name(x, z)))).collect()
    } else {
        let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        let Some((x, z)) = region_coords(&name) else {
            bail!("{}: a region file is named r.X.Z.mca (or give the folder that holds them)", path.display());
        };
        vec![(x, z, path.to_path_buf())]
    };
    for &(x, z) in &needed {
        match candidates.iter().find(|c| c.0 == x && c.1 == z) {
            Some((_, _, p)) if p.exists() => {
                let bytes = crate::gate::read_bytes(p, "region file")?;
                files.push(RegionFile { x, z, bytes });
                paths.push(p.clone());
            }
            _ => missing.push((x, z)),
        }
    }
    if files.is_empty() {
        bail!(
            "the box {min}..{max} needs region(s) {}, which {} does not hold",
            needed.iter().map(|&(x, z)| region_file_name(x, z)).collect::<Vec<_>>().join(", "),
            path.display()
        );
    }
    Ok(World { files, paths, missing })
}

/// Blocks of terrain around the box that previews show with the structure.
const PREVIEW_MARGIN: i32 = 8;

/// Blocks of terrain around the box that derivations see (for `support`).
const SUPPORT_MARGIN: i32 = 1;

/// The observed terrain under and around a structure, for previews: the
/// world's non-air blocks where the structure placed nothing, in front of
/// `front_z` (the preview's cut along the box's front).
fn terrain_context(terrain: &BlockGrid, structure: &BlockGrid, front_z: i32) -> BlockGrid {
    let mut out = terrain.clone();
    let mut cleared = Vec::new();
    for (p, c) in terrain.iter_set() {
        let placed = structure.get(p).is_some();
        if placed || p.z >= front_z || terrain.palette[c as usize].kind() == BlockKind::Air {
            cleared.push(p);
        }
    }
    for p in cleared {
        if let Some(i) = out.index(p) {
            out.cells[i] = BlockGrid::UNSET;
        }
    }
    out
}

/// Refuses an output region file named for another region than the one
/// the box lies in (Minecraft places a region's chunks by its file name),
/// and says what to rename an output that has no region name.
fn check_region_name(out: &Path, needed: &[(i32, i32)]) -> Result<()> {
    let &[(x, z)] = needed else { return Ok(()) };
    let name = out.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    match region_coords(&name) {
        Some(named) if named != (x, z) => bail!(
            "--out {} names region {},{}, but the box lies in region {x},{z}: Minecraft places a region's chunks \
             by its file name, so name the output {}",
            out.display(),
            named.0,
            named.1,
            region_file_name(x, z)
        ),
        Some(_) => {}
        None => crate::notes::warn(&format!(
            "note: {} holds region {x},{z}; Minecraft reads a region by its file name, so copy it into a world as {}",
            out.display(),
            region_file_name(x, z)
        )),
    }
    Ok(())
}

/// Writes the blocks into a copy of the one region file the box lies in.
fn write_into_region(regions: &[RegionFile], blocks: &BlockGrid, out: &Path) -> Result<()> {
    let [region] = regions else {
        bail!(
            "the box spans {} region files; a .mca output holds one — choose a box inside one region (512×512 blocks)",
            regions.len()
        );
    };
    let bytes = write_region(region, blocks).context("cannot write the region")?;
    write_atomic(out, &bytes)
}
