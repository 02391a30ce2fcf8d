//! `genform.load`, `Grammar` and `Model`: any formalism of the CLI's table
//! (`genform_app::formalism::FORMALISMS`), sampled, derived from genomes,
//! exported, meshed into NumPy arrays.

use anyhow::Result;
use genform_app::{GrammarHandle, Sample, SampleRequest};
use genform_core::scene::Tessellation;
use genform_core::{Genome, Limits, Scene};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};
use std::path::PathBuf;
use std::sync::Arc;

use crate::errors::{OrRaise, Whole, error};
use crate::mesh;

/// A compiled grammar, shared by the models drawn from it.
pub type GrammarCore = GrammarHandle;

/// Expresses `genome` under `limits` into a model of `core`.
pub fn derive(core: &Arc<GrammarCore>, genome: Genome, limits: Limits) -> Result<Model> {
    let (scene, summary) = core.derive(&genome, limits)?;
    Ok(Model { body: Body::Scene(Box::new(scene)), genome: Some(genome), grammar: Some(core.clone()), limits, summary })
}

/// A compiled grammar of any formalism (`genform.load(path)`).
#[pyclass(module = "genform", frozen)]
pub struct Grammar {
    /// The grammar.
    pub core: Arc<GrammarCore>,
}

/// A path argument: `str` or `os.PathLike`.
pub fn path_arg(obj: &Bound<'_, PyAny>) -> PyResult<PathBuf> {
    obj.extract::<PathBuf>()
}

#[pyfunction]
/// Compiles a grammar file; the formalism follows the extension.
pub fn load(path: &Bound<'_, PyAny>) -> PyResult<Grammar> {
    let path = path_arg(path)?;
    Ok(Grammar { core: Arc::new(GrammarHandle::open(&path).or_raise()?) })
}

/// 8-bit sRGB as floats in [0, 1].
fn unit_rgb([r, g, b]: [u8; 3]) -> (f32, f32, f32) {
    (f32::from(r) / 255.0, f32::from(g) / 255.0, f32::from(b) / 255.0)
}

#[pyfunction]
/// The display colour of a tag as sRGB in [0, 1], the GLB materials' and
/// previews' palette (a trailing `#rrggbb` wins, else a hash of the name).
pub fn tag_color(name: &str) -> (f32, f32, f32) {
    unit_rgb(genform_export::tag_color(name))
}

#[pyfunction]
/// The formalisms genform loads: `{"name", "extensions"}` per row.
pub fn formalisms(py: Python<'_>) -> PyResult<Vec<Bound<'_, PyDict>>> {
    genform_app::formalisms()
        .into_iter()
        .map(|f| {
            let d = PyDict::new(py);
            d.set_item("name", f.name())?;
            d.set_item("extensions", f.extensions().to_vec())?;
            Ok(d)
        })
        .collect()
}

/// `genform sample`'s options from keyword arguments (flag names without
/// the dashes, `-` as `_`), checked by the application's option table.
fn request(seed: u64, options: Option<&Bound<'_, PyDict>>) -> PyResult<SampleRequest> {
    let mut r = SampleRequest { given: vec!["--seed".into()], ..SampleRequest::new(seed) };
    let Some(options) = options else { return Ok(r) };
    let json = options.py().import("json")?;
    for (key, value) in options.iter() {
        let key: String = key.extract()?;
        if value.is_none() {
            continue;
        }
        // Paths (str or os.PathLike) as text; everything else as JSON.
        let value: serde_json::Value = match value.extract::<PathBuf>() {
            Ok(p) if !value.is_instance_of::<pyo3::types::PyString>() => p.display().to_string().into(),
            _ => {
                let text: String = json.call_method1("dumps", (value,))?.extract()?;
                serde_json::from_str(&text).map_err(|e| error(format!("option `{key}`: {e}")))?
            }
        };
        r.set(&key, &value, &|s| Ok(PathBuf::from(s))).map_err(|e| error(format!("sample(): {e:#}")))?;
    }
    Ok(r)
}

#[pymethods]
impl Grammar {
    /// The grammar file.
    #[getter]
    fn path(&self) -> String {
        self.core.path.display().to_string()
    }

    /// The grammar's name (its generator's name, else the file's stem).
    #[getter]
    fn name(&self) -> String {
        match &self.core.generator {
            Some(g) => g.name.clone(),
            None => self.core.path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default(),
        }
    }

    /// The formalism's name, e.g. "shape grammar".
    #[getter]
    fn formalism(&self) -> &'static str {
        self.core.formalism.name()
    }

    /// Whether the grammar has a generator graph (genomes, derive, evolve).
    #[getter]
    fn has_generator(&self) -> bool {
        self.core.generator.is_some()
    }

    /// What `genform info` prints.
    fn info(&self) -> String {
        self.core.loaded.describe()
    }

    /// Draws one model, as `genform sample --seed SEED` does.
    #[pyo3(signature = (seed = Whole(0), **options))]
    fn sample(&self, py: Python<'_>, seed: Whole<u64>, options: Option<&Bound<'_, PyDict>>) -> PyResult<Model> {
        let mut req = request(seed.0, options)?;
        self.core.formalism.check(&req).or_raise()?;
        let core = self.core.clone();
        py.detach(move || sample(&core, &mut req)).or_raise()
    }

    /// Expresses a genome (a dict like `Model.genome`, or its JSON text).
    fn derive(&self, py: Python<'_>, genome: &Bound<'_, PyAny>) -> PyResult<Model> {
        let text = genome_text(py, genome)?;
        let genome = self.core.parse_genome(&text).or_raise()?;
        let limits = self.core.generator().or_raise()?.limits;
        let core = self.core.clone();
        py.detach(move || derive(&core, genome, limits)).or_raise()
    }

    fn __repr__(&self) -> String {
        format!("<genform.Grammar {} ({})>", self.core.path.display(), self.core.formalism.name())
    }

    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<(Bound<'py, PyAny>, (String,))> {
        Ok((py.import("genform")?.getattr("load")?, (self.path(),)))
    }
}

