//! Building footprints from GeoJSON or OBJ: the lots a shape grammar is
//! derived on, one derivation per polygon (`footprints "…";` in a `.sg`
//! file, or `genform sample --footprints FILE`). [`read_lots`] picks the
//! reader by the file's extension (`.obj`, else GeoJSON).
//!
//! OBJ: every face (`f`, any number of corners) that faces up — its normal
//! within 60° of +y — is one lot, its corners projected onto the ground
//! `(x, z)`; other faces (walls, undersides) are skipped, so a plane of lot
//! polygons exported from Blender or QGIS, or the flat roofs of a massing
//! model, read alike. Coordinates are genform's own (y up).
//!
//! GeoJSON: a FeatureCollection, a Feature, a GeometryCollection or a bare
//! geometry; every Polygon and each polygon of a MultiPolygon is one lot
//! (its outer ring; holes are left out), carrying its feature's properties
//! ([`LotProps`]: OSM's `height`, `min_height`, `building:levels`,
//! `building`). Positions are `[x, y]` with y north, placed at world
//! `(x, −y)` (x east, y up, z south), in metres, read in one of three ways:
//!
//! * **longitude and latitude** (RFC 7946: WGS 84 degrees) when the legacy
//!   `crs` member names a geographic CRS (`CRS84`, EPSG:4326), or when
//!   there is no `crs`, every position lies within ±180 × ±90 and no lot
//!   spans 0.05 units (0.05° is 3–5 km; a lot in metres 5 cm wide is no
//!   lot): projected with `proj4rs` onto a transverse Mercator tangent to
//!   the footprints' centre (WGS 84 ellipsoid, scale 1 at the centre), so
//!   a district a few kilometres across is in true metres to within 10⁻⁶
//!   (scale error ≈ x²/2R²: 0.12 ppm at 2 km from the centre);
//! * **EPSG:3857** (Web Mercator, also 900913, 3785, 102100, 102113,
//!   named by `crs`): its "metres" are stretched by 1/cos(latitude)
//!   (1.56× at 50° N), so positions are unprojected to longitude and
//!   latitude (spherical Mercator, exact) and then read as above;
//! * **any other coordinates**: metres of a projected CRS (UTM, national
//!   grids) or of a local frame, used as they are.
//!
//! Local origin: geographic footprints are built about their centre (the
//! tangent point); metric ones farther than 10 km from the origin are
//! moved so that the centre of their bounding box, rounded to whole
//! metres, is the origin — at 6·10⁶ m an f32 scene would round every
//! vertex to 0.5 m. [`Footprints::origin`] says where the origin lies, in
//! the file's terms. OBJ files are re-centred by the same rule.
//!
//! A feature genform cannot use (a position that is no pair of numbers, a
//! ring of under three corners) is skipped with a warning naming it
//! ([`Footprints::skipped`]); a file that is not GeoJSON is an error.

use anyhow::{Context, Result, bail};
pub use genform_shape::{FootprintLot, FootprintSet as Footprints, LotProps};
use serde_json::Value;
use std::path::Path;

/// Most footprints one file may give (each is a whole derivation).
pub const MAX_FOOTPRINTS: usize = 100_000;

/// Metric footprints farther than this from the origin (metres) are
/// re-centred on their bounding box.
const FAR: f64 = 10_000.0;

/// Mean radius of EPSG:3857's sphere (metres).
const WEB_MERCATOR_R: f64 = 6_378_137.0;

/// The lots of the footprint file at `path` (OBJ when its extension says
/// so, else GeoJSON), centred on a local origin, with what was skipped.
pub fn read_lots(path: &Path) -> Result<Footprints> {
    if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("obj")) { read_obj(path) } else { read_geojson(path) }
}

