//! Writers for genform Scenes.
//!
//! Every writer turns a [`Scene`] into the bytes of one file; this crate does
//! no file I/O. The formats:
//!
//! - [`Format::Obj`]: Wavefront OBJ text ([`write_obj`]); with a material
//!   library (`.mtl`) of the tag colours through [`export_obj_with_mtl`]
//!   (and, for textured tags, `map_Kd` naming the images
//!   [`obj_texture_files`] lists for the caller to write beside it).
//! - [`Format::Glb`]: binary glTF 2.0 ([`write_glb`]).
//! - [`Format::Ply`]: binary little-endian PLY, a triangle soup plus the
//!   surfaces' polygons and typed edges ([`write_ply`]).
//! - [`Format::Stl`]: binary STL ([`write_stl`]).
//! - [`Format::Svg`]: an orthographic line drawing onto the xy plane
//!   ([`write_svg`]).
//! - [`Format::Png`]: a preview image ([`render_png`]): flat drawings through
//!   the SVG writer and resvg, everything else by a software rasterizer.
//! - [`Format::Schem`], [`Format::Litematic`], [`Format::Vox`]: the scene's
//!   block grids ([`Scene::blocks`]) as a Sponge schematic, a Litematica
//!   schematic or a MagicaVoxel model ([`minecraft`]).
//!
//! GLB and OBJ split the model as [`ExportOptions::granularity`] says
//! ([`Granularity`]): one merged mesh with a part per material (the
//! default above [`AUTO_MERGE_ABOVE`] instances), one mesh per tag, or
//! one node per instance (GLB nodes sharing one mesh per primitive and
//! tag; OBJ objects each with their own vertices, the default for small
//! models).
//!
//! Polygon surfaces ([`Scene::surfaces`]) keep their polygons and typed
//! edges where the format can hold them: OBJ (`f` polygons, `l` edges
//! grouped by type), PLY (polygon faces and an `edge` element with the
//! type), GLB (triangles plus a `LINES` primitive per edge type, materials
//! `edge<N>`); STL gets their triangles. The PNG and SVG previews draw the
//! faces, the edges in the colours of [`edge_color`], and the guides
//! ([`Scene::guides`]) faintly; no model format writes guides.
//!
//! Flat drawings (a 2D turtle's strokes, a graph grammar's shapes) are
//! written by OBJ, GLB, PLY and STL as flat polygons in the z = 0 plane
//! ([`drawing_geometry`]: ribbons as wide as the strokes, fills in their
//! SVG colours); 3D strokes stay lines (OBJ `l`, GLB `LINES`).
//!
//! Block grids are drawn by OBJ, GLB, PLY, STL and PNG as greedy meshes
//! (one mesh per block state); region files are read and written by
//! [`minecraft::read_terrain`] and [`minecraft::write_region`].
//!
//! Textured tags ([`Scene::texture_of`]) get texture coordinates projected
//! from world positions onto each face's plane (`uv`): GLB embeds the
//! images as base-colour textures, OBJ writes `vt` and `map_Kd`; the other
//! formats show the tag's colour. Scenes without textures are written
//! exactly as before textures existed.
//!
//! All output is deterministic: the same scene gives the same bytes.
//! [`export`] checks the scene first (missing mesh assets, non-finite
//! coordinates, nothing to write) and reports an [`ExportError`]; the
//! `write_*` functions trust their input.

mod drawing;
mod fixed;
mod flat;
mod glb;
mod granularity;
pub mod import;
pub mod minecraft;
mod obj;
mod palette;
pub mod plot;
mod ply;
mod render;
mod shapes;
mod stl;
mod surfaces;
mod svg;
mod uv;

use genform_core::scene::{Primitive, Scene, Tessellation};
use std::fmt;
use std::path::Path;
use std::str::FromStr;

pub use drawing::{HAIRLINE_SHARE, drawing_geometry};
pub use glb::{write_glb, write_glb_with};
pub use granularity::{AUTO_MERGE_ABOVE, Granularity};
pub use import::{ImportError, MAX_IMPORT_TRIANGLES, MeshFileError, MeshFormat, read_mesh, read_mesh_file};
pub use obj::{obj_texture_file, write_obj, write_obj_materials, write_obj_with};
pub use palette::{edge_color, tag_color};
pub use ply::write_ply;
pub use render::{
    Backdrop, Camera, MAX_IMAGE_SIDE, RenderOptions, fitted_camera, render_png, render_rgb, render_rgb_over,
};
pub use stl::write_stl;
pub use surfaces::{grown_to_y_up, preview_y_up, surfaces_y_up};
pub use svg::{SvgOptions, write_svg};