/// A genome argument as JSON text: a `str`, or anything `json.dumps` takes.
pub fn genome_text(py: Python<'_>, genome: &Bound<'_, PyAny>) -> PyResult<String> {
    match genome.extract::<String>() {
        Ok(s) => Ok(s),
        Err(_) => py.import("json")?.call_method1("dumps", (genome,))?.extract(),
    }
}

/// One sample; grammars with a generator graph keep the genome, so the
/// model can be derived again and evolved.
fn sample(core: &Arc<GrammarCore>, req: &mut SampleRequest) -> Result<Model> {
    req.keep_genome = core.generator.is_some();
    let s = core.guarded(|| core.loaded.sample(req))?;
    let genome = s.genome().cloned();
    let limits = core.generator.as_ref().map_or(Limits::default(), |g| req.limits.apply(g.limits));
    let summary = s.summary();
    Ok(Model { body: Body::Sample(s), genome, grammar: Some(core.clone()), limits, summary })
}

/// A point as Python sees it.
type Point = (f32, f32, f32);

/// What a model is: a formalism's sample (which may write its own formats)
/// or a Scene expressed from a genome.
pub enum Body {
    /// From `Grammar.sample`.
    Sample(Box<dyn Sample>),
    /// From a genome.
    Scene(Box<Scene>),
}

/// One derived model.
#[pyclass(module = "genform", frozen)]
pub struct Model {
    /// The model.
    pub body: Body,
    /// Its genome, for grammars with a generator graph.
    pub genome: Option<Genome>,
    /// The grammar it came from (none for a codon scene's phenotype, whose
    /// grammar was mapped from codons).
    pub grammar: Option<Arc<GrammarCore>>,
    /// The limits it was derived under.
    pub limits: Limits,
    /// One line about it.
    pub summary: String,
}

impl Model {
    /// The Scene.
    pub fn scene(&self) -> &Scene {
        match &self.body {
            Body::Sample(s) => s.scene(),
            Body::Scene(s) => s,
        }
    }

    /// A model that is only its scene (a codon scene's best phenotype).
    pub fn of_scene(scene: Scene, summary: String) -> Model {
        Model { body: Body::Scene(Box::new(scene)), genome: None, grammar: None, limits: Limits::default(), summary }
    }

    /// The genome's JSON text.
    pub fn genome_json(&self) -> Option<String> {
        let g = self.grammar.as_ref()?.generator.as_ref()?;
        Some(self.genome.as_ref()?.to_json(g.generator.graph()))
    }
}

