//! GeoJSON footprints (RFC 7946 and its legacy `crs` member; see the
//! parent module).

use super::frames::*;
use anyhow::{Context, Result, bail};
use genform_shape::{FootprintSet as Footprints, LotProps};
use serde_json::Value;
use std::path::Path;

/// The lots of the GeoJSON file at `path` in local metres; its LineString
/// and MultiLineString features are streets, which each lot's
/// `street_edge` faces ([`face_streets`]).
pub fn read_geojson(path: &Path) -> Result<Footprints> {
    let text = crate::text::read_text(path, "footprints")?;
    let value: Value = serde_json::from_str(&text).with_context(|| format!("{} is not JSON", path.display()))?;
    let mut raw = Vec::new();
    let mut skipped = Vec::new();
    let mut streets = Vec::new();
    collect(&value, None, &mut Found { lots: &mut raw, streets: &mut streets, skipped: &mut skipped })
        .with_context(|| format!("{} is not GeoJSON genform can read", path.display()))?;
    if raw.len() > MAX_FOOTPRINTS {
        bail!("{} holds {} footprints; at most {MAX_FOOTPRINTS} are derived in one run", path.display(), raw.len());
    }
    if raw.is_empty() && !skipped.is_empty() {
        return Err(no_usable(path, &skipped));
    }
    let crs = crs_name(&value);
    let frame = frame_of(crs.as_deref(), &raw);
    finish(path, raw, skipped, &streets, frame, crs.as_deref())
}

/// The name the legacy `crs` member gives, if any.
pub(super) fn crs_name(v: &Value) -> Option<String> {
    let c = v.get("crs")?;
    let name = c.get("properties").and_then(|p| p.get("name")).and_then(Value::as_str)?;
    Some(name.to_string())
}

/// A feature's name in messages: its number (1-based) and its `id`, or
/// the `id`, `@id` or `name` of its properties.
pub(super) fn feature_label(k: usize, f: &Value) -> String {
    let p = f.get("properties");
    let id = f
        .get("id")
        .or_else(|| p.and_then(|p| p.get("id")))
        .or_else(|| p.and_then(|p| p.get("@id")))
        .or_else(|| p.and_then(|p| p.get("name")));
    match id {
        Some(Value::String(s)) => format!("feature {} (\"{s}\")", k + 1),
        Some(v @ Value::Number(_)) => format!("feature {} (id {v})", k + 1),
        _ => format!("feature {}", k + 1),
    }
}

/// The feature a geometry belongs to: its label and properties.
pub(super) type Owner<'a> = Option<(&'a str, LotProps)>;

/// What [`collect`] finds: lots, street lines and what it skipped.
pub(super) struct Found<'a> {
    lots: &'a mut Vec<RawLot>,
    streets: &'a mut Vec<Vec<[f64; 2]>>,
    skipped: &'a mut Vec<String>,
}

pub(super) fn collect(v: &Value, owner: Owner, found: &mut Found) -> Result<()> {
    let kind = v.get("type").and_then(Value::as_str).context("an object without a \"type\"")?;
    let label = |n: usize| -> (String, LotProps) {
        match owner {
            Some((l, p)) => (l.to_string(), p),
            None => (format!("footprint {}", n + 1), LotProps { index: n as f64, ..LotProps::default() }),
        }
    };
    match kind {
        "FeatureCollection" => {
            let feats =
                v.get("features").and_then(Value::as_array).context("a FeatureCollection without \"features\"")?;
            for (k, f) in feats.iter().enumerate() {
                let name = feature_label(k, f);
                if f.get("type").and_then(Value::as_str) != Some("Feature") {
                    found.skipped.push(format!("{name} is not a Feature"));
                    continue;
                }
                collect(f, Some((&name, props_of(f.get("properties"), k))), found)?;
            }
        }
        // A feature without geometry (`null`) has no lot.
        "Feature" => {
            let name = feature_label(0, v);
            let owner = owner.or(Some((&name, props_of(v.get("properties"), 0))));
            match v.get("geometry") {
                Some(Value::Null) | None => {}
                Some(g) => collect(g, owner, found)?,
            }
        }
        "GeometryCollection" => {
            for g in
                v.get("geometries").and_then(Value::as_array).context("a GeometryCollection without \"geometries\"")?
            {
                collect(g, owner, found)?;
            }
        }
        "Polygon" => {
            let (name, props) = label(found.lots.len());
            match v.get("coordinates").context("a Polygon without \"coordinates\"").and_then(outer_ring) {
                Ok(xy) => found.lots.push(RawLot { xy, label: name, props }),
                Err(e) => found.skipped.push(format!("{name}: {e}")),
            }
        }
        "MultiPolygon" => {
            let (name, props) = label(found.lots.len());
            let Some(polys) = v.get("coordinates").and_then(Value::as_array) else {
                found.skipped.push(format!("{name}: a MultiPolygon without coordinates"));
                return Ok(());
            };
            for (i, p) in polys.iter().enumerate() {
                let name = format!("{name}, polygon {}", i + 1);
                match outer_ring(p) {
                    Ok(xy) => found.lots.push(RawLot { xy, label: name, props }),
                    Err(e) => found.skipped.push(format!("{name}: {e}")),
                }
            }
        }
        // Lines are streets (positions that are no numbers left out: a
        // street missing only leaves a lot without its street).
        "LineString" => found.streets.push(line(v.get("coordinates"))),
        "MultiLineString" => {
            for l in v.get("coordinates").and_then(Value::as_array).into_iter().flatten() {
                found.streets.push(line(Some(l)));
            }
        }
        // Points are not lots.
        "Point" | "MultiPoint" => {}
        other => bail!("unknown GeoJSON type \"{other}\""),
    }
    Ok(())
}

/// A LineString's `[x, y]` positions (those that are numbers).
fn line(coords: Option<&Value>) -> Vec<[f64; 2]> {
    let pts = coords.and_then(Value::as_array).into_iter().flatten();
    pts.filter_map(|p| Some([p.get(0)?.as_f64()?, p.get(1)?.as_f64()?])).collect()
}

/// The outer ring of a Polygon's coordinates as `[x, y]` positions,
/// without the closing repeat of the first position.
pub(super) fn outer_ring(coords: &Value) -> Result<Vec<[f64; 2]>> {
    let ring = coords.get(0).and_then(Value::as_array).context("a Polygon without an outer ring")?;
    let mut pts = Vec::with_capacity(ring.len());
    for p in ring {
        let xy = p.as_array().filter(|a| a.len() >= 2).context("a position that is not [x, y]")?;
        let x = xy[0].as_f64().context("a coordinate that is not a number")?;
        let y = xy[1].as_f64().context("a coordinate that is not a number")?;
        pts.push([x, y]);
    }
    ring_of(pts)
}
