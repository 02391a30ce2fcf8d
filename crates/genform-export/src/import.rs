//! Reading triangle meshes (targets and assets): OBJ, STL and GLB.
//!
//! [`read_mesh`] turns the bytes of one file into a [`Mesh`] in the file's
//! world space. It reads geometry only (no materials, normals or textures)
//! and does no file I/O: the caller reads the bytes. [`read_mesh_file`] is
//! the one reader of mesh files every user goes through (scene targets,
//! growth-environment boundaries, grammar assets): the format from the
//! extension, the name from the file stem.
//!
//! - OBJ: `v` and `f` statements ([`Mesh::from_obj`]).
//! - STL: binary (recognised by its size matching its triangle count) or
//!   ASCII (`solid … facet … outer loop … vertex x y z …`). Equal vertices
//!   are welded so that neighbouring facets share corners.
//! - GLB (binary glTF 2.0): every triangle primitive (`mode` 4 or absent) of
//!   every mesh reached from the default scene's nodes, with the node
//!   hierarchy's transforms (`matrix` or translation–rotation–scale)
//!   applied and the winding turned for mirroring transforms. Positions
//!   must be `FLOAT` `VEC3` accessors (any `byteStride`); indices `u8`,
//!   `u16`, `u32` or none. Data must be in the file's own binary chunk:
//!   external or `data:` URIs, sparse accessors and compressed or quantized
//!   geometry (Draco, meshopt, `KHR_mesh_quantization`) are refused with an
//!   error saying so. Points and lines are skipped.

use genform_core::scene::Mesh;
use glam::{DMat4, DQuat, DVec3, Vec3};
use serde_json::Value;
use std::collections::HashMap;
use std::fmt;
use std::path::{Path, PathBuf};

/// The most triangles an imported mesh may have (after glTF instancing).
pub const MAX_IMPORT_TRIANGLES: usize = 1 << 26;

/// A mesh file format [`read_mesh`] understands.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MeshFormat {
    /// Wavefront OBJ (`.obj`).
    Obj,
    /// STL, binary or ASCII (`.stl`).
    Stl,
    /// Binary glTF 2.0 (`.glb`).
    Glb,
}

impl MeshFormat {
    /// Every format.
    pub const ALL: [MeshFormat; 3] = [MeshFormat::Obj, MeshFormat::Stl, MeshFormat::Glb];

    /// The format a file name asks for, by its extension (case-insensitive).
    pub fn from_path(path: &Path) -> Option<MeshFormat> {
        MeshFormat::from_extension(path.extension()?.to_str()?)
    }

    /// The format of an extension (`"stl"`, `".GLB"`, …).
    pub fn from_extension(ext: &str) -> Option<MeshFormat> {
        let e = ext.strip_prefix('.').unwrap_or(ext);
        MeshFormat::ALL.into_iter().find(|f| f.extension().eq_ignore_ascii_case(e))
    }

    /// The extension, lowercase without the dot.
    pub fn extension(self) -> &'static str {
        match self {
            MeshFormat::Obj => "obj",
            MeshFormat::Stl => "stl",
            MeshFormat::Glb => "glb",
        }
    }
}

impl fmt::Display for MeshFormat {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            MeshFormat::Obj => "OBJ",
            MeshFormat::Stl => "STL",
            MeshFormat::Glb => "GLB",
        })
    }
}

/// Why a mesh file could not be read.
#[derive(thiserror::Error, Debug, Clone, PartialEq)]
pub enum ImportError {
    /// The file is damaged or not of the format it claims; the message says
    /// where.
    #[error("{format} mesh `{name}`: {message}")]
    Malformed {
        /// The format read.
        format: MeshFormat,
        /// The mesh name given.
        name: String,
        /// What is wrong, and where.
        message: String,
    },
    /// The file uses a feature genform does not read; the message says which
    /// and what to do instead.
    #[error("{format} mesh `{name}` uses {what}, which genform cannot read; {hint}")]
    Unsupported {
        /// The format read.
        format: MeshFormat,
        /// The mesh name given.
        name: String,
        /// The feature.
        what: String,
        /// How to get a file genform can read.
        hint: String,
    },
    /// The file holds no triangles.
    #[error("{format} mesh `{name}` holds no triangles")]
    Empty {
        /// The format read.
        format: MeshFormat,
        /// The mesh name given.
        name: String,
    },
    /// The mesh would have more than [`MAX_IMPORT_TRIANGLES`] triangles.
    #[error("{format} mesh `{name}` has more than {max} triangles", max = MAX_IMPORT_TRIANGLES)]
    TooLarge {
        /// The format read.
        format: MeshFormat,
        /// The mesh name given.
        name: String,
    },
}