/// [`read_lots`] as bare corner lists, the skipped lots warned about.
pub fn read_footprints(path: &Path) -> Result<Vec<Vec<[f64; 2]>>> {
    let set = read_lots(path)?;
    for why in &set.skipped {
        crate::notes::warn(&format!("warning: {}: {why}; skipped", path.display()));
    }
    Ok(set.lots.into_iter().map(|l| l.corners).collect())
}

/// The up-facing faces of the OBJ file at `path` as lots, re-centred when
/// they lie far from the origin.
pub fn read_obj(path: &Path) -> Result<Footprints> {
    let faces = read_obj_faces(path)?;
    let mut lots: Vec<FootprintLot> = faces
        .into_iter()
        .enumerate()
        .map(|(k, corners)| FootprintLot {
            corners,
            label: format!("face {}", k + 1),
            props: LotProps { index: k as f64, ..LotProps::default() },
        })
        .collect();
    let origin = recentre(&mut lots).map(|[x, z]| format!("({x}, 0, {z}) of the OBJ file"));
    Ok(Footprints { lots, origin, skipped: Vec::new() })
}

/// Moves metric lots lying farther than [`FAR`] from the origin so that the
/// centre of their bounding box, rounded to whole metres, is the origin;
/// that centre in world `(x, z)`, if moved.
fn recentre(lots: &mut [FootprintLot]) -> Option<[f64; 2]> {
    let (lo, hi) = bounds(lots.iter().flat_map(|l| l.corners.iter().copied()))?;
    if lo.iter().chain(&hi).all(|v| v.abs() <= FAR) {
        return None;
    }
    let o = [((lo[0] + hi[0]) / 2.0).round(), ((lo[1] + hi[1]) / 2.0).round()];
    for p in lots.iter_mut().flat_map(|l| l.corners.iter_mut()) {
        *p = [p[0] - o[0], p[1] - o[1]];
    }
    Some(o)
}

/// The bounding box of `points`; `None` when there are none.
fn bounds(points: impl Iterator<Item = [f64; 2]>) -> Option<([f64; 2], [f64; 2])> {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in points {
        for i in 0..2 {
            lo[i] = lo[i].min(p[i]);
            hi[i] = hi[i].max(p[i]);
        }
    }
    lo[0].is_finite().then_some((lo, hi))
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

/// A lot as the file gives it: `[x, y]` positions (y north).
struct RawLot {
    xy: Vec<[f64; 2]>,
    label: String,
    props: LotProps,
}

/// How a GeoJSON file's positions are to be read.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Frame {
    /// WGS 84 longitude and latitude, degrees.
    LonLat,
    /// EPSG:3857 pseudo-metres.
    WebMercator,
    /// Metres of a projected CRS or a local frame.
    Metres,
}

/// The lots of the GeoJSON file at `path` in local metres.
pub fn read_geojson(path: &Path) -> Result<Footprints> {
    let text = crate::text::read_text(path, "footprints")?;
    let value: Value = serde_json::from_str(&text).with_context(|| format!("{} is not JSON", path.display()))?;
    let mut raw = Vec::new();
    let mut skipped = Vec::new();
    collect(&value, None, &mut raw, &mut skipped)
        .with_context(|| format!("{} is not GeoJSON genform can read", path.display()))?;
    if raw.len() > MAX_FOOTPRINTS {
        bail!("{} holds {} footprints; at most {MAX_FOOTPRINTS} are derived in one run", path.display(), raw.len());
    }
    if raw.is_empty() && !skipped.is_empty() {
        let n = skipped.len();
        let shown: Vec<&str> = skipped.iter().take(3).map(String::as_str).collect();
        bail!(
            "{} holds no usable footprint: {}{}",
            path.display(),
            shown.join("; "),
            if n > 3 { format!(" (and {} more)", n - 3) } else { String::new() }
        );
    }
    let crs = crs_name(&value);
    let frame = frame_of(crs.as_deref(), &raw);
    let (lots, origin) = match frame {
        Frame::Metres => {
            let mut lots: Vec<FootprintLot> = raw
                .into_iter()
                .map(|r| FootprintLot {
                    corners: r.xy.iter().map(|&[x, y]| [x, -y]).collect(),
                    label: r.label,
                    props: r.props,
                })
                .collect();
            let of = crs.as_deref().map_or(String::new(), |c| format!(" of {c}"));
            let origin = recentre(&mut lots).map(|[x, z]| format!("({x}, {}){of}", -z));
            (lots, origin)
        }
        Frame::LonLat | Frame::WebMercator => {
            let mut raw = raw;
            if frame == Frame::WebMercator {
                for p in raw.iter_mut().flat_map(|r| r.xy.iter_mut()) {
                    *p = web_mercator_to_lonlat(*p);
                }
            }
            let (lots, origin, out) = project_lonlat(raw)?;
            skipped.extend(out);
            let from = if frame == Frame::WebMercator { " (read from EPSG:3857)" } else { "" };
            (lots, Some(format!("{origin}{from}")))
        }
    };
    if lots.is_empty() && !skipped.is_empty() {
        bail!("{} holds no usable footprint: {}", path.display(), skipped[0]);
    }
    Ok(Footprints { lots, origin, skipped })
}

