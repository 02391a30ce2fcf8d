//! Building footprints from GeoJSON or OBJ: the lots a shape grammar is
//! derived on, one derivation per polygon (`footprints "…";` in a `.sg`
//! file, or `genform sample --footprints FILE`). [`read_footprints`] picks
//! the reader by the file's extension (`.obj`, else GeoJSON).
//!
//! OBJ: every face (`f`, any number of corners) that faces up — its normal
//! within 60° of +y — is one lot, its corners projected onto the ground
//! `(x, z)`; other faces (walls, undersides) are skipped, so a plane of lot
//! polygons exported from Blender or QGIS, or the flat roofs of a massing
//! model, read alike. Coordinates are genform's own (y up).
//!
//! GeoJSON: a FeatureCollection, a Feature, a GeometryCollection or a bare
//! geometry; every Polygon and each polygon of a MultiPolygon is one lot
//! (its outer ring; holes are left out). Coordinates are taken as metres
//! in a projected system, `[x, y]` with y north: a lot's world corner is
//! `(x, −y)` in genform's frame (x east, y up, z south). Longitude and
//! latitude are refused with a hint, as their degrees would make lots a
//! few millionths of a metre wide.

use anyhow::{Context, Result, bail};
use serde_json::Value;
use std::path::Path;

/// Most footprints one file may give (each is a whole derivation).
pub const MAX_FOOTPRINTS: usize = 100_000;

/// The lots of the footprint file at `path` (OBJ when its extension says
/// so, else GeoJSON): world `(x, z)` corners each.
pub fn read_footprints(path: &Path) -> Result<Vec<Vec<[f64; 2]>>> {
    if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("obj")) { read_obj(path) } else { read_geojson(path) }
}

