//! Renders the example grammars in `examples/graph/` to
//! `docs/img/graph-<name>.svg` and `.png` (seed 1, or the seed given as the
//! first argument).
//!
//! `cargo run -p genform-graph --example render_examples --release`

use genform_core::{Rng, SourceFile};
use genform_export::{RenderOptions, SvgOptions, render_png, write_svg};
use std::path::Path;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let seed: u64 = std::env::args().nth(1).map_or(Ok(1), |s| s.parse())?;
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let out = root.join("docs/img");
    std::fs::create_dir_all(&out)?;
    let mut files: Vec<_> = std::fs::read_dir(root.join("examples/graph"))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.to_string_lossy().ends_with(".gg.yaml"))
        .collect();
    files.sort();
    for path in files {
        let text = std::fs::read_to_string(&path)?;
        let file = SourceFile::new(path.display().to_string(), text);
        let (grammar, _) = genform_graph::compile(&file).map_err(|d| d.render(false))?;
        let d = grammar.derive(&mut Rng::from_seed(seed), None, genform_graph::DEFAULT_MAX_ELEMENTS)?;
        let scene = d.graph.to_scene();
        let name = grammar.name().replace('_', "-");
        let svg = write_svg(&scene, &SvgOptions { background: None, ..SvgOptions::default() });
        std::fs::write(out.join(format!("graph-{name}.svg")), &svg)?;
        let (w, h) = image_size(&svg, 800);
        let png = render_png(&scene, &RenderOptions { width: w, height: h, background: [255; 3], camera: None });
        std::fs::write(out.join(format!("graph-{name}.png")), png)?;
        println!("{name}: {} steps, {} elements ({:?})", d.steps, d.graph.element_count(), d.stats.stop);
    }
    Ok(())
}

/// `width` pixels wide, as tall as the SVG's view box asks.
fn image_size(svg: &str, width: u32) -> (u32, u32) {
    let view_box = svg.split("viewBox=\"").nth(1).and_then(|s| s.split('"').next()).unwrap_or("0 0 1 1");
    let n: Vec<f32> = view_box.split(' ').filter_map(|t| t.parse().ok()).collect();
    let aspect = if n.len() == 4 && n[2] > 0.0 && n[3] > 0.0 { n[2] / n[3] } else { 1.0 };
    (width, ((width as f32 / aspect).round() as u32).clamp(1, 4 * width))
}