/// Reads the mesh in `bytes` (a file of `format`), naming it `name`.
pub fn read_mesh(name: &str, bytes: &[u8], format: MeshFormat) -> Result<Mesh, ImportError> {
    let mesh = match format {
        MeshFormat::Obj => Mesh::from_obj(name, &String::from_utf8_lossy(bytes))
            .map_err(|message| ImportError::Malformed { format, name: name.into(), message })?,
        MeshFormat::Stl => stl::read(name, bytes)?,
        MeshFormat::Glb => glb::read(name, bytes)?,
    };
    if mesh.triangles.is_empty() {
        return Err(ImportError::Empty { format, name: name.into() });
    }
    Ok(mesh)
}

/// Why a mesh file could not be read ([`read_mesh_file`]).
#[derive(thiserror::Error, Debug)]
pub enum MeshFileError {
    /// The extension is none of [`MeshFormat::ALL`]'s: rename the file or
    /// convert it to OBJ, STL or GLB.
    #[error("cannot tell the mesh format of {}; use .obj, .stl or .glb", path.display())]
    UnknownFormat {
        /// The file.
        path: PathBuf,
    },
    /// The file cannot be read (missing, a folder, no permission).
    #[error("cannot read {}: {error}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// What the system said.
        error: std::io::Error,
    },
    /// The file was read but holds no mesh genform can use.
    #[error("cannot read {}: {error}", path.display())]
    Import {
        /// The file.
        path: PathBuf,
        /// What is wrong with its contents.
        error: ImportError,
    },
}

/// Reads the mesh file at `path`: its format from the extension
/// ([`MeshFormat::from_path`]), its name from the file stem, its contents
/// by [`read_mesh`].
pub fn read_mesh_file(path: &Path) -> Result<Mesh, MeshFileError> {
    let format = MeshFormat::from_path(path).ok_or_else(|| MeshFileError::UnknownFormat { path: path.into() })?;
    let bytes = std::fs::read(path).map_err(|error| MeshFileError::Io { path: path.into(), error })?;
    let name = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    read_mesh(&name, &bytes, format).map_err(|error| MeshFileError::Import { path: path.into(), error })
}

/// Builds a mesh from loose triangles, welding bit-equal corners.
#[derive(Default)]
struct Welder {
    mesh: Mesh,
    index: HashMap<[u32; 3], u32>,
}

impl Welder {
    fn vertex(&mut self, p: Vec3) -> u32 {
        let key = (p + Vec3::ZERO).to_array().map(f32::to_bits);
        let positions = &mut self.mesh.positions;
        *self.index.entry(key).or_insert_with(|| {
            positions.push(p);
            (positions.len() - 1) as u32
        })
    }

    fn triangle(&mut self, t: [Vec3; 3]) {
        let t = t.map(|p| self.vertex(p));
        self.mesh.triangles.push(t);
    }
}

mod stl {
    use crate::import::*;

    fn malformed(name: &str, message: String) -> ImportError {
        ImportError::Malformed { format: MeshFormat::Stl, name: name.into(), message }
    }

    pub fn read(name: &str, bytes: &[u8]) -> Result<Mesh, ImportError> {
        if bytes.len() >= 84 {
            let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as u64;
            if 84 + 50 * n == bytes.len() as u64 {
                return binary(name, bytes, n as usize);
            }
        }
        let text = String::from_utf8_lossy(bytes);
        if text.trim_start().starts_with("solid") {
            return ascii(name, &text);
        }
        Err(malformed(
            name,
            "neither binary STL (the size does not match the triangle count in the header) nor ASCII STL \
             (no `solid` at the start)"
                .into(),
        ))
    }