/// An output file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Format {
    /// Wavefront OBJ text (`.obj`).
    Obj,
    /// Binary glTF 2.0 (`.glb`).
    Glb,
    /// Binary little-endian PLY (`.ply`).
    Ply,
    /// Binary STL (`.stl`).
    Stl,
    /// A rendered preview image (`.png`).
    Png,
    /// An orthographic line drawing (`.svg`).
    Svg,
    /// A Sponge schematic of the block grids (`.schem`).
    Schem,
    /// A Litematica schematic of the block grids (`.litematic`).
    Litematic,
    /// A MagicaVoxel model of the block grids (`.vox`).
    Vox,
}

impl Format {
    /// Every format, in the order of [`Format::extensions`].
    pub const ALL: [Format; 9] = [
        Format::Obj,
        Format::Glb,
        Format::Ply,
        Format::Stl,
        Format::Png,
        Format::Svg,
        Format::Schem,
        Format::Litematic,
        Format::Vox,
    ];

    /// The format a file name asks for, from its extension (case-insensitive);
    /// `None` when the extension is missing or unknown.
    pub fn from_path(path: &Path) -> Option<Format> {
        path.extension()?.to_str()?.parse().ok()
    }

    /// The known extensions, lowercase and without the dot.
    pub fn extensions() -> &'static [&'static str] {
        &["obj", "glb", "ply", "stl", "png", "svg", "schem", "litematic", "vox"]
    }

    /// This format's extension, lowercase and without the dot.
    pub fn extension(self) -> &'static str {
        match self {
            Format::Obj => "obj",
            Format::Glb => "glb",
            Format::Ply => "ply",
            Format::Stl => "stl",
            Format::Png => "png",
            Format::Svg => "svg",
            Format::Schem => "schem",
            Format::Litematic => "litematic",
            Format::Vox => "vox",
        }
    }

    /// Whether this format holds geometry (all but [`Format::Png`]); these
    /// refuse an empty scene.
    pub fn is_geometry(self) -> bool {
        self != Format::Png
    }

    /// Whether this format holds only block grids ([`Format::Schem`],
    /// [`Format::Litematic`], [`Format::Vox`]).
    pub fn is_blocks_only(self) -> bool {
        matches!(self, Format::Schem | Format::Litematic | Format::Vox)
    }
}

impl fmt::Display for Format {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Format::Obj => "OBJ",
            Format::Glb => "GLB",
            Format::Ply => "PLY",
            Format::Stl => "STL",
            Format::Png => "PNG",
            Format::Svg => "SVG",
            Format::Schem => "Sponge schematic",
            Format::Litematic => "Litematica schematic",
            Format::Vox => "MagicaVoxel",
        })
    }
}

impl FromStr for Format {
    type Err = ExportError;

    /// Parses an extension (`"glb"`, `".GLB"`, …).
    fn from_str(s: &str) -> Result<Format, ExportError> {
        let e = s.strip_prefix('.').unwrap_or(s);
        Format::ALL
            .into_iter()
            .find(|f| f.extension().eq_ignore_ascii_case(e))
            .ok_or_else(|| ExportError::UnknownFormat(s.to_string()))
    }
}

/// Settings for [`export`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ExportOptions {
    /// How finely curved primitives are tessellated (all formats).
    pub tessellation: Tessellation,
    /// Image settings for [`Format::Png`].
    pub render: RenderOptions,
    /// Drawing settings for [`Format::Svg`].
    pub svg: SvgOptions,
    /// Settings for the block formats.
    pub blocks: BlockOptions,
    /// How [`Format::Glb`] and [`Format::Obj`] split the model into nodes
    /// and objects ([`Granularity::Auto`] by default).
    pub granularity: Granularity,
}

/// Settings for [`Format::Schem`] and [`Format::Litematic`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BlockOptions {
    /// Sponge schematic version ([`minecraft::SchemVersion::V2`] by default).
    pub schem_version: minecraft::SchemVersion,
    /// Minecraft DataVersion written into schematics
    /// ([`minecraft::DATA_VERSION_1_21_1`] by default).
    pub data_version: i32,
}