#[pymethods]
impl Model {
    /// The genome as JSON-able data (None for formalisms without genomes).
    #[getter]
    fn genome<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        match self.genome_json() {
            Some(text) => Ok(Some(py.import("json")?.call_method1("loads", (text,))?)),
            None => Ok(None),
        }
    }

    /// The genome as JSON text.
    #[pyo3(name = "genome_json")]
    fn py_genome_json(&self) -> Option<String> {
        self.genome_json()
    }

    /// One line about the model.
    #[getter]
    fn summary(&self) -> String {
        self.summary.clone()
    }

    /// The grammar the model came from (None for a codon scene's phenotype).
    #[getter]
    fn grammar(&self) -> Option<Grammar> {
        self.grammar.clone().map(|core| Grammar { core })
    }

    /// (vertices (N, 3) float32, faces (M, 3) uint32), in the OBJ file's order.
    fn mesh<'py>(&self, py: Python<'py>) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
        let a = py.detach(|| mesh::arrays(self.scene(), Tessellation::default()));
        let (nv, nf) = (a.vertices.len() / 3, a.faces.len() / 3);
        // from_vec hands the buffers to NumPy without copying them.
        let v = PyArray1::from_vec(py, a.vertices).reshape([nv, 3])?;
        let f = PyArray1::from_vec(py, a.faces).reshape([nf, 3])?;
        Ok((v.into_any(), f.into_any()))
    }

    /// (group index per face of `mesh()`, uint32 (M,); group names: the
    /// scene's tags, then one per block state), for one material per tag.
    fn face_tags<'py>(&self, py: Python<'py>) -> PyResult<(Bound<'py, PyAny>, Vec<String>)> {
        let a = py.detach(|| mesh::arrays(self.scene(), Tessellation::default()));
        Ok((PyArray1::from_vec(py, a.tags).into_any(), a.tag_names))
    }

    /// The surfaces' typed edges (Genr8/HEMLS growth): (positions (N, 3)
    /// float32, +y up as in `mesh()`, every surface's points one after the
    /// other; edges (M, 2) uint32 into them; types (M,) int32, -1 for
    /// untyped; {type: colour as sRGB in [0, 1]} for the types in use, the
    /// GLB's `edge<N>` materials' colours). Empty arrays without surfaces.
    #[allow(clippy::type_complexity)]
    fn surface_edges<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>, Bound<'py, PyAny>, Bound<'py, PyDict>)> {
        let scene = genform_export::surfaces_y_up(self.scene());
        let (mut points, mut edges, mut types) = (Vec::<f32>::new(), Vec::<u32>::new(), Vec::<i32>::new());
        let colors = PyDict::new(py);
        for surface in &scene.surfaces {
            let base = (points.len() / 3) as u32;
            points.extend(surface.positions.iter().flat_map(|p| p.to_array()));
            for e in &surface.edges {
                edges.extend([base + e.a, base + e.b]);
                let kind = if e.kind == genform_core::SurfaceEdge::UNTYPED { -1 } else { e.kind as i32 };
                types.push(kind);
                if !colors.contains(kind)? {
                    colors.set_item(kind, unit_rgb(genform_export::edge_color(e.kind)))?;
                }
            }
        }
        let (np, ne) = (points.len() / 3, types.len());
        let p = PyArray1::from_vec(py, points).reshape([np, 3])?;
        let e = PyArray1::from_vec(py, edges).reshape([ne, 2])?;
        Ok((p.into_any(), e.into_any(), PyArray1::from_vec(py, types).into_any(), colors))
    }

    /// The display colour of each group of `face_tags()` (same order), as
    /// sRGB in [0, 1]: the colours of the GLB's materials (tags through the
    /// tag palette, block states through the block palette).
    fn tag_colors(&self, py: Python<'_>) -> Vec<(f32, f32, f32)> {
        let a = py.detach(|| mesh::arrays(self.scene(), Tessellation::default()));
        a.tag_colors.iter().map(|c| unit_rgb(*c)).collect()
    }

    /// Triangles of instances, polygons, a flat drawing's strokes and
    /// shapes, surfaces and block meshes (the faces of `mesh()`).
    fn triangle_count(&self, py: Python<'_>) -> usize {
        let scene = &*genform_export::drawing_geometry(self.scene());
        if scene.blocks.is_empty() {
            return scene.triangle_count(Tessellation::default());
        }
        py.detach(|| mesh::arrays(scene, Tessellation::default()).faces.len() / 3)
    }

    /// ((min x, y, z), (max x, y, z)) of all geometry, blocks included;
    /// None when empty.
    fn bounds(&self, py: Python<'_>) -> Option<(Point, Point)> {
        let drawn = genform_export::drawing_geometry(self.scene());
        let scene = &*genform_export::surfaces_y_up(&drawn);
        let (lo, hi) = if scene.blocks.is_empty() {
            scene.bounds(Tessellation::default())?
        } else {
            let a = py.detach(|| mesh::arrays(scene, Tessellation::default()));
            let mut points = a.vertices.chunks_exact(3).map(|c| glam::Vec3::new(c[0], c[1], c[2]));
            let first = points.next()?;
            points.fold((first, first), |(lo, hi), p| (lo.min(p), hi.max(p)))
        };
        Some((lo.into(), hi.into()))
    }

    /// Writes the model in the format the extension names; returns the files written.
    fn save(&self, py: Python<'_>, path: &Bound<'_, PyAny>) -> PyResult<Vec<String>> {
        let path = path_arg(path)?;
        let written = py
            .detach(|| match &self.body {
                Body::Sample(s) => {
                    let extra = self.grammar.as_ref().map_or(&[][..], |g| g.formalism.output_extensions());
                    if !genform_app::ends_with_any(&path, extra) && genform_export::Format::from_path(&path).is_none() {
                        return Err(genform_app::unknown_format(&path, extra));
                    }
                    let write = || s.write(&path, &genform_export::ExportOptions::default());
                    match &self.grammar {
                        Some(g) => g.guarded(write),
                        None => write(),
                    }
                }
                Body::Scene(scene) => match &self.grammar {
                    Some(g) => g.guarded(|| genform_app::write_model(scene, &path)),
                    None => genform_app::write_model(scene, &path),
                },
            })
            .or_raise()?;
        Ok(written.iter().map(|p| p.display().to_string()).collect())
    }

    /// A shaded preview as PNG bytes.
    #[pyo3(signature = (width = Whole(512), height = Whole(512)))]
    fn png<'py>(&self, py: Python<'py>, width: Whole<u32>, height: Whole<u32>) -> PyResult<Bound<'py, PyBytes>> {
        let (width, height) = (width.0, height.0);
        if width == 0 || height == 0 || width > 8192 || height > 8192 {
            return Err(error(format!("png(): width and height must be 1 to 8192, not {width}×{height}")));
        }
        let opts = genform_export::ExportOptions {
            render: genform_export::RenderOptions { width, height, ..Default::default() },
            ..Default::default()
        };
        let bytes = py
            .detach(|| genform_export::export(self.scene(), genform_export::Format::Png, &opts))
            .map_err(|e| error(format!("cannot render the preview: {e}")))?;
        Ok(PyBytes::new(py, &bytes))
    }

    /// Jupyter's inline picture.
    fn _repr_png_<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyBytes>> {
        self.png(py, Whole(400), Whole(300))
    }

    fn __repr__(&self) -> String {
        format!("<genform.Model {}>", self.summary)
    }

    /// Models with a genome pickle as (grammar path, genome, limits), for Ray.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
        let (Some(text), Some(grammar)) = (self.genome_json(), &self.grammar) else {
            return Err(error("only models with a genome can be pickled (this formalism has none)"));
        };
        let l = self.limits;
        let args = (grammar.path.display().to_string(), text, (l.max_genes, l.max_depth, l.max_primitives));
        Ok((py.import("genform")?.getattr("_model_from_genome")?, args.into_pyobject(py)?.into_any()))
    }
}

#[pyfunction]
/// Rebuilds a pickled model: `grammar.derive(genome)` under `limits`.
pub fn derive_with_limits(
    py: Python<'_>,
    grammar: &Grammar,
    genome: &str,
    limits: (usize, usize, usize),
) -> PyResult<Model> {
    let genome = grammar.core.parse_genome(genome).or_raise()?;
    let limits = Limits { max_genes: limits.0, max_depth: limits.1, max_primitives: limits.2 };
    let core = grammar.core.clone();
    py.detach(move || derive(&core, genome, limits)).or_raise()
}
