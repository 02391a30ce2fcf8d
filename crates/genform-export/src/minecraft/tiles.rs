//! Flat block structures as tile pictures: a box-split derivation in a box
//! one block thick is a 2D tile pattern (the PNG backend of Eger's first
//! box-split paper), drawn cell by cell instead of in perspective.

use super::colors::block_color;
use genform_core::{BlockGrid, BlockKind, Scene};

/// The one grid of a scene that holds only blocks, when that grid is one
/// cell thick along some axis.
pub(crate) fn flat_grid(scene: &Scene) -> Option<&BlockGrid> {
    let only_blocks = scene.instances.is_empty()
        && scene.polylines.is_empty()
        && scene.polygons.is_empty()
        && scene.shapes2d.is_empty()
        && scene.surfaces.is_empty();
    match scene.blocks.as_slice() {
        [g] if only_blocks && g.size.min_element() == 1 && g.size.max_element() > 1 => Some(g),
        _ => None,
    }
}

/// Draws a one-cell-thick grid into a `width` × `height` RGB image: square
/// tiles, as large as fit, centred on `background`; air and unset cells
/// show the background. The two long axes map to the picture as seen from
/// above (y thin: x right, z down) or from the front (x right or z right,
/// y up).
pub(crate) fn render_tiles(grid: &BlockGrid, width: u32, height: u32, background: [u8; 3]) -> Vec<u8> {
    let s = grid.size;
    // (columns, rows, cell of (column, row))
    let (cols, rows): (u32, u32) = if s.y == 1 {
        (s.x, s.z)
    } else if s.z == 1 {
        (s.x, s.y)
    } else {
        (s.z, s.y)
    };
    let cell = |c: u32, r: u32| -> usize {
        let (x, y, z) = if s.y == 1 {
            (c, 0, r)
        } else if s.z == 1 {
            (c, rows - 1 - r, 0)
        } else {
            (0, rows - 1 - r, c)
        };
        ((y as usize * s.z as usize) + z as usize) * s.x as usize + x as usize
    };
    let tile = (width / cols.max(1)).min(height / rows.max(1)).max(1);
    let (ox, oy) = (width.saturating_sub(tile * cols) / 2, height.saturating_sub(tile * rows) / 2);
    let mut rgb = background.repeat(width as usize * height as usize);
    let colors: Vec<Option<[u8; 3]>> =
        grid.palette.iter().map(|b| (b.kind() != BlockKind::Air).then(|| block_color(b))).collect();
    for r in 0..rows {
        for c in 0..cols {
            let v = grid.cells[cell(c, r)];
            let Some(Some(color)) = colors.get(v as usize) else { continue };
            for py in oy + r * tile..(oy + (r + 1) * tile).min(height) {
                for px in ox + c * tile..(ox + (c + 1) * tile).min(width) {
                    let i = (py as usize * width as usize + px as usize) * 3;
                    rgb[i..i + 3].copy_from_slice(color);
                }
            }
        }
    }
    rgb
}

#[cfg(test)]
mod tests {
    use super::*;
    use genform_core::BlockState;
    use glam::{IVec3, UVec3};

    #[test]
    fn a_flat_grid_becomes_tiles_seen_from_above() {
        let mut g = BlockGrid::new(IVec3::ZERO, UVec3::new(4, 1, 2));
        g.set(IVec3::new(0, 0, 0), &BlockState::new("stone"));
        g.set(IVec3::new(3, 0, 1), &BlockState::new("gold_block"));
        g.set(IVec3::new(1, 0, 0), &BlockState::air());
        let mut scene = Scene::new();
        scene.blocks.push(g.clone());
        assert!(flat_grid(&scene).is_some());
        let bg = [255, 255, 255];
        let rgb = render_tiles(&g, 40, 20, bg);
        let px = |x: usize, y: usize| [rgb[(y * 40 + x) * 3], rgb[(y * 40 + x) * 3 + 1], rgb[(y * 40 + x) * 3 + 2]];
        // 10-pixel tiles: stone top-left, gold bottom-right, air and unset
        // cells the background.
        assert_eq!(px(5, 5), block_color(&BlockState::new("stone")));
        assert_eq!(px(35, 15), block_color(&BlockState::new("gold_block")));
        assert_eq!(px(15, 5), bg);
        assert_eq!(px(25, 15), bg);
        scene.blocks[0] = BlockGrid::new(IVec3::ZERO, UVec3::new(4, 2, 2));
        assert!(flat_grid(&scene).is_none(), "a solid structure gets the 3D preview");
    }
}