impl Default for BlockOptions {
    fn default() -> Self {
        BlockOptions { schem_version: minecraft::SchemVersion::V2, data_version: minecraft::DATA_VERSION_1_21_1 }
    }
}

/// Why a scene could not be exported.
#[derive(thiserror::Error, Debug, Clone, PartialEq)]
pub enum ExportError {
    /// The extension or format name is not one of [`Format::extensions`].
    #[error("unknown output format `{0}`; known: {ext}", ext = Format::extensions().join(", "))]
    UnknownFormat(String),
    /// A geometry format was asked for and the scene has nothing it can hold.
    #[error("the scene is empty: there is no geometry to write as {0}")]
    EmptyScene(Format),
    /// An instance refers to a mesh asset the scene does not have, or an
    /// asset has a triangle with a vertex index out of range.
    #[error("instance {instance} refers to mesh asset {mesh}, which is missing or malformed")]
    BadMesh {
        /// Index into [`Scene::instances`].
        instance: usize,
        /// The mesh id it refers to.
        mesh: u32,
    },
    /// A surface has a face or edge naming a vertex it does not have, or a
    /// face of fewer than three corners.
    #[error("surface {surface} is malformed: {reason}")]
    BadSurface {
        /// Index into [`Scene::surfaces`].
        surface: usize,
        /// What is wrong.
        reason: String,
    },
    /// Some coordinate is NaN or infinite (a degenerate transform upstream).
    #[error("the scene has non-finite coordinates (NaN or infinity) in {0}")]
    NonFinite(String),
    /// A block format could not hold the blocks.
    #[error(transparent)]
    Blocks(#[from] minecraft::MinecraftError),
    /// Writing to the sink of [`export_to`] failed (the I/O error's text).
    #[error("{0}")]
    Io(String),
    /// The image size is zero or larger than [`MAX_IMAGE_SIDE`].
    #[error("cannot render a {width}×{height} image (each side must be 1..={max})", max = MAX_IMAGE_SIDE)]
    ImageSize {
        /// The requested width.
        width: u32,
        /// The requested height.
        height: u32,
    },
}

/// Writes `scene` as `format` and returns the file's bytes.
///
/// Checks the scene first: every [`Primitive::Mesh`] must name a valid asset
/// and every surface face and edge an existing vertex (all formats),
/// geometry formats need at least one triangle or drawn
/// block (OBJ, GLB and SVG also accept polylines alone, and OBJ, GLB, PLY
/// and SVG surface edges alone; SVG does not draw
/// blocks) and finite coordinates, and PNG needs a size within
/// [`MAX_IMAGE_SIDE`]. An empty scene renders as a blank image.
///
/// The block formats write only [`Scene::blocks`] (several grids are merged
/// into one grid over their bounding box, later grids winning where they
/// overlap) and need at least one grid with a cell.
pub fn export(scene: &Scene, format: Format, opts: &ExportOptions) -> Result<Vec<u8>, ExportError> {
    if format.is_blocks_only() {
        return export_blocks(scene, format, &opts.blocks);
    }
    // The mesh formats get a flat drawing as polygons (ribbons for its
    // strokes); SVG and PNG draw it as it is.
    let drawn = match format {
        Format::Obj | Format::Glb | Format::Ply | Format::Stl => drawing_geometry(scene),
        _ => std::borrow::Cow::Borrowed(scene),
    };
    let scene = &*drawn;
    check_meshes(scene)?;
    check_surfaces(scene)?;
    let tess = opts.tessellation;
    if format.is_geometry() {
        check_geometry(scene, format, tess)?;
    }
    Ok(match format {
        // One up axis, +y: surfaces grow with +z up and are turned here; the
        // GLB turns their nodes instead (its vertices stay as grown).
        Format::Obj => write_obj_with(&surfaces_y_up(scene), tess, opts.granularity).into_bytes(),
        Format::Glb => write_glb_with(scene, tess, opts.granularity),
        Format::Ply => write_ply(&surfaces_y_up(scene), tess),
        Format::Stl => write_stl(&surfaces_y_up(scene), tess),
        Format::Svg => svg::Drawing::new(scene, tess).write(scene, &opts.svg).into_bytes(),
        Format::Png => {
            let (w, h) = (opts.render.width, opts.render.height);
            if !(1..=MAX_IMAGE_SIDE).contains(&w) || !(1..=MAX_IMAGE_SIDE).contains(&h) {
                return Err(ExportError::ImageSize { width: w, height: h });
            }
            render::render_png_with(scene, &opts.render, tess)
        }
        Format::Schem | Format::Litematic | Format::Vox => return export_blocks(scene, format, &opts.blocks),
    })
}

/// An OBJ and its material library: `(OBJ bytes, MTL bytes)`, the OBJ
/// naming `mtl_file` (a file name beside the OBJ, as OBJ readers look for
/// it) in its `mtllib` line ([`write_obj_materials`]); checked and
/// prepared as [`export`] does for [`Format::Obj`], which writes the OBJ
/// alone.
pub fn export_obj_with_mtl(
    scene: &Scene,
    opts: &ExportOptions,
    mtl_file: &str,
) -> Result<(Vec<u8>, Vec<u8>), ExportError> {
    let drawn = drawing_geometry(scene);
    let scene = &*drawn;
    check_meshes(scene)?;
    check_surfaces(scene)?;
    check_geometry(scene, Format::Obj, opts.tessellation)?;
    let (obj, mtl) = write_obj_materials(&surfaces_y_up(scene), opts.tessellation, opts.granularity, mtl_file);
    Ok((obj.into_bytes(), mtl.into_bytes()))
}

/// The image files the material library `mtl_file` of
/// [`export_obj_with_mtl`] names (`map_Kd`), to be written beside it:
/// one per texture a tag of `scene` shows, as (file name
/// ([`obj_texture_file`]), PNG bytes), in texture order. Empty for a
/// scene without textures.
pub fn obj_texture_files<'s>(scene: &'s Scene, mtl_file: &str) -> Vec<(String, &'s [u8])> {
    let used = |k: usize| scene.tag_textures.iter().any(|&(_, x)| x as usize == k);
    let textures = scene.textures.iter().enumerate().filter(|&(k, _)| used(k));
    textures.map(|(_, t)| (obj_texture_file(mtl_file, t), t.png.as_slice())).collect()
}

