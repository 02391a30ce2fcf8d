//! Graph grammars (`.gg.yaml`): rewrite the host graph and write the result
//! as a drawing (SVG, PNG) or as a graph (YAML).

use anyhow::{Context, Result};
use genform_core::Scene;
use genform_graph::{Graph, GraphGrammar};
use std::path::{Path, PathBuf};

use super::boxsplit::DEFAULT_SOURCE_WRAPS;
use super::codons::{CodonDecoder, DecodeScratch, Decoded, Invalid, Phase, Rejection, exhausted, read_from, reject};
use super::options::SampleRequest;
use super::row::{Formalism, Genomes, Loaded, LoadedGrammar, Sample, ends_with_any, no_generator};
use super::scene_keys::{ModelSettings, SceneLimits};
use crate::files::{write_atomic_with, write_model_with};
use crate::text::compile_file;
use genform_core::scene::{Polygon, Shape2dKind};
use genform_export::ExportOptions;
use glam::{Vec2, Vec3};

/// Default `[limits] elements` of graph grammars in codon scenes.
pub const SCENE_MAX_ELEMENTS: usize = 20_000;

/// The graph-grammar row of the table.
pub struct GraphGrammars;

/// The endings of graph outputs (the derived graph as YAML).
const YAML: &[&str] = &[".yaml", ".yml"];

impl Formalism for GraphGrammars {
    fn name(&self) -> &'static str {
        "graph grammar"
    }

    fn extensions(&self) -> &'static [&'static str] {
        &[".gg.yaml"]
    }

    fn sample_options(&self) -> &'static [&'static str] {
        &["--steps", "--max-modules"]
    }

    fn output_extensions(&self) -> &'static [&'static str] {
        YAML
    }

    fn genomes(&self) -> Genomes {
        Genomes::Codons
    }

    fn load(&self, path: &Path) -> Result<Box<dyn LoadedGrammar>> {
        let grammar = compile_file(path, genform_graph::compile)?;
        Ok(Box::new(GraphFile { path: path.to_path_buf(), grammar }))
    }

    fn scene_keys(&self) -> &'static [&'static str] {
        &["steps", "mapper.max_wraps"]
    }

    fn limit_keys(&self, _model: &ModelSettings) -> &'static [&'static str] {
        &["elements"]
    }

    fn decoder(
        &self,
        grammar: &Path,
        model: &ModelSettings,
        limits: &SceneLimits,
        codon_range: u32,
    ) -> Result<Box<dyn CodonDecoder>> {
        let compiled = compile_file(grammar, genform_graph::compile)?;
        Ok(Box::new(GraphDecoder {
            grammar: compiled,
            steps: model.steps.map(|s| s as usize),
            max_elements: limits.elements.unwrap_or(SCENE_MAX_ELEMENTS),
            range: codon_range,
            wraps: model.mapper.max_wraps.unwrap_or(DEFAULT_SOURCE_WRAPS),
        }))
    }

    fn kind(&self, _model: &ModelSettings) -> &'static str {
        "graph"
    }
}

/// Codons as the choices of a graph derivation (which matches, which
/// options).
struct GraphDecoder {
    grammar: GraphGrammar,
    steps: Option<usize>,
    max_elements: usize,
    range: u32,
    wraps: u32,
}

impl CodonDecoder for GraphDecoder {
    /// The last derived graph, whose allocations the next derivation reuses.
    fn scratch(&self) -> DecodeScratch {
        Box::new(None::<Graph>)
    }

    fn decode(
        &self,
        codons: &[u32],
        scratch: &mut DecodeScratch,
        scene: &mut Scene,
        detail: bool,
        lap: &mut dyn FnMut(Phase),
    ) -> Result<Decoded, Rejection> {
        let kept = scratch.downcast_mut::<Option<Graph>>().expect("a graph scratch holds a graph");
        let mut source = genform_core::CodonSource::new(codons, self.range, self.wraps);
        let d = self.grammar.derive_reusing(&mut source, self.steps, self.max_elements, kept.take());
        lap(Phase::Mapping);
        if let Some(r) = exhausted(codons, &source, detail) {
            return Err(r);
        }
        let d = d.map_err(|e| {
            let reason = match e {
                genform_graph::DeriveError::TooManyElements { .. } => Invalid::ElementLimit,
                _ => Invalid::Derivation,
            };
            reject(reason, detail, || e.to_string())
        })?;
        *scene = d.graph.to_scene();
        *kept = Some(d.graph);
        drawing_as_polygons(scene);
        Ok(read_from(&source))
    }
}

/// Segments of circles drawn as polygons.
const CIRCLE_SEGMENTS: usize = 16;