/// The name the legacy `crs` member gives, if any.
fn crs_name(v: &Value) -> Option<String> {
    let c = v.get("crs")?;
    let name = c.get("properties").and_then(|p| p.get("name")).and_then(Value::as_str)?;
    Some(name.to_string())
}

/// The EPSG code in a CRS name: `EPSG:3857`, `urn:ogc:def:crs:EPSG::3857`.
fn epsg_code(name: &str) -> Option<u32> {
    let upper = name.to_ascii_uppercase();
    if !upper.contains("EPSG") {
        return None;
    }
    upper.rsplit(':').next()?.trim().parse().ok()
}

fn frame_of(crs: Option<&str>, raw: &[RawLot]) -> Frame {
    match crs {
        Some(name) => {
            let upper = name.to_ascii_uppercase();
            match epsg_code(name) {
                Some(3857 | 900913 | 3785 | 102100 | 102113) => Frame::WebMercator,
                Some(4326 | 4258 | 4269 | 4979) => Frame::LonLat,
                _ if upper.ends_with("CRS84") || upper.ends_with("CRS:84") => Frame::LonLat,
                _ => Frame::Metres,
            }
        }
        None => {
            let in_range = raw.iter().flat_map(|r| &r.xy).all(|[x, y]| x.abs() <= 180.0 && y.abs() <= 90.0);
            let small = raw.iter().all(|r| extent(&r.xy) < 0.05);
            if !raw.is_empty() && in_range && small { Frame::LonLat } else { Frame::Metres }
        }
    }
}

/// EPSG:3857 `[x, y]` to `[longitude, latitude]` in degrees (the inverse
/// spherical Mercator, exact).
fn web_mercator_to_lonlat([x, y]: [f64; 2]) -> [f64; 2] {
    let lon = (x / WEB_MERCATOR_R).to_degrees();
    let lat = (2.0 * (y / WEB_MERCATOR_R).exp().atan() - std::f64::consts::FRAC_PI_2).to_degrees();
    [lon, lat]
}