    fn binary(name: &str, bytes: &[u8], n: usize) -> Result<Mesh, ImportError> {
        if n > MAX_IMPORT_TRIANGLES {
            return Err(ImportError::TooLarge { format: MeshFormat::Stl, name: name.into() });
        }
        let mut w = Welder::default();
        w.mesh.name = name.into();
        for (i, rec) in bytes[84..].chunks_exact(50).enumerate() {
            let f = |k: usize| f32::from_le_bytes(rec[12 + 4 * k..16 + 4 * k].try_into().unwrap_or([0; 4]));
            let t = [0, 1, 2].map(|v| Vec3::new(f(3 * v), f(3 * v + 1), f(3 * v + 2)));
            if !t.iter().all(|p| p.is_finite()) {
                return Err(malformed(name, format!("triangle {i} has a non-finite vertex")));
            }
            w.triangle(t);
        }
        Ok(w.mesh)
    }

    fn ascii(name: &str, text: &str) -> Result<Mesh, ImportError> {
        let mut w = Welder::default();
        w.mesh.name = name.into();
        let mut corners: Vec<Vec3> = Vec::new();
        for (ln, line) in text.lines().enumerate() {
            let mut it = line.split_whitespace();
            match it.next() {
                Some("outer") => corners.clear(),
                Some("vertex") => {
                    let mut c = [0f32; 3];
                    for v in &mut c {
                        *v = it.next().and_then(|t| t.parse::<f32>().ok()).filter(|v| v.is_finite()).ok_or_else(
                            || malformed(name, format!("line {}: a vertex needs three finite numbers", ln + 1)),
                        )?;
                    }
                    corners.push(Vec3::from_array(c));
                }
                Some("endloop") => {
                    if corners.len() < 3 {
                        return Err(malformed(name, format!("line {}: a facet needs at least 3 vertices", ln + 1)));
                    }
                    for k in 1..corners.len() - 1 {
                        w.triangle([corners[0], corners[k], corners[k + 1]]);
                    }
                    if w.mesh.triangles.len() > MAX_IMPORT_TRIANGLES {
                        return Err(ImportError::TooLarge { format: MeshFormat::Stl, name: name.into() });
                    }
                    corners.clear();
                }
                _ => {}
            }
        }
        Ok(w.mesh)
    }
}

mod glb {
    use crate::import::*;

    const FLOAT: u64 = 5126;
    const JSON: u32 = 0x4E4F_534A;
    const BIN: u32 = 0x004E_4942;

