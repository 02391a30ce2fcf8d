//! OBJ footprints: the faces that look up (see the parent module).

use super::frames::{MAX_FOOTPRINTS, recentre};
use anyhow::{Context, Result, bail};
use genform_shape::{FootprintLot, FootprintSet as Footprints};
use std::path::Path;

/// The up-facing faces of the OBJ file at `path` as lots, re-centred when
/// they lie far from the origin.
pub fn read_obj(path: &Path) -> Result<Footprints> {
    let faces = read_obj_faces(path)?;
    let mut lots: Vec<FootprintLot> =
        faces.into_iter().enumerate().map(|(k, corners)| FootprintLot::numbered(k, "face", corners)).collect();
    let origin = recentre(&mut lots).map(|[x, z]| format!("({x}, 0, {z}) of the OBJ file"));
    Ok(Footprints { lots, origin, skipped: Vec::new() })
}

/// The up-facing faces of the OBJ file at `path` as lots.
fn read_obj_faces(path: &Path) -> Result<Vec<Vec<[f64; 2]>>> {
    let text = crate::text::read_text(path, "footprints")?;
    let mut verts: Vec<[f64; 3]> = Vec::new();
    let mut lots = Vec::new();
    for (ln, line) in text.lines().enumerate() {
        let at = || format!("{}:{}", path.display(), ln + 1);
        let mut it = line.split_whitespace();
        match it.next() {
            Some("v") => {
                let c: Vec<f64> = it.take(3).map(str::parse).collect::<Result<_, _>>().ok().unwrap_or_default();
                if c.len() != 3 || !c.iter().all(|x| x.is_finite()) {
                    bail!("{}: a vertex needs three finite numbers: `{line}`", at());
                }
                verts.push([c[0], c[1], c[2]]);
            }
            Some("f") => {
                let mut face = Vec::new();
                for tok in it {
                    let idx: i64 = tok
                        .split('/')
                        .next()
                        .unwrap_or("")
                        .parse()
                        .with_context(|| format!("{}: `{tok}` is no vertex index", at()))?;
                    let k = if idx < 0 { verts.len() as i64 + idx } else { idx - 1 };
                    let v = usize::try_from(k)
                        .ok()
                        .and_then(|k| verts.get(k))
                        .with_context(|| format!("{}: vertex {idx} does not exist ({} so far)", at(), verts.len()))?;
                    face.push(*v);
                }
                if face.len() < 3 {
                    bail!("{}: a face needs at least three corners", at());
                }
                // Newell's normal: keep the faces that look up.
                let mut n = [0.0f64; 3];
                for i in 0..face.len() {
                    let (a, b) = (face[i], face[(i + 1) % face.len()]);
                    n[0] += (a[1] - b[1]) * (a[2] + b[2]);
                    n[1] += (a[2] - b[2]) * (a[0] + b[0]);
                    n[2] += (a[0] - b[0]) * (a[1] + b[1]);
                }
                let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
                if len > 0.0 && n[1] >= 0.5 * len {
                    lots.push(face.iter().map(|v| [v[0], v[2]]).collect());
                }
                if lots.len() > MAX_FOOTPRINTS {
                    bail!(
                        "{} holds more than {MAX_FOOTPRINTS} footprints; at most that many are derived in one run",
                        path.display()
                    );
                }
            }
            _ => {}
        }
    }
    Ok(lots)
}