/// [`export`] written to `sink`: the same bytes, but an SVG drawing goes
/// out piece by piece instead of as one text (a graph grammar's drawing
/// of a million shapes would otherwise be held whole). Nothing is written
/// when the scene is refused.
///
/// # Errors
///
/// [`export`]'s, and the sink's as [`ExportError::Io`].
pub fn export_to(
    scene: &Scene,
    format: Format,
    opts: &ExportOptions,
    sink: &mut dyn std::io::Write,
) -> Result<(), ExportError> {
    if format != Format::Svg {
        let bytes = export(scene, format, opts)?;
        return sink.write_all(&bytes).map_err(|e| ExportError::Io(e.to_string()));
    }
    check_meshes(scene)?;
    check_surfaces(scene)?;
    check_geometry(scene, format, opts.tessellation)?;
    svg::Drawing::new(scene, opts.tessellation)
        .write_to(scene, &opts.svg, sink)
        .map_err(|e| ExportError::Io(e.to_string()))
}

/// [`export`] for the block formats.
fn export_blocks(scene: &Scene, format: Format, opts: &BlockOptions) -> Result<Vec<u8>, ExportError> {
    let grid = minecraft::merge_grids(&scene.blocks).filter(|g| g.volume() > 0);
    let grid = grid.ok_or(ExportError::EmptyScene(format))?;
    Ok(match format {
        Format::Schem => minecraft::write_schem(&grid, opts.schem_version, opts.data_version)?,
        Format::Litematic => minecraft::write_litematic(&grid, opts.data_version, "genform")?,
        _ => minecraft::write_vox(&grid).map_err(|e| match e {
            minecraft::MinecraftError::Empty => ExportError::EmptyScene(format),
            e => e.into(),
        })?,
    })
}