/// Projects longitude/latitude lots onto a transverse Mercator tangent to
/// their bounding box's centre: the lots in world `(x, z)` metres, the
/// centre in words, and the lots skipped (positions off the globe).
fn project_lonlat(raw: Vec<RawLot>) -> Result<(Vec<FootprintLot>, String, Vec<String>)> {
    let mut skipped = Vec::new();
    let (raw, off): (Vec<RawLot>, Vec<RawLot>) =
        raw.into_iter().partition(|r| r.xy.iter().all(|[x, y]| x.abs() <= 180.0 && y.abs() <= 90.0));
    for r in off {
        skipped.push(format!("{} has a position outside longitude ±180° and latitude ±90°", r.label));
    }
    let Some((lo, hi)) = bounds(raw.iter().flat_map(|r| r.xy.iter().copied())) else {
        return Ok((Vec::new(), String::new(), skipped));
    };
    let (lon0, lat0) = ((lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0);
    let geo = proj4rs::Proj::from_proj_string("+proj=longlat +datum=WGS84 +no_defs")
        .map_err(|e| anyhow::anyhow!("cannot set up WGS 84: {e}"))?;
    let tm = proj4rs::Proj::from_proj_string(&format!(
        "+proj=tmerc +lat_0={lat0} +lon_0={lon0} +k=1 +x_0=0 +y_0=0 +datum=WGS84 +units=m +no_defs"
    ))
    .map_err(|e| anyhow::anyhow!("cannot set up a transverse Mercator about {lat0}, {lon0}: {e}"))?;
    let mut lots = Vec::with_capacity(raw.len());
    for r in raw {
        let mut pts: Vec<(f64, f64)> = r.xy.iter().map(|[lon, lat]| (lon.to_radians(), lat.to_radians())).collect();
        let mut ok = true;
        for p in &mut pts {
            ok &= proj4rs::transform::transform(&geo, &tm, p).is_ok() && p.0.is_finite() && p.1.is_finite();
        }
        if !ok {
            skipped.push(format!("{} cannot be projected", r.label));
            continue;
        }
        lots.push(FootprintLot {
            corners: pts.iter().map(|&(x, y)| [x, -y]).collect(),
            label: r.label,
            props: r.props,
        });
    }
    let ns = if lat0 < 0.0 { 'S' } else { 'N' };
    let ew = if lon0 < 0.0 { 'W' } else { 'E' };
    let origin = format!(
        "{:.7}°{ns} {:.7}°{ew} (WGS 84; lots in metres on a transverse Mercator about it)",
        lat0.abs(),
        lon0.abs()
    );
    Ok((lots, origin, skipped))
}

fn extent(lot: &[[f64; 2]]) -> f64 {
    bounds(lot.iter().copied()).map_or(0.0, |(lo, hi)| (hi[0] - lo[0]).max(hi[1] - lo[1]))
}

/// A feature's name in messages: its number (1-based) and its `id`, or
/// the `id`, `@id` or `name` of its properties.
fn feature_label(k: usize, f: &Value) -> String {
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

/// A number, or the number a string begins with (`"12"`, `"12.5 m"`,
/// `"40 ft"` and `"40'"` in feet are metres ×0.3048).
fn number(v: &Value) -> Option<f64> {
    match v {
        Value::Number(n) => n.as_f64(),
        Value::String(s) => {
            let s = s.trim();
            let end = s.find(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-' || c == '+')).unwrap_or(s.len());
            let x: f64 = s[..end].parse().ok()?;
            let unit = s[end..].trim();
            let feet = unit == "'" || unit.eq_ignore_ascii_case("ft") || unit.eq_ignore_ascii_case("feet");
            Some(if feet { x * 0.3048 } else { x })
        }
        _ => None,
    }
    .filter(|x| x.is_finite() && *x >= 0.0)
}

/// The use class of OSM's `building` value: 0 unknown or `yes`, 1
/// residential, 2 commercial, 3 industrial, 4 civic (schools, churches,
/// public buildings), 5 outbuilding (garages, sheds, roofs).
pub fn use_class(building: &str) -> f64 {
    match building {
        "house" | "detached" | "semidetached_house" | "terrace" | "apartments" | "residential" | "bungalow"
        | "dormitory" | "farm" | "cabin" | "static_caravan" | "houseboat" => 1.0,
        "commercial" | "retail" | "office" | "supermarket" | "kiosk" | "hotel" => 2.0,
        "industrial" | "warehouse" | "factory" | "manufacture" => 3.0,
        "civic" | "public" | "government" | "school" | "university" | "college" | "kindergarten" | "hospital"
        | "church" | "cathedral" | "chapel" | "mosque" | "synagogue" | "temple" | "religious" | "train_station"
        | "transportation" | "fire_station" | "sports_hall" | "stadium" => 4.0,
        "garage" | "garages" | "carport" | "shed" | "hut" | "roof" | "barn" | "farm_auxiliary" | "greenhouse"
        | "service" | "parking" | "cowshed" | "stable" => 5.0,
        _ => 0.0,
    }
}

/// What a feature's properties say of its lot (0 where they say nothing).
fn props_of(props: Option<&Value>, index: usize) -> LotProps {
    let get = |k: &str| props.and_then(|p| p.get(k)).and_then(number).unwrap_or(0.0);
    let levels = props.and_then(|p| p.get("building:levels").or_else(|| p.get("levels"))).and_then(number);
    LotProps {
        height: get("height"),
        min_height: get("min_height"),
        levels: levels.unwrap_or(0.0),
        use_class: props.and_then(|p| p.get("building")).and_then(Value::as_str).map_or(0.0, use_class),
        index: index as f64,
    }
}

/// The feature a geometry belongs to: its label and properties.
type Owner<'a> = Option<(&'a str, LotProps)>;

fn collect(v: &Value, owner: Owner, out: &mut Vec<RawLot>, skipped: &mut Vec<String>) -> Result<()> {
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
                    skipped.push(format!("{name} is not a Feature"));
                    continue;
                }
                collect(f, Some((&name, props_of(f.get("properties"), k))), out, skipped)?;
            }
        }
        // A feature without geometry (`null`) has no lot.
        "Feature" => {
            let name = feature_label(0, v);
            let owner = owner.or(Some((&name, props_of(v.get("properties"), 0))));
            match v.get("geometry") {
                Some(Value::Null) | None => {}
                Some(g) => collect(g, owner, out, skipped)?,
            }
        }
        "GeometryCollection" => {
            for g in
                v.get("geometries").and_then(Value::as_array).context("a GeometryCollection without \"geometries\"")?
            {
                collect(g, owner, out, skipped)?;
            }
        }
        "Polygon" => {
            let (name, props) = label(out.len());
            match v.get("coordinates").context("a Polygon without \"coordinates\"").and_then(outer_ring) {
                Ok(xy) => out.push(RawLot { xy, label: name, props }),
                Err(e) => skipped.push(format!("{name}: {e}")),
            }
        }
        "MultiPolygon" => {
            let (name, props) = label(out.len());
            let Some(polys) = v.get("coordinates").and_then(Value::as_array) else {
                skipped.push(format!("{name}: a MultiPolygon without coordinates"));
                return Ok(());
            };
            for (i, p) in polys.iter().enumerate() {
                let name = format!("{name}, polygon {}", i + 1);
                match outer_ring(p) {
                    Ok(xy) => out.push(RawLot { xy, label: name, props }),
                    Err(e) => skipped.push(format!("{name}: {e}")),
                }
            }
        }
        // Points and lines are not lots.
        "Point" | "MultiPoint" | "LineString" | "MultiLineString" => {}
        other => bail!("unknown GeoJSON type \"{other}\""),
    }
    Ok(())
}