    struct Reader<'a> {
        name: &'a str,
        doc: Value,
        bin: Option<&'a [u8]>,
    }

    fn malformed(name: &str, message: impl Into<String>) -> ImportError {
        ImportError::Malformed { format: MeshFormat::Glb, name: name.into(), message: message.into() }
    }

    fn unsupported(name: &str, what: impl Into<String>, hint: &str) -> ImportError {
        ImportError::Unsupported { format: MeshFormat::Glb, name: name.into(), what: what.into(), hint: hint.into() }
    }

    const REEXPORT: &str = "export the model again as a self-contained GLB without compression";

    pub fn read(name: &str, bytes: &[u8]) -> Result<Mesh, ImportError> {
        let u32_at = |o: usize| bytes.get(o..o + 4).map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]));
        if bytes.get(..4) != Some(b"glTF") {
            return Err(malformed(name, "not a GLB file (it does not start with `glTF`)"));
        }
        if u32_at(4) != Some(2) {
            return Err(unsupported(name, "a glTF container version other than 2", REEXPORT));
        }
        let total = (u32_at(8).unwrap_or(0) as usize).min(bytes.len());
        let (mut json, mut bin) = (None, None);
        let mut at = 12;
        while at + 8 <= total {
            let (Some(len), Some(kind)) = (u32_at(at), u32_at(at + 4)) else { break };
            let data = bytes
                .get(at + 8..at + 8 + len as usize)
                .ok_or_else(|| malformed(name, format!("the chunk at byte {at} runs past the end of the file")))?;
            match kind {
                JSON if json.is_none() => json = Some(data),
                BIN if bin.is_none() => bin = Some(data),
                _ => {}
            }
            at += 8 + (len as usize).next_multiple_of(4);
        }
        let json = json.ok_or_else(|| malformed(name, "there is no JSON chunk"))?;
        let doc: Value = serde_json::from_slice(json)
            .map_err(|e| malformed(name, format!("the JSON chunk is not valid JSON: {e}")))?;
        Reader { name, doc, bin }.mesh()
    }

    /// A non-negative integer field, with a default when absent.
    fn uint(v: &Value, key: &str, default: Option<u64>) -> Option<u64> {
        match v.get(key) {
            None => default,
            Some(x) => x.as_u64(),
        }
    }

    impl Reader<'_> {
        fn bad(&self, message: impl Into<String>) -> ImportError {
            malformed(self.name, message)
        }

        fn item(&self, kind: &str, i: u64) -> Result<&Value, ImportError> {
            self.doc
                .get(kind)
                .and_then(|a| a.get(i as usize))
                .ok_or_else(|| self.bad(format!("{kind}[{i}] is referred to but does not exist")))
        }

        fn mesh(&self) -> Result<Mesh, ImportError> {
            let required = self.doc.get("extensionsRequired").and_then(Value::as_array);
            if let Some(ext) = required.into_iter().flatten().next() {
                // Every extension a file requires changes how it must be read.
                let ext = ext.as_str().unwrap_or("?");
                return Err(match ext {
                    "KHR_draco_mesh_compression" => unsupported(self.name, "Draco mesh compression", REEXPORT),
                    _ => unsupported(self.name, format!("the required extension `{ext}`"), REEXPORT),
                });
            }
            let nodes = self.doc.get("nodes").and_then(Value::as_array).map_or(&[][..], Vec::as_slice);
            let roots: Vec<u64> = match self.doc.get("scenes").and_then(Value::as_array) {
                Some(scenes) if !scenes.is_empty() => {
                    let s = uint(&self.doc, "scene", Some(0)).ok_or_else(|| self.bad("`scene` is not an index"))?;
                    let scene =
                        scenes.get(s as usize).ok_or_else(|| self.bad(format!("scenes[{s}] does not exist")))?;
                    self.indices(scene, "nodes")?
                }
                // No scenes: every node that is nobody's child.
                _ => {
                    let mut child = vec![false; nodes.len()];
                    for n in nodes {
                        for c in self.indices(n, "children")? {
                            if let Some(f) = child.get_mut(c as usize) {
                                *f = true;
                            }
                        }
                    }
                    (0..nodes.len() as u64).filter(|&i| !child[i as usize]).collect()
                }
            };
            let mut out = Mesh { name: self.name.into(), ..Mesh::default() };
            let mut visited = vec![false; nodes.len()];
            let mut stack: Vec<(u64, DMat4)> = roots.into_iter().rev().map(|r| (r, DMat4::IDENTITY)).collect();
            while let Some((n, parent)) = stack.pop() {
                let node = self.item("nodes", n)?;
                if std::mem::replace(&mut visited[n as usize], true) {
                    return Err(self.bad(format!("node {n} is reached twice; glTF nodes must form trees")));
                }
                let world = parent * self.local(node, n)?;
                if let Some(m) = node.get("mesh") {
                    let m = m.as_u64().ok_or_else(|| self.bad(format!("nodes[{n}].mesh is not an index")))?;
                    self.add_mesh(m, &world, &mut out)?;
                }
                for c in self.indices(node, "children")?.into_iter().rev() {
                    stack.push((c, world));
                }
            }
            Ok(out)
        }

        fn indices(&self, v: &Value, key: &str) -> Result<Vec<u64>, ImportError> {
            match v.get(key) {
                None => Ok(Vec::new()),
                Some(a) => a
                    .as_array()
                    .and_then(|a| a.iter().map(Value::as_u64).collect())
                    .ok_or_else(|| self.bad(format!("`{key}` is not a list of indices"))),
            }
        }

        fn numbers<const N: usize>(&self, v: Option<&Value>, what: &str) -> Result<Option<[f64; N]>, ImportError> {
            let Some(v) = v else { return Ok(None) };
            let a =
                v.as_array().filter(|a| a.len() == N).ok_or_else(|| self.bad(format!("{what} needs {N} numbers")))?;
            let mut out = [0.0; N];
            for (o, x) in out.iter_mut().zip(a) {
                *o = x.as_f64().filter(|x| x.is_finite()).ok_or_else(|| self.bad(format!("{what} is not finite")))?;
            }
            Ok(Some(out))
        }

        fn local(&self, node: &Value, n: u64) -> Result<DMat4, ImportError> {
            if let Some(m) = self.numbers::<16>(node.get("matrix"), &format!("nodes[{n}].matrix"))? {
                return Ok(DMat4::from_cols_array(&m));
            }
            let t = self.numbers::<3>(node.get("translation"), "a translation")?.unwrap_or([0.0; 3]);
            let r = self.numbers::<4>(node.get("rotation"), "a rotation")?.unwrap_or([0.0, 0.0, 0.0, 1.0]);
            let s = self.numbers::<3>(node.get("scale"), "a scale")?.unwrap_or([1.0; 3]);
            let q = DQuat::from_array(r);
            let q = if q.length_squared() > 0.0 { q.normalize() } else { DQuat::IDENTITY };
            Ok(DMat4::from_scale_rotation_translation(DVec3::from(s), q, DVec3::from(t)))
        }

        fn add_mesh(&self, m: u64, world: &DMat4, out: &mut Mesh) -> Result<(), ImportError> {
            let mesh = self.item("meshes", m)?;
            let prims = mesh.get("primitives").and_then(Value::as_array).map_or(&[][..], Vec::as_slice);
            let flip = world.determinant() < 0.0;
            for (pi, prim) in prims.iter().enumerate() {
                if prim.get("extensions").and_then(|e| e.get("KHR_draco_mesh_compression")).is_some() {
                    return Err(unsupported(self.name, "Draco mesh compression", REEXPORT));
                }
                if uint(prim, "mode", Some(4)) != Some(4) {
                    continue;
                }
                let pos = prim
                    .get("attributes")
                    .and_then(|a| a.get("POSITION"))
                    .and_then(Value::as_u64)
                    .ok_or_else(|| self.bad(format!("meshes[{m}].primitives[{pi}] has no POSITION")))?;
                let positions = self.positions(pos)?;
                let idx = match uint(prim, "indices", None) {
                    Some(a) => self.index_list(a)?,
                    None => (0..positions.len() as u32).collect(),
                };
                if idx.len() % 3 != 0 {
                    return Err(self
                        .bad(format!("meshes[{m}].primitives[{pi}] has {} indices, not a multiple of 3", idx.len())));
                }
                if let Some(&bad) = idx.iter().find(|&&i| i as usize >= positions.len()) {
                    return Err(
                        self.bad(format!("meshes[{m}].primitives[{pi}] refers to vertex {bad} of {}", positions.len()))
                    );
                }
                if out.triangles.len() + idx.len() / 3 > MAX_IMPORT_TRIANGLES {
                    return Err(ImportError::TooLarge { format: MeshFormat::Glb, name: self.name.into() });
                }
                let base = out.positions.len() as u32;
                out.positions.extend(positions.iter().map(|p| world.transform_point3(p.as_dvec3()).as_vec3()));
                for t in idx.chunks_exact(3) {
                    let t = [t[0] + base, t[1] + base, t[2] + base];
                    out.triangles.push(if flip { [t[0], t[2], t[1]] } else { t });
                }
            }
            Ok(())
        }

        /// The bytes of accessor `a`'s elements: (data, stride, count), with
        /// `elem` bytes per element; `None` data for an all-zero accessor.
        fn elements(&self, a: u64, elem: usize) -> Result<(Option<&[u8]>, usize, usize), ImportError> {
            let acc = self.item("accessors", a)?;
            if acc.get("sparse").is_some() {
                return Err(unsupported(self.name, format!("a sparse accessor (accessors[{a}])"), REEXPORT));
            }
            let count =
                uint(acc, "count", None).ok_or_else(|| self.bad(format!("accessors[{a}] has no count")))? as usize;
            let Some(v) = uint(acc, "bufferView", None) else {
                // No data: all zeros (bounded by the file's size).
                if count > self.doc.to_string().len() + self.bin.map_or(0, <[u8]>::len) {
                    return Err(self.bad(format!("accessors[{a}] has {count} elements and no data")));
                }
                return Ok((None, elem, count));
            };
            let view = self.item("bufferViews", v)?;
            let buf = uint(view, "buffer", None).ok_or_else(|| self.bad(format!("bufferViews[{v}] has no buffer")))?;
            let buffer = self.item("buffers", buf)?;
            if let Some(uri) = buffer.get("uri").and_then(Value::as_str) {
                let what = if uri.starts_with("data:") {
                    "a buffer embedded as a data URI"
                } else {
                    "an external buffer file"
                };
                return Err(unsupported(self.name, format!("{what} (buffers[{buf}])"), REEXPORT));
            }
            let bin = self
                .bin
                .filter(|_| buf == 0)
                .ok_or_else(|| self.bad(format!("buffers[{buf}] has no data in the file")))?;
            let start = uint(view, "byteOffset", Some(0)).unwrap_or(0) as usize;
            let len = uint(view, "byteLength", None)
                .ok_or_else(|| self.bad(format!("bufferViews[{v}] has no byteLength")))? as usize;
            let data = start
                .checked_add(len)
                .and_then(|end| bin.get(start..end))
                .ok_or_else(|| self.bad(format!("bufferViews[{v}] runs past the binary chunk")))?;
            let stride = uint(view, "byteStride", Some(elem as u64)).unwrap_or(0) as usize;
            if stride < elem {
                return Err(self.bad(format!("bufferViews[{v}] has a byteStride below the element size {elem}")));
            }
            let off = uint(acc, "byteOffset", Some(0)).unwrap_or(0) as usize;
            let need = if count == 0 {
                0
            } else {
                (count - 1).saturating_mul(stride).saturating_add(elem).saturating_add(off)
            };
            if need > data.len() {
                return Err(self
                    .bad(format!("accessors[{a}] needs {need} bytes of bufferViews[{v}], which has {}", data.len())));
            }
            Ok((Some(&data[off..]), stride, count))
        }

        fn positions(&self, a: u64) -> Result<Vec<Vec3>, ImportError> {
            let acc = self.item("accessors", a)?;
            if uint(acc, "componentType", None) != Some(FLOAT)
                || acc.get("type").and_then(Value::as_str) != Some("VEC3")
            {
                return Err(unsupported(
                    self.name,
                    format!("positions that are not FLOAT VEC3 (accessors[{a}], e.g. quantized)"),
                    REEXPORT,
                ));
            }
            let (data, stride, count) = self.elements(a, 12)?;
            let Some(data) = data else { return Ok(vec![Vec3::ZERO; count]) };
            (0..count)
                .map(|i| {
                    let f = |k: usize| f32::from_le_bytes(data[i * stride + 4 * k..][..4].try_into().unwrap_or([0; 4]));
                    let p = Vec3::new(f(0), f(1), f(2));
                    if p.is_finite() {
                        Ok(p)
                    } else {
                        Err(self.bad(format!("accessors[{a}] has a non-finite position")))
                    }
                })
                .collect()
        }

        fn index_list(&self, a: u64) -> Result<Vec<u32>, ImportError> {
            let acc = self.item("accessors", a)?;
            let size = match uint(acc, "componentType", None) {
                Some(5121) => 1,
                Some(5123) => 2,
                Some(5125) => 4,
                _ => return Err(self.bad(format!("accessors[{a}] is not an unsigned u8, u16 or u32 index list"))),
            };
            // Index views have no stride of their own (spec), so read them packed.
            let (data, _, count) = self.elements(a, size)?;
            let Some(data) = data else { return Ok(vec![0; count]) };
            Ok((0..count)
                .map(|i| {
                    let b = &data[i * size..(i + 1) * size];
                    match size {
                        1 => u32::from(b[0]),
                        2 => u32::from(u16::from_le_bytes([b[0], b[1]])),
                        _ => u32::from_le_bytes([b[0], b[1], b[2], b[3]]),
                    }
                })
                .collect())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{test_scenes, write_glb, write_obj, write_stl};
    use genform_core::scene::{Scene, Tessellation};
    use serde_json::json;

    const TESS: Tessellation = Tessellation { radial: 6, rings: 4 };

    fn triangles(m: &Mesh) -> Vec<[Vec3; 3]> {
        m.triangles.iter().map(|t| t.map(|i| m.positions[i as usize])).collect()
    }

    fn scene_triangles(s: &Scene) -> Vec<[Vec3; 3]> {
        let mut v = Vec::new();
        s.for_each_triangle(TESS, |t, _| v.push(t));
        v
    }

    /// Every triangle of `want` has a match in `got` (same corners in the same
    /// cyclic order, within `tol`), and the counts agree.
    fn same_triangles(got: &[[Vec3; 3]], want: &[[Vec3; 3]], tol: f32) {
        assert_eq!(got.len(), want.len());
        let mut used = vec![false; got.len()];
        for w in want {
            let hit = (0..got.len())
                .find(|&i| !used[i] && (0..3).any(|r| (0..3).all(|k| got[i][(k + r) % 3].distance(w[k]) <= tol)));
            let i = hit.unwrap_or_else(|| panic!("no match for {w:?}"));
            used[i] = true;
        }
    }

    #[test]
    fn glb_round_trip_keeps_the_triangles() {
        let s = test_scenes::mixed();
        let m = read_mesh("mixed", &write_glb(&s, TESS), MeshFormat::Glb).unwrap();
        // The writer drops degenerate triangles (the flattened box) and
        // re-orthogonalizes node matrices by up to 1e-4 of an instance's size.
        let want: Vec<[Vec3; 3]> =
            scene_triangles(&s).into_iter().filter(|[a, b, c]| (*b - *a).cross(*c - *a).length() > 1e-9).collect();
        same_triangles(&triangles(&m), &want, 1e-3);
    }

    #[test]
    fn stl_round_trip_is_exact_and_welded() {
        let s = test_scenes::boxes(3);
        let m = read_mesh("boxes", &write_stl(&s, TESS), MeshFormat::Stl).unwrap();
        same_triangles(&triangles(&m), &scene_triangles(&s), 0.0);
        assert_eq!(m.positions.len(), 24, "8 corners per box");
        let mixed = test_scenes::mixed();
        let m = read_mesh("mixed", &write_stl(&mixed, TESS), MeshFormat::Stl).unwrap();
        assert_eq!(triangles(&m), scene_triangles(&mixed));
    }

    #[test]
    fn ascii_stl_and_obj() {
        let text = "solid t\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n   vertex 1 1 0\n   \
                    vertex 0 1 0\n  endloop\n endfacet\nendsolid t\n";
        let m = read_mesh("t", text.as_bytes(), MeshFormat::Stl).unwrap();
        assert_eq!(m.triangles, vec![[0, 1, 2], [0, 2, 3]]);
        let e = read_mesh("t", b"solid t\nouter loop\nvertex 0 0 x\n", MeshFormat::Stl).unwrap_err();
        assert!(e.to_string().contains("line 3"), "{e}");
        assert!(matches!(read_mesh("t", b"solid t\nendsolid\n", MeshFormat::Stl), Err(ImportError::Empty { .. })));
        assert!(read_mesh("t", b"garbage", MeshFormat::Stl).unwrap_err().to_string().contains("neither"));
        let obj = write_obj(&test_scenes::boxes(2), TESS);
        assert_eq!(read_mesh("b", obj.as_bytes(), MeshFormat::Obj).unwrap().triangles.len(), 24);
        assert!(matches!(read_mesh("b", b"v 0 0\n", MeshFormat::Obj), Err(ImportError::Malformed { .. })));
    }

    #[test]
    fn mesh_files_are_read_by_extension_and_named_by_stem() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/shape/assets");
        let path = dir.join("trunk.obj");
        let m = read_mesh_file(&path).unwrap();
        assert_eq!(m, Mesh::from_obj("trunk", &std::fs::read_to_string(&path).unwrap()).unwrap());
        let missing = read_mesh_file(&dir.join("gone.stl")).unwrap_err();
        assert!(matches!(missing, MeshFileError::Io { .. }) && missing.to_string().contains("gone.stl"), "{missing}");
        let unknown = read_mesh_file(&dir.join("trunk.ply")).unwrap_err();
        assert!(matches!(unknown, MeshFileError::UnknownFormat { .. }), "{unknown}");
        assert!(unknown.to_string().contains("use .obj, .stl or .glb"), "{unknown}");
    }

    #[test]
    fn formats_by_extension() {
        assert_eq!(MeshFormat::from_path(Path::new("a/b.GLB")), Some(MeshFormat::Glb));
        assert_eq!(MeshFormat::from_extension(".stl"), Some(MeshFormat::Stl));
        assert_eq!(MeshFormat::from_path(Path::new("x.ply")), None);
        assert_eq!(MeshFormat::Obj.to_string(), "OBJ");
    }

    /// A GLB of `doc` with `bin` as its binary chunk.
    fn glb(doc: &Value, bin: &[u8]) -> Vec<u8> {
        let mut j = serde_json::to_vec(doc).unwrap();
        j.resize(j.len().next_multiple_of(4), b' ');
        let mut b = bin.to_vec();
        b.resize(b.len().next_multiple_of(4), 0);
        let mut out = b"glTF".to_vec();
        out.extend(2u32.to_le_bytes());
        out.extend(((12 + 8 + j.len() + 8 + b.len()) as u32).to_le_bytes());
        out.extend((j.len() as u32).to_le_bytes());
        out.extend(b"JSON");
        out.extend(j);
        out.extend((b.len() as u32).to_le_bytes());
        out.extend(b"BIN\0");
        out.extend(b);
        out
    }

    /// One triangle, interleaved with a dummy float (stride 16), u8 indices,
    /// placed by a parent node that mirrors x and a child that translates.
    fn strided_doc() -> (Value, Vec<u8>) {
        let mut bin = Vec::new();
        for p in [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
            for c in p {
                bin.extend(c.to_le_bytes());
            }
            bin.extend(9.0f32.to_le_bytes());
        }
        bin.extend([0u8, 1, 2, 0]);
        let doc = json!({
            "asset": {"version": "2.0"},
            "scene": 0,
            "scenes": [{"nodes": [0]}],
            "nodes": [{"scale": [-1.0, 1.0, 1.0], "children": [1]}, {"translation": [0.0, 0.0, 5.0], "mesh": 0}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}, {"attributes": {"POSITION": 0}, "mode": 1}]}],
            "accessors": [
                {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"},
                {"bufferView": 1, "componentType": 5121, "count": 3, "type": "SCALAR"}
            ],
            "bufferViews": [
                {"buffer": 0, "byteOffset": 0, "byteLength": 48, "byteStride": 16},
                {"buffer": 0, "byteOffset": 48, "byteLength": 3}
            ],
            "buffers": [{"byteLength": 52}]
        });
        (doc, bin)
    }

    #[test]
    fn glb_strides_hierarchy_and_mirroring() {
        let (doc, bin) = strided_doc();
        let m = read_mesh("t", &glb(&doc, &bin), MeshFormat::Glb).unwrap();
        // Mirrored: x negated and the winding turned, so the normal stays +z.
        let t = triangles(&m);
        assert_eq!(t, vec![[Vec3::new(0.0, 0.0, 5.0), Vec3::new(0.0, 1.0, 5.0), Vec3::new(-1.0, 0.0, 5.0)]]);
        assert!((t[0][1] - t[0][0]).cross(t[0][2] - t[0][0]).z > 0.0);
    }

    #[test]
    fn glb_refuses_what_it_cannot_read() {
        let (doc, bin) = strided_doc();
        let with = |f: &dyn Fn(&mut Value)| {
            let mut d = doc.clone();
            f(&mut d);
            read_mesh("t", &glb(&d, &bin), MeshFormat::Glb).unwrap_err().to_string()
        };
        assert!(with(&|d| d["buffers"][0]["uri"] = json!("mesh.bin")).contains("external buffer"));
        assert!(
            with(&|d| d["buffers"][0]["uri"] = json!("data:application/octet-stream;base64,AA==")).contains("data URI")
        );
        assert!(with(&|d| d["accessors"][0]["sparse"] = json!({"count": 1})).contains("sparse accessor"));
        assert!(with(&|d| d["extensionsRequired"] = json!(["KHR_draco_mesh_compression"])).contains("Draco"));
        assert!(
            with(&|d| d["meshes"][0]["primitives"][0]["extensions"] = json!({"KHR_draco_mesh_compression": {}}))
                .contains("Draco")
        );
        assert!(with(&|d| d["accessors"][0]["componentType"] = json!(5123)).contains("FLOAT VEC3"));
        assert!(with(&|d| d["accessors"][0]["count"] = json!(4)).contains("needs"));
        assert!(with(&|d| d["nodes"][1]["children"] = json!([0])).contains("reached twice"));
        assert!(with(&|d| d["nodes"][1]["mesh"] = json!(7)).contains("meshes[7]"));
        let good = glb(&doc, &bin);
        assert!(read_mesh("t", &good[..40], MeshFormat::Glb).is_err());
        assert!(read_mesh("t", b"glTX....", MeshFormat::Glb).unwrap_err().to_string().contains("not a GLB"));
        let empty = glb(&json!({"asset": {"version": "2.0"}}), &[]);
        assert!(matches!(read_mesh("t", &empty, MeshFormat::Glb), Err(ImportError::Empty { .. })));
    }
}