/// Every mesh reference resolves and every asset triangle is in range.
fn check_meshes(scene: &Scene) -> Result<(), ExportError> {
    for (i, inst) in scene.instances.iter().enumerate() {
        if let Primitive::Mesh(id) = inst.primitive {
            let ok = scene.meshes.get(id as usize).is_some_and(|m| {
                let n = m.positions.len();
                m.triangles.iter().all(|t| t.iter().all(|&v| (v as usize) < n))
            });
            if !ok {
                return Err(ExportError::BadMesh { instance: i, mesh: id });
            }
        }
    }
    Ok(())
}

/// Every surface face has at least three corners, and every face corner
/// and edge end names one of the surface's vertices.
fn check_surfaces(scene: &Scene) -> Result<(), ExportError> {
    for (k, s) in scene.surfaces.iter().enumerate() {
        let bad = |reason: String| Err(ExportError::BadSurface { surface: k, reason });
        let n = s.positions.len();
        let offsets_ok = s.face_offsets.first().is_none_or(|&o| o == 0)
            && s.face_offsets.windows(2).all(|w| w[0] <= w[1])
            && s.face_offsets.last().is_none_or(|&o| o as usize == s.face_vertices.len());
        if !offsets_ok {
            return bad("its face offsets do not run from 0 to the end of the face loops".into());
        }
        for (f, face) in s.faces().enumerate() {
            if face.len() < 3 {
                return bad(format!("face {f} has {} corners (at least 3 needed)", face.len()));
            }
            if let Some(&v) = face.iter().find(|&&v| v as usize >= n) {
                return bad(format!("face {f} names vertex {v}, but there are {n}"));
            }
        }
        if let Some((i, e)) = s.edges.iter().enumerate().find(|(_, e)| e.a.max(e.b) as usize >= n) {
            return bad(format!("edge {i} ({} to {}) names a vertex past the {n} there are", e.a, e.b));
        }
    }
    Ok(())
}

/// Finite coordinates and something to write.
fn check_geometry(scene: &Scene, format: Format, tess: Tessellation) -> Result<(), ExportError> {
    let (mut triangles, mut finite) = (0usize, true);
    scene.for_each_triangle(tess, |t, _| {
        triangles += 1;
        finite &= t.iter().all(|p| p.is_finite());
    });
    if !finite {
        return Err(ExportError::NonFinite("a triangle".into()));
    }
    if !scene.polygons.iter().all(|p| p.points.iter().all(|p| p.is_finite())) {
        return Err(ExportError::NonFinite("a polygon".into()));
    }
    if format != Format::Svg && minecraft::has_drawn_blocks(scene) {
        triangles += 1;
    }
    let lines = matches!(format, Format::Obj | Format::Glb | Format::Svg);
    if !scene.surfaces.iter().all(|s| s.positions.iter().all(|p| p.is_finite())) {
        return Err(ExportError::NonFinite("a surface".into()));
    }
    let mut drawable_lines = matches!(format, Format::Obj | Format::Glb | Format::Ply | Format::Svg)
        && scene.surfaces.iter().any(|s| s.edges.iter().any(|e| e.a != e.b));
    if lines {
        for l in &scene.polylines {
            if !l.points.iter().all(|p| p.is_finite()) {
                return Err(ExportError::NonFinite("a polyline".into()));
            }
            drawable_lines |= l.points.len() >= 2;
        }
    }
    // 2D drawing elements exist only for SVG (and PNG, which is not a
    // geometry format).
    let drawing = format == Format::Svg && !scene.shapes2d.is_empty();
    if triangles == 0 && !drawable_lines && !drawing {
        return Err(ExportError::EmptyScene(format));
    }
    Ok(())
}

#[cfg(test)]
pub(crate) mod test_scenes {
    use genform_core::scene::{Instance, Polygon, Polyline, Primitive, Scene};
    use glam::{Affine3A, Quat, Vec3};

    /// A `w` × `h` RGB PNG file of a reddish gradient.
    pub fn tiny_png(w: u32, h: u32) -> Vec<u8> {
        let mut out = Vec::new();
        let mut enc = png::Encoder::new(&mut out, w, h);
        enc.set_color(png::ColorType::Rgb);
        let mut writer = enc.write_header().unwrap();
        let data: Vec<u8> = (0..w * h).flat_map(|i| [150, (i * 7 % 64) as u8, 40]).collect();
        writer.write_image_data(&data).unwrap();
        writer.finish().unwrap();
        out
    }