/// Adds a polygon (z = 0) for every filled 2D shape and stroked line of a
/// graph drawing, so the image and volume scorers, which see polygons but
/// not SVG shapes, see the drawing: rectangles as quads, circles as
/// 16-gons, lines as quads as wide as their stroke. Paths and images are
/// left out.
fn drawing_as_polygons(scene: &mut Scene) {
    let at = |p: Vec2| Vec3::new(p.x, p.y, 0.0);
    let mut polygons = Vec::new();
    for shape in &scene.shapes2d {
        let points: Vec<Vec3> = match &shape.kind {
            Shape2dKind::Rect { min, size } => {
                let (a, b) = (*min, *min + *size);
                vec![at(a), at(Vec2::new(b.x, a.y)), at(b), at(Vec2::new(a.x, b.y))]
            }
            Shape2dKind::Circle { center, radius } => (0..CIRCLE_SEGMENTS)
                .map(|i| {
                    let t = std::f32::consts::TAU * i as f32 / CIRCLE_SEGMENTS as f32;
                    at(*center + *radius * Vec2::new(t.cos(), t.sin()))
                })
                .collect(),
            Shape2dKind::Line { from, to } => {
                let width = shape
                    .attributes
                    .iter()
                    .find(|(k, _)| k == "stroke-width")
                    .and_then(|(_, v)| v.parse::<f32>().ok())
                    .unwrap_or(genform_graph::DEFAULT_STROKE_WIDTH as f32);
                let d = *to - *from;
                if d.length_squared() == 0.0 || width.is_nan() || width <= 0.0 {
                    continue;
                }
                let n = Vec2::new(-d.y, d.x).normalize() * (0.5 * width);
                vec![at(*from + n), at(*to + n), at(*to - n), at(*from - n)]
            }
            Shape2dKind::Path { .. } | Shape2dKind::Image { .. } => continue,
        };
        polygons.push(Polygon { points, tag: shape.tag });
    }
    scene.polygons.extend(polygons);
}

/// A compiled graph grammar and the file it came from.
struct GraphFile {
    path: PathBuf,
    grammar: GraphGrammar,
}

impl LoadedGrammar for GraphFile {
    fn sample(&self, request: &SampleRequest) -> Result<Box<dyn Sample>> {
        let grammar = &self.grammar;
        let max_elements = request.max_modules.unwrap_or(genform_graph::DEFAULT_MAX_ELEMENTS);
        let d = grammar
            .derive(&mut request.rng(), request.steps.map(|s| s as usize), max_elements)
            .with_context(|| format!("{}: the derivation stopped", grammar.name()))?;
        let (v, e) = (d.graph.vertex_count(), d.graph.edge_count());
        let summary = format!(
            "{} seed {}: {} steps, {v} vertices, {e} edges, {} elements",
            grammar.name(),
            request.seed,
            d.steps,
            v + e
        );
        Ok(Box::new(GraphSample { scene: std::sync::OnceLock::new(), graph: d.graph, summary }))
    }

    fn describe(&self) -> String {
        let g = &self.grammar;
        let host = g.host();
        let mut out =
            format!("graph grammar {}: host {} vertices, {} edges\n", g.name(), host.vertex_count(), host.edge_count());
        match g.step_limit() {
            Some(n) => out.push_str(&format!("step limit: {n}\n")),
            None => out.push_str("step limit: none (runs until nothing matches)\n"),
        }
        out.push_str(&format!("time limit: {} s per derivation (`time_limit:`)\n", g.time_limit().as_secs_f64()));
        out.push_str(&format!("productions: {}\n", g.production_names().collect::<Vec<_>>().join(", ")));
        out
    }

    fn into_generator(self: Box<Self>) -> Result<Loaded> {
        Err(no_generator(
            &self.path,
            "graph grammars have no derivation-tree genome: each step rewrites a match found in the host graph \
             as it grows. They are evolved with codons that choose the matches and options: write a codon scene \
             (see examples/scenes/ge_graph_tree_sketch.toml) for `genform evolve`, and rebuild a result with \
             `genform derive SCENE.toml --genome best-codons.json`",
        ))
    }
}

/// A derived graph: drawn as a Scene, or written as YAML.
struct GraphSample {
    graph: Graph,
    /// The drawing, made when first asked for (a YAML output needs none).
    scene: std::sync::OnceLock<Scene>,
    summary: String,
}

impl Sample for GraphSample {
    fn scene(&self) -> &Scene {
        self.scene.get_or_init(|| self.graph.to_scene())
    }

    fn summary(&self) -> String {
        self.summary.clone()
    }

    fn write(&self, out: &Path, export: &ExportOptions) -> Result<Vec<PathBuf>> {
        if ends_with_any(out, YAML) {
            write_atomic_with(out, |mut w| self.graph.write_yaml(&mut w))?;
            Ok(vec![out.to_path_buf()])
        } else {
            write_model_with(self.scene(), out, export)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use genform_core::scene::Shape2d;

    #[test]
    fn drawings_become_polygons_the_scorers_see() {
        let mut scene = Scene::new();
        let shape = |kind, attributes: Vec<(String, String)>| Shape2d { kind, attributes: attributes.into(), tag: 0 };
        scene.shapes2d.push(shape(Shape2dKind::Rect { min: Vec2::ZERO, size: Vec2::new(2.0, 1.0) }, vec![]));
        scene.shapes2d.push(shape(Shape2dKind::Circle { center: Vec2::ONE, radius: 0.5 }, vec![]));
        let wide = vec![("stroke-width".to_string(), "0.4".to_string())];
        scene.shapes2d.push(shape(Shape2dKind::Line { from: Vec2::ZERO, to: Vec2::new(0.0, 3.0) }, wide));
        scene.shapes2d.push(shape(Shape2dKind::Path { d: "M 0 0".into() }, vec![]));
        drawing_as_polygons(&mut scene);
        assert_eq!(scene.polygons.len(), 3);
        assert_eq!(scene.polygons[0].points[2], Vec3::new(2.0, 1.0, 0.0));
        assert_eq!(scene.polygons[1].points.len(), CIRCLE_SEGMENTS);
        let line = &scene.polygons[2].points;
        assert!((line[0].x - -0.2).abs() < 1e-6 && (line[3].x - 0.2).abs() < 1e-6, "{line:?}");
    }
}
