//! End-to-end tests of the pictures `genform evolve` draws for the user:
//! `fitness.svg` scaled to what matters and with its legend off the data,
//! `gallery.png` with every model filling its cell. The real binary on the
//! shipped spaceship scene, whose worst individuals score far below its
//! best and mean.

mod common;
use common::{assert_legends_clear, ok, root};

/// Background of the previews (`RenderOptions::default`).
const BACKGROUND: [u8; 3] = [236, 238, 241];
/// Side of a gallery preview, and the caption strip under it (2 lines of the 5×7 font at 2×).
const PREVIEW: usize = 256;
const CAPTION: usize = 2 * 18;
const GUTTER: usize = 4;

#[test]
fn fitness_plot_follows_best_and_mean_and_gallery_models_fill_their_cells() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = root().join("examples/scenes/spaceship_volume.toml");
    ok(tmp.path(), &["evolve", scene.to_str().unwrap(), "--generations", "40", "--out", "run", "--quiet"]);
    let run = tmp.path().join("run");

    // The y-axis spans the mean and the best, not the worst.
    let csv = std::fs::read_to_string(run.join("stats.csv")).unwrap();
    let column = |name: &str| -> Vec<f64> {
        let i = csv.lines().next().unwrap().split(',').position(|c| c == name).unwrap();
        csv.lines().skip(1).map(|l| l.split(',').nth(i).unwrap().parse().unwrap()).collect()
    };
    let fold = |v: Vec<f64>, f: fn(f64, f64) -> f64| v.into_iter().reduce(f).unwrap();
    let (best, mean, worst) = (
        fold(column("max_fitness"), f64::max),
        fold(column("avg_fitness"), f64::min),
        fold(column("min_fitness"), f64::min),
    );
    let span = best - mean;
    assert!(worst < mean - 2.0 * span, "the test needs a worst far below: worst {worst}, mean {mean}, best {best}");
    let svg = std::fs::read_to_string(run.join("fitness.svg")).unwrap();
    let layout = assert_legends_clear("fitness.svg", &svg);
    assert_eq!(layout.plots.len(), 2);
    for (_, _, [lo, hi]) in &layout.plots {
        assert!(*lo <= mean && *lo >= mean - 0.1 * span, "y-axis from {lo}, the lowest mean is {mean}");
        assert!(*hi >= best && *hi <= best + 0.1 * span, "y-axis to {hi}, the best is {best}");
    }
    assert!(svg.contains(">min (clipped)<"), "the legend says the worst line leaves the axis");

    // Every gallery cell's model covers most of its preview in one direction.
    let bytes = std::fs::read(run.join("gallery.png")).unwrap();
    let mut reader = png::Decoder::new(std::io::Cursor::new(&bytes)).read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    let (w, h) = (info.width as usize, info.height as usize);
    let px = |x: usize, y: usize| -> [u8; 3] { buf[(y * w + x) * 3..][..3].try_into().unwrap() };
    let cell_w = (w - 5 * GUTTER) / 4;
    let cell_h = PREVIEW + CAPTION;
    assert_eq!((h - GUTTER) % (cell_h + GUTTER), 0, "{w}×{h}: not a grid of 4 columns of {PREVIEW}-pixel previews");
    let rows = (h - GUTTER) / (cell_h + GUTTER);
    let mut cells = 0;
    for r in 0..rows {
        for c in 0..4 {
            let x0 = GUTTER + c * (cell_w + GUTTER) + (cell_w - PREVIEW) / 2;
            let y0 = GUTTER + r * (cell_h + GUTTER);
            if px(x0, y0) != BACKGROUND {
                continue; // an empty cell past the last model
            }
            let drawn: Vec<(usize, usize)> = (y0..y0 + PREVIEW)
                .flat_map(|y| (x0..x0 + PREVIEW).map(move |x| (x, y)))
                .filter(|&(x, y)| px(x, y) != BACKGROUND)
                .collect();
            let extent = |f: fn(&(usize, usize)) -> usize| {
                drawn.iter().map(f).max().unwrap_or(0) - drawn.iter().map(f).min().unwrap_or(0) + 1
            };
            let fill = extent(|p| p.0).max(extent(|p| p.1)) as f64 / PREVIEW as f64;
            assert!(fill >= 0.6, "cell {r},{c}: the model spans {:.0} % of its cell", 100.0 * fill);
            cells += 1;
        }
    }
    assert!(cells >= 4, "{cells} models in the gallery");
}