    /// A wall in the plane z = 0 facing +z, 4 m wide and 3 m high, split
    /// at x = 1.5 into two flat boxes (tag `wall`, textured with a 2 × 1 m
    /// `brick`), and a box tagged `plain` beside it.
    pub fn textured_wall() -> Scene {
        use genform_core::scene::Texture;
        let mut s = Scene::new();
        let wall = s.tag("wall");
        let plain = s.tag("plain");
        let brick = std::sync::Arc::new(Texture::from_png("brick", tiny_png(4, 2), [2.0, 1.0]).unwrap());
        s.set_texture(wall, &brick);
        let piece = |x0: f32, x1: f32| Instance {
            transform: Affine3A::from_scale_rotation_translation(
                Vec3::new(x1 - x0, 3.0, 0.1),
                Quat::IDENTITY,
                Vec3::new((x0 + x1) / 2.0, 1.5, -0.05),
            ),
            primitive: Primitive::Box,
            tag: wall,
        };
        s.instances.push(piece(0.0, 1.5));
        s.instances.push(piece(1.5, 4.0));
        s.instances.push(Instance {
            transform: Affine3A::from_translation(Vec3::new(8.0, 0.5, 0.0)),
            primitive: Primitive::Box,
            tag: plain,
        });
        s
    }

    /// `n` unit boxes in a row along x, tagged `hull`.
    pub fn boxes(n: usize) -> Scene {
        let mut s = Scene::new();
        let tag = s.tag("hull");
        for i in 0..n {
            s.instances.push(Instance {
                transform: Affine3A::from_translation(Vec3::new(2.0 * i as f32, 0.0, 0.0)),
                primitive: Primitive::Box,
                tag,
            });
        }
        s
    }