/// The up-facing faces of the OBJ file at `path` as lots.
pub fn read_obj(path: &Path) -> Result<Vec<Vec<[f64; 2]>>> {
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

/// The lots of the GeoJSON file at `path`: world `(x, z)` corners each.
pub fn read_geojson(path: &Path) -> Result<Vec<Vec<[f64; 2]>>> {
    let text = crate::text::read_text(path, "footprints")?;
    let value: Value = serde_json::from_str(&text).with_context(|| format!("{} is not JSON", path.display()))?;
    let mut lots = Vec::new();
    collect(&value, &mut lots).with_context(|| format!("{} is not GeoJSON genform can read", path.display()))?;
    if lots.len() > MAX_FOOTPRINTS {
        bail!("{} holds {} footprints; at most {MAX_FOOTPRINTS} are derived in one run", path.display(), lots.len());
    }
    let degrees = lots.iter().flatten().all(|[x, z]| x.abs() <= 180.0 && z.abs() <= 90.0)
        && lots.iter().all(|l| extent(l) < 0.05);
    if !lots.is_empty() && degrees {
        bail!(
            "{}: the footprints look like longitude and latitude (every lot under 0.05 units across); \
             genform reads metres: project the file first (e.g. `ogr2ogr -t_srs EPSG:3857 out.geojson in.geojson`)",
            path.display()
        );
    }
    Ok(lots)
}

fn extent(lot: &[[f64; 2]]) -> f64 {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in lot {
        for i in 0..2 {
            lo[i] = lo[i].min(p[i]);
            hi[i] = hi[i].max(p[i]);
        }
    }
    (hi[0] - lo[0]).max(hi[1] - lo[1])
}

fn collect(v: &Value, out: &mut Vec<Vec<[f64; 2]>>) -> Result<()> {
    let kind = v.get("type").and_then(Value::as_str).context("an object without a \"type\"")?;
    match kind {
        "FeatureCollection" => {
            for f in v.get("features").and_then(Value::as_array).context("a FeatureCollection without \"features\"")? {
                collect(f, out)?;
            }
        }
        // A feature without geometry (`null`) has no lot.
        "Feature" => match v.get("geometry") {
            Some(Value::Null) | None => {}
            Some(g) => collect(g, out)?,
        },
        "GeometryCollection" => {
            for g in
                v.get("geometries").and_then(Value::as_array).context("a GeometryCollection without \"geometries\"")?
            {
                collect(g, out)?;
            }
        }
        "Polygon" => out.push(outer_ring(v.get("coordinates").context("a Polygon without \"coordinates\"")?)?),
        "MultiPolygon" => {
            let polys = v.get("coordinates").and_then(Value::as_array).context("a MultiPolygon without coordinates")?;
            for p in polys {
                out.push(outer_ring(p)?);
            }
        }
        // Points and lines are not lots.
        "Point" | "MultiPoint" | "LineString" | "MultiLineString" => {}
        other => bail!("unknown GeoJSON type \"{other}\""),
    }
    Ok(())
}

/// The outer ring of a Polygon's coordinates as world `(x, z)` corners,
/// without the closing repeat of the first position.
fn outer_ring(coords: &Value) -> Result<Vec<[f64; 2]>> {
    let ring = coords.get(0).and_then(Value::as_array).context("a Polygon without an outer ring")?;
    let mut pts = Vec::with_capacity(ring.len());
    for p in ring {
        let xy = p.as_array().filter(|a| a.len() >= 2).context("a position that is not [x, y]")?;
        let x = xy[0].as_f64().context("a coordinate that is not a number")?;
        let y = xy[1].as_f64().context("a coordinate that is not a number")?;
        pts.push([x, -y]);
    }
    if pts.len() > 1 && pts.first() == pts.last() {
        pts.pop();
    }
    Ok(pts)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str) -> Result<Vec<Vec<[f64; 2]>>> {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("lots.geojson");
        std::fs::write(&path, text).unwrap();
        read_geojson(&path)
    }

    #[test]
    fn polygons_and_multipolygons_become_lots_north_to_minus_z() {
        let lots = read(
            r#"{"type": "FeatureCollection", "features": [
                {"type": "Feature", "properties": {}, "geometry": {"type": "Polygon",
                 "coordinates": [[[0, 0], [10, 0], [10, 8], [0, 8], [0, 0]], [[2, 2], [3, 2], [3, 3]]]}},
                {"type": "Feature", "geometry": null},
                {"type": "Feature", "geometry": {"type": "MultiPolygon", "coordinates": [
                    [[[20, 0], [26, 0], [23, 5], [20, 0]]], [[[30, 0], [34, 0], [34, 4]]]]}},
                {"type": "Feature", "geometry": {"type": "Point", "coordinates": [1, 2]}}
            ]}"#,
        )
        .unwrap();
        assert_eq!(lots.len(), 3);
        assert_eq!(lots[0], vec![[0.0, 0.0], [10.0, 0.0], [10.0, -8.0], [0.0, -8.0]], "closing corner dropped");
        assert_eq!(lots[1].len(), 3);
        assert_eq!(lots[2], vec![[30.0, 0.0], [34.0, 0.0], [34.0, -4.0]]);
    }

    #[test]
    fn obj_faces_that_look_up_are_lots() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("lots.obj");
        // A quad facing up (counter-clockwise seen from +y), a triangle
        // facing down and a wall; `v/vt/vn` indices and a negative one.
        let obj = "v 0 0 0\nv 0 0 -8\nv 10 0 -8\nv 10 0 0\nf 1/1/1 4/2/1 3 2\nf 1 2 3\nf 1 4 -1\n\
                   v 0 5 0\nf 1 4 -1\n";
        std::fs::write(&path, obj).unwrap();
        let lots = read_footprints(&path).unwrap();
        assert_eq!(lots, vec![vec![[0.0, 0.0], [10.0, 0.0], [10.0, -8.0], [0.0, -8.0]]]);
        std::fs::write(&path, "v 0 0 0\nf 1 2 3\n").unwrap();
        let e = format!("{:#}", read_footprints(&path).unwrap_err());
        assert!(e.contains("lots.obj:2: vertex 2 does not exist"), "{e}");
    }

    #[test]
    fn bad_files_say_what_is_wrong() {
        let e = format!("{:#}", read(r#"{"type": "Polygon"}"#).unwrap_err());
        assert!(e.contains("without \"coordinates\""), "{e}");
        let e = format!("{:#}", read(r#"{"type": "Circle"}"#).unwrap_err());
        assert!(e.contains("unknown GeoJSON type \"Circle\""), "{e}");
        let e = format!("{:#}", read("[1, 2").unwrap_err());
        assert!(e.contains("is not JSON"), "{e}");
        let lonlat = r#"{"type": "Polygon", "coordinates": [[[13.40, 52.52], [13.401, 52.52], [13.401, 52.521]]]}"#;
        let e = format!("{:#}", read(lonlat).unwrap_err());
        assert!(e.contains("longitude and latitude") && e.contains("project"), "{e}");
    }
}