/// The outer ring of a Polygon's coordinates as `[x, y]` positions,
/// without the closing repeat of the first position.
fn outer_ring(coords: &Value) -> Result<Vec<[f64; 2]>> {
    let ring = coords.get(0).and_then(Value::as_array).context("a Polygon without an outer ring")?;
    let mut pts = Vec::with_capacity(ring.len());
    for p in ring {
        let xy = p.as_array().filter(|a| a.len() >= 2).context("a position that is not [x, y]")?;
        let x = xy[0].as_f64().context("a coordinate that is not a number")?;
        let y = xy[1].as_f64().context("a coordinate that is not a number")?;
        pts.push([x, y]);
    }
    if pts.len() > 1 && pts.first() == pts.last() {
        pts.pop();
    }
    if pts.len() < 3 {
        bail!("an outer ring of {} corners (3 at least)", pts.len());
    }
    Ok(pts)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str) -> Result<Footprints> {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("lots.geojson");
        std::fs::write(&path, text).unwrap();
        read_geojson(&path)
    }

    fn corners(set: &Footprints) -> Vec<Vec<[f64; 2]>> {
        set.lots.iter().map(|l| l.corners.clone()).collect()
    }

    #[test]
    fn polygons_and_multipolygons_become_lots_north_to_minus_z() {
        let set = read(
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
        let lots = corners(&set);
        assert_eq!(lots.len(), 3);
        assert_eq!(lots[0], vec![[0.0, 0.0], [10.0, 0.0], [10.0, -8.0], [0.0, -8.0]], "closing corner dropped");
        assert_eq!(lots[1].len(), 3);
        assert_eq!(lots[2], vec![[30.0, 0.0], [34.0, 0.0], [34.0, -4.0]]);
        assert_eq!(set.lots[2].label, "feature 3, polygon 2");
        assert!(set.origin.is_none(), "local metres stay where they are");
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
        // Far from the origin: re-centred on whole metres.
        let far = "v 1603600.25 0 -6464370\nv 1603610.25 0 -6464370\nv 1603610.25 0 -6464380\nf 1 2 3\n";
        std::fs::write(&path, far).unwrap();
        let set = read_lots(&path).unwrap();
        assert_eq!(set.lots[0].corners, vec![[-4.75, 5.0], [5.25, 5.0], [5.25, -5.0]]);
        assert_eq!(set.origin.as_deref(), Some("(1603605, 0, -6464375) of the OBJ file"));
    }

    #[test]
    fn bad_files_say_what_is_wrong() {
        let e = format!("{:#}", read(r#"{"type": "Polygon"}"#).unwrap_err());
        assert!(e.contains("without \"coordinates\""), "{e}");
        let e = format!("{:#}", read(r#"{"type": "Circle"}"#).unwrap_err());
        assert!(e.contains("unknown GeoJSON type \"Circle\""), "{e}");
        let e = format!("{:#}", read("[1, 2").unwrap_err());
        assert!(e.contains("is not JSON"), "{e}");
    }

    /// The length in metres of a 0.001° step east and north at `lat`
    /// (WGS 84 ellipsoid: meridian and parallel radii of curvature).
    fn degree_steps(lat: f64) -> (f64, f64) {
        let (a, e2) = (6_378_137.0f64, 0.006_694_379_990_14f64);
        let s = lat.to_radians().sin();
        let w = (1.0 - e2 * s * s).sqrt();
        let east = a / w * lat.to_radians().cos();
        let north = a * (1.0 - e2) / (w * w * w);
        (east * 0.001f64.to_radians(), north * 0.001f64.to_radians())
    }

    #[test]
    fn longitude_latitude_is_projected_to_metres_about_the_centre() {
        let lonlat = r#"{"type": "Feature", "id": "way/1", "properties": {"height": "12.5 m", "building:levels": "4",
            "building": "apartments"}, "geometry": {"type": "Polygon",
            "coordinates": [[[13.400, 52.520], [13.401, 52.520], [13.401, 52.521], [13.400, 52.521], [13.400, 52.520]]]}}"#;
        let set = read(lonlat).unwrap();
        let c = &set.lots[0].corners;
        let (east, north) = degree_steps(52.5205);
        let w = c[1][0] - c[0][0];
        let d = c[0][1] - c[3][1];
        assert!((w - east).abs() < 0.01, "{w} vs {east}");
        assert!((d - north).abs() < 0.01, "{d} vs {north}");
        let cx: f64 = c.iter().map(|p| p[0]).sum::<f64>() / 4.0;
        let cz: f64 = c.iter().map(|p| p[1]).sum::<f64>() / 4.0;
        assert!(cx.abs() < 0.01 && cz.abs() < 0.01, "centred: {cx} {cz}");
        assert!(set.origin.as_deref().unwrap().starts_with("52.5205000°N 13.4005000°E"), "{:?}", set.origin);
        let p = set.lots[0].props;
        assert_eq!((p.height, p.levels, p.use_class), (12.5, 4.0, 1.0));
        assert_eq!(set.lots[0].label, "feature 1 (\"way/1\")");
    }

    #[test]
    fn web_mercator_is_not_metres() {
        // The same square in EPSG:3857: 1.64 times too large at 52.5° N.
        let r = WEB_MERCATOR_R;
        let merc = |lon: f64, lat: f64| {
            let y = r * (std::f64::consts::FRAC_PI_4 + lat.to_radians() / 2.0).tan().ln();
            format!("[{}, {}]", r * lon.to_radians(), y)
        };
        let ring = [(13.400, 52.520), (13.401, 52.520), (13.401, 52.521), (13.400, 52.521)]
            .map(|(a, b)| merc(a, b))
            .join(", ");
        let text = format!(
            r#"{{"type": "FeatureCollection", "crs": {{"type": "name", "properties": {{"name": "urn:ogc:def:crs:EPSG::3857"}}}},
            "features": [{{"type": "Feature", "properties": {{}}, "geometry": {{"type": "Polygon", "coordinates": [[{ring}]]}}}}]}}"#
        );
        let set = read(&text).unwrap();
        let c = &set.lots[0].corners;
        let (east, north) = degree_steps(52.5205);
        assert!((c[1][0] - c[0][0] - east).abs() < 0.01, "{:?}", c);
        assert!((c[0][1] - c[3][1] - north).abs() < 0.01, "{:?}", c);
        assert!(set.origin.as_deref().unwrap().contains("EPSG:3857"), "{:?}", set.origin);
    }

    #[test]
    fn far_metres_are_recentred_and_bad_lots_skipped() {
        let set = read(
            r#"{"type": "FeatureCollection", "crs": {"type": "name", "properties": {"name": "EPSG:32633"}},
            "features": [
              {"type": "Feature", "properties": {"name": "a"}, "geometry": {"type": "Polygon",
               "coordinates": [[[457500.4, 5550000], [457510.4, 5550000], [457510.4, 5550010], [457500.4, 5550010]]]}},
              {"type": "Feature", "properties": {"name": "b"}, "geometry": {"type": "Polygon",
               "coordinates": [[[457500, 5550000], [457510, "x"], [457510, 5550010]]]}},
              {"type": "Feature", "id": 7, "geometry": {"type": "Polygon", "coordinates": [[[457500, 5550000], [457510, 5550000]]]}}
            ]}"#,
        )
        .unwrap();
        assert_eq!(set.lots.len(), 1);
        let [x, z] = set.lots[0].corners[0];
        assert!((x + 4.6).abs() < 1e-6 && z == 5.0, "whole-metre origin: {x} {z}");
        assert_eq!(set.origin.as_deref(), Some("(457505, 5550005) of EPSG:32633"));
        assert_eq!(set.skipped.len(), 2, "{:?}", set.skipped);
        assert!(
            set.skipped[0].starts_with("feature 2 (\"b\"): a coordinate that is not a number"),
            "{:?}",
            set.skipped
        );
        assert!(set.skipped[1].starts_with("feature 3 (id 7): an outer ring of 2 corners"), "{:?}", set.skipped);
    }

    #[test]
    fn osm_values_are_read_as_numbers() {
        assert_eq!(number(&serde_json::json!("40 ft")), Some(40.0 * 0.3048));
        assert_eq!(number(&serde_json::json!("7")), Some(7.0));
        assert_eq!(number(&serde_json::json!(3.5)), Some(3.5));
        assert_eq!(number(&serde_json::json!("tall")), None);
        assert_eq!(use_class("garage"), 5.0);
        assert_eq!(use_class("yes"), 0.0);
    }
}