    /// A unit box tagged `hull` at x = −3, and two surfaces tagged `shell`:
    /// a 2×2 grid of unit quads on z = 0 (its middle vertex raised to 0.5;
    /// 9 vertices, 12 edges, 4 faces) with boundary edges of type 1 and
    /// inner ones of type 2, and that grid smoothed once by Catmull–Clark
    /// and lifted by 1 (25 vertices, 40 edges (16 untyped), 16 faces). Guides:
    /// a boundary square under them at z = −1 (tag `boundary`), an
    /// attractor above and a repeller below.
    pub fn surfaces() -> Scene {
        use genform_core::surface::{Guide, GuideKind, Surface, SurfaceEdge};
        let mut s = boxes(1);
        s.instances[0].transform = Affine3A::from_translation(Vec3::new(-3.0, 0.0, 0.0));
        let tag = s.tag("shell");
        let mut grid = Surface::new(tag);
        let id = |i: u32, j: u32| 3 * j + i;
        for j in 0..3 {
            for i in 0..3 {
                let z = if (i, j) == (1, 1) { 0.5 } else { 0.0 };
                grid.positions.push(Vec3::new(i as f32, j as f32, z));
            }
        }
        for j in 0..2 {
            for i in 0..2 {
                grid.push_face(&[id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        for j in 0..3 {
            for i in 0..3 {
                if i < 2 {
                    let kind = if j == 1 { 2 } else { 1 };
                    grid.edges.push(SurfaceEdge { a: id(i, j), b: id(i + 1, j), kind });
                }
                if j < 2 {
                    let kind = if i == 1 { 2 } else { 1 };
                    grid.edges.push(SurfaceEdge { a: id(i, j), b: id(i, j + 1), kind });
                }
            }
        }
        let mut smooth = grid.catmull_clark(1);
        smooth.positions.iter_mut().for_each(|p| p.z += 1.0);
        s.surfaces.push(grid);
        s.surfaces.push(smooth);
        let plane = genform_core::Mesh {
            name: "ground".into(),
            positions: vec![
                Vec3::new(-1.0, -1.0, -1.0),
                Vec3::new(3.0, -1.0, -1.0),
                Vec3::new(3.0, 3.0, -1.0),
                Vec3::new(-1.0, 3.0, -1.0),
            ],
            triangles: vec![[0, 1, 2], [0, 2, 3]],
        };
        let (b, a, r) = (s.tag("boundary"), s.tag("attractor"), s.tag("repeller"));
        s.guides.push(Guide { kind: GuideKind::Mesh(std::sync::Arc::new(plane)), tag: b });
        s.guides.push(Guide { kind: GuideKind::Point { at: Vec3::new(1.0, 1.0, 2.5), radius: 0.15 }, tag: a });
        s.guides.push(Guide { kind: GuideKind::Point { at: Vec3::new(0.5, 1.5, -0.5), radius: 0.15 }, tag: r });
        s
    }

    /// A bit of everything: rotated, scaled, reflected and degenerate
    /// instances of every primitive, a mesh asset, a polygon and a polyline.
    pub fn mixed() -> Scene {
        let mut s = Scene::new();
        let (a, b, c) = (s.tag("wall"), s.tag("roof tile"), s.tag("trunk"));
        let mesh = std::sync::Arc::new(
            genform_core::Mesh::from_obj(
                "tet",
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n",
            )
            .unwrap(),
        );
        let m = s.mesh(&mesh);
        let prims = [
            Primitive::Box,
            Primitive::Sphere,
            Primitive::Frustum { top: 1.0 },
            Primitive::Frustum { top: 0.0 },
            Primitive::TaperedBox { top: 0.0 },
            Primitive::TaperedBox { top: 0.5 },
            Primitive::Mesh(m),
        ];
        for (i, p) in prims.into_iter().enumerate() {
            let x = 3.0 * i as f32;
            let rot = Quat::from_euler(glam::EulerRot::YXZ, 0.3 * i as f32, 0.2, -0.1 * i as f32);
            s.instances.push(Instance {
                transform: Affine3A::from_scale_rotation_translation(
                    Vec3::new(1.0 + 0.1 * i as f32, 2.0, 0.5),
                    rot,
                    Vec3::new(x, 0.0, 0.0),
                ),
                primitive: p,
                tag: [a, b, c][i % 3],
            });
            // The same primitive reflected.
            s.instances.push(Instance {
                transform: Affine3A::from_scale_rotation_translation(
                    Vec3::new(-1.0, 1.0, 1.5),
                    rot,
                    Vec3::new(x, 4.0, 0.0),
                ),
                primitive: p,
                tag: a,
            });
        }
        // Singular (a flattened box) and sheared instances.
        s.instances.push(Instance {
            transform: Affine3A::from_scale(Vec3::new(2.0, 0.0, 2.0)) * Affine3A::from_translation(Vec3::Y * -8.0),
            primitive: Primitive::Box,
            tag: b,
        });
        s.instances.push(Instance {
            transform: Affine3A::from_cols_array(&[1.0, 0.0, 0.0, 0.7, 1.0, 0.0, 0.0, 0.0, 1.0, -4.0, 0.0, 0.0]),
            primitive: Primitive::Box,
            tag: c,
        });
        s.polygons.push(Polygon {
            points: vec![
                Vec3::new(0.0, -2.0, 0.0),
                Vec3::new(4.0, -2.0, 0.0),
                Vec3::new(4.0, -2.0, 3.0),
                Vec3::new(0.0, -2.0, 3.0),
            ],
            tag: b,
        });
        s.polylines.push(Polyline {
            points: &[Vec3::new(0.0, 6.0, 0.0), Vec3::new(2.0, 7.0, 0.0), Vec3::new(4.0, 6.0, 1.0)],
            width: 0.1,
            tag: c,
        });
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use genform_core::scene::Instance;

    #[test]
    fn formats_from_paths() {
        assert_eq!(Format::from_path(Path::new("out/ship.GLB")), Some(Format::Glb));
        assert_eq!(Format::from_path(Path::new("a.b.obj")), Some(Format::Obj));
        assert_eq!(Format::from_path(Path::new("x.png")), Some(Format::Png));
        assert_eq!(Format::from_path(Path::new("x.gltf")), None);
        assert_eq!(Format::from_path(Path::new("noext")), None);
        for (f, e) in Format::ALL.iter().zip(Format::extensions()) {
            assert_eq!(f.extension(), *e);
            assert_eq!(e.parse::<Format>().unwrap(), *f);
        }
        let err = "fbx".parse::<Format>().unwrap_err();
        assert!(err.to_string().contains("obj, glb, ply, stl, png"), "{err}");
    }

    #[test]
    fn export_checks_the_scene() {
        let opts = ExportOptions::default();
        let empty = Scene::new();
        for f in [Format::Obj, Format::Glb, Format::Ply, Format::Stl] {
            assert_eq!(export(&empty, f, &opts), Err(ExportError::EmptyScene(f)));
        }
        assert!(!export(&empty, Format::Png, &opts).unwrap().is_empty());

        let mut s = test_scenes::boxes(1);
        s.instances.push(Instance { primitive: Primitive::Mesh(3), ..s.instances[0] });
        assert_eq!(export(&s, Format::Stl, &opts), Err(ExportError::BadMesh { instance: 1, mesh: 3 }));

        let mut s = test_scenes::boxes(2);
        s.instances[1].transform.translation.x = f32::NAN;
        assert!(matches!(export(&s, Format::Obj, &opts), Err(ExportError::NonFinite(_))));

        let s = test_scenes::boxes(1);
        let mut o = opts;
        o.render.width = 0;
        assert_eq!(export(&s, Format::Png, &o), Err(ExportError::ImageSize { width: 0, height: 600 }));
    }

    #[test]
    fn block_scenes_export_to_block_and_mesh_formats() {
        use genform_core::{BlockGrid, BlockState};
        use glam::{IVec3, UVec3};
        let opts = ExportOptions::default();
        let mut s = Scene::new();
        for f in [Format::Schem, Format::Litematic, Format::Vox] {
            assert_eq!(export(&s, f, &opts), Err(ExportError::EmptyScene(f)));
        }
        // Only air: the block formats write it, nothing is drawn.
        let mut air = BlockGrid::new(IVec3::ZERO, UVec3::new(2, 2, 2));
        air.set(IVec3::ZERO, &BlockState::air());
        s.blocks.push(air);
        assert!(export(&s, Format::Schem, &opts).is_ok());
        for f in [Format::Vox, Format::Obj, Format::Stl] {
            assert_eq!(export(&s, f, &opts), Err(ExportError::EmptyScene(f)));
        }
        // Two grids: merged for the block formats, meshed for the others.
        let mut g = BlockGrid::new(IVec3::new(4, 0, 0), UVec3::new(1, 1, 1));
        g.set(IVec3::new(4, 0, 0), &BlockState::new("stone"));
        s.blocks.push(g);
        let schem = export(&s, Format::Schem, &opts).unwrap();
        let back = minecraft::read_schem(&schem).unwrap();
        assert_eq!((back.origin, back.size), (IVec3::ZERO, UVec3::new(5, 2, 2)));
        assert_eq!(back.get(IVec3::new(4, 0, 0)).unwrap().id(), "stone");
        let v3 = ExportOptions {
            blocks: BlockOptions { schem_version: minecraft::SchemVersion::V3, data_version: 3337 },
            ..opts
        };
        assert_ne!(export(&s, Format::Schem, &v3).unwrap(), schem);
        let stl = export(&s, Format::Stl, &opts).unwrap();
        assert_eq!(u32::from_le_bytes(stl[80..84].try_into().unwrap()), 12);
        let ply = export(&s, Format::Ply, &opts).unwrap();
        assert!(String::from_utf8_lossy(&ply[..200]).contains("element face 12"));
        assert_eq!(export(&s, Format::Svg, &opts), Err(ExportError::EmptyScene(Format::Svg)));
        let big = BlockGrid::new(IVec3::ZERO, UVec3::new(70_000, 1, 1));
        s.blocks.push(big);
        let e = export(&s, Format::Schem, &opts).unwrap_err();
        assert!(e.to_string().contains("too large for schem"), "{e}");
    }

    #[test]
    fn every_format_exports_deterministically() {
        let s = test_scenes::mixed();
        let mut opts = ExportOptions::default();
        opts.render.width = 160;
        opts.render.height = 120;
        let mut s = s;
        let mut g = genform_core::BlockGrid::new(glam::IVec3::new(0, -8, 0), glam::UVec3::new(3, 2, 2));
        g.set(glam::IVec3::new(1, -8, 1), &genform_core::BlockState::new("stone"));
        g.set(glam::IVec3::new(2, -7, 0), &genform_core::BlockState::parse("oak_slab[type=top]").unwrap());
        s.blocks.push(g);
        for f in Format::ALL {
            let a = export(&s, f, &opts).unwrap();
            let b = export(&s.clone(), f, &opts).unwrap();
            assert!(!a.is_empty());
            assert!(a == b, "{f} output differs between runs");
        }
    }
}
