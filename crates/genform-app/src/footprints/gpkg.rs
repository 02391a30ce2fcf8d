//! GeoPackage footprints (OGC 12-128: an SQLite file): one feature layer's
//! polygons as lots, its columns their properties, its CRS read from
//! `gpkg_spatial_ref_sys` and handed to the projection the GeoJSON reader
//! uses (see the parent module's documentation). The SQLite file is
//! opened by `rusqlite` (SQLite bundled); the geometry blobs are a small
//! GeoPackage header (read here) over standard WKB (read by georust's
//! `wkb`: ISO and extended WKB, Z and M).

use super::frames::*;
use anyhow::{Context, Result, bail};
use genform_shape::FootprintSet as Footprints;
use serde_json::Value;
use std::path::Path;

/// SQLite's file header, the first 16 bytes of every database file.
const SQLITE_MAGIC: &[u8; 16] = b"SQLite format 3\0";

/// A feature layer of a GeoPackage: its table, geometry column, geometry
/// type (`POLYGON`, `MULTIPOLYGON`, `GEOMETRY`, `POINT`, …) and `srs_id`.
#[derive(Clone, Debug)]
struct Layer {
    table: String,
    column: String,
    kind: String,
    srs_id: i64,
}

impl Layer {
    /// A layer of polygons by its declared type: the layers chosen when
    /// the path names none.
    fn is_polygon(&self) -> bool {
        matches!(self.kind.to_ascii_uppercase().as_str(), "POLYGON" | "MULTIPOLYGON")
    }

    /// A layer that may hold street lines (`LINESTRING`,
    /// `MULTILINESTRING`, or any geometry).
    fn may_hold_lines(&self) -> bool {
        matches!(
            self.kind.to_ascii_uppercase().as_str(),
            "LINESTRING" | "MULTILINESTRING" | "GEOMETRY" | "GEOMETRYCOLLECTION"
        )
    }

    /// A layer that may hold polygons (`GEOMETRY`, a collection, a
    /// surface): read when the path names it; points and lines never.
    fn may_hold_polygons(&self) -> bool {
        !matches!(
            self.kind.to_ascii_uppercase().as_str(),
            "POINT"
                | "MULTIPOINT"
                | "LINESTRING"
                | "MULTILINESTRING"
                | "CIRCULARSTRING"
                | "COMPOUNDCURVE"
                | "CURVE"
                | "MULTICURVE"
        )
    }
}

/// The lots of layer `layer` of the GeoPackage at `path` (its only
/// polygon layer when `None`) in local metres, each feature's columns its
/// properties.
pub fn read_gpkg(path: &Path, layer: Option<&str>) -> Result<Footprints> {
    use rusqlite::{Connection, OpenFlags};
    crate::gate::admit_read(path, "footprints")?;
    let shown = path.display();
    // SQLite opens any file and fails at the first query; say plainly what
    // a file that is no database is.
    let mut head = Vec::with_capacity(16);
    std::io::Read::read_to_end(
        &mut std::io::Read::take(
            std::fs::File::open(path).with_context(|| format!("cannot read footprints {shown}"))?,
            16,
        ),
        &mut head,
    )
    .with_context(|| format!("cannot read footprints {shown}"))?;
    if head != SQLITE_MAGIC {
        bail!("{shown} is not a GeoPackage: a GeoPackage is an SQLite database, and this file is none");
    }
    let db = Connection::open_with_flags(path, OpenFlags::SQLITE_OPEN_READ_ONLY | OpenFlags::SQLITE_OPEN_NO_MUTEX)
        .with_context(|| format!("cannot open {shown} as an SQLite database"))?;
    let read = |e: rusqlite::Error| anyhow::anyhow!("cannot read the GeoPackage {shown}: {e}");
    for table in ["gpkg_contents", "gpkg_geometry_columns", "gpkg_spatial_ref_sys"] {
        let n: i64 = db
            .query_row(
                "SELECT count(*) FROM sqlite_master WHERE type IN ('table', 'view') AND name = ?1",
                [table],
                |r| r.get(0),
            )
            .map_err(read)?;
        if n == 0 {
            bail!("{shown} is an SQLite database but not a GeoPackage: it has no `{table}` table");
        }
    }
    let layers = feature_layers(&db).map_err(read)?;
    // `#plots,streets`: the lots' layer, then layers of street lines.
    let mut names = layer.map(|l| l.split(',').map(str::trim));
    let lot_layer = names.as_mut().and_then(|n| n.next()).filter(|n| !n.is_empty());
    let street_layers: Vec<&str> = names.map(|n| n.collect()).unwrap_or_default();
    let chosen = choose_layer(&layers, lot_layer, path)?;
    let (frame, crs) = gpkg_frame(&db, chosen.srs_id)
        .with_context(|| format!("layer `{}` of {shown} has an unsupported CRS", chosen.table))?;
    let (raw, skipped) = gpkg_rows(&db, chosen).map_err(read)?;
    let mut streets = Vec::new();
    for name in street_layers {
        let Some(l) = layers.iter().find(|l| l.table == name) else {
            bail!("{shown} has no feature layer `{name}` for the streets");
        };
        if !l.may_hold_lines() {
            bail!("layer `{name}` of {shown} holds {} geometries, not street lines", l.kind);
        }
        if l.srs_id != chosen.srs_id {
            bail!("layer `{name}` of {shown} (srs_id {}) is not in the lots' CRS (srs_id {})", l.srs_id, chosen.srs_id);
        }
        streets.extend(gpkg_lines(&db, l).map_err(read)?);
    }
    let at = format!("{shown}#{}", chosen.table);
    if raw.len() > MAX_FOOTPRINTS {
        bail!("{at} holds more than {MAX_FOOTPRINTS} footprints; at most that many are derived in one run");
    }
    if raw.is_empty() && !skipped.is_empty() {
        return Err(no_usable(Path::new(&at), &skipped));
    }
    let frame = frame.unwrap_or_else(|| frame_of(None, &raw));
    let mut set = finish(Path::new(&at), raw, skipped, &streets, frame, crs.as_deref())?;
    // A geographic CRS other than WGS 84's is read as if it were: the
    // origin says which it was (the shapes agree to parts per million).
    if let (Frame::LonLat, Some(c)) = (frame, &crs)
        && c != "EPSG:4326"
    {
        set.origin = set.origin.map(|o| format!("{o} (read from {c})"));
    }
    Ok(set)
}

/// Quotes an SQLite identifier.
fn quoted(name: &str) -> String {
    format!("\"{}\"", name.replace('"', "\"\""))
}

/// The feature layers of a GeoPackage, in the order of `gpkg_contents`.
fn feature_layers(db: &rusqlite::Connection) -> rusqlite::Result<Vec<Layer>> {
    let mut q = db.prepare(
        "SELECT c.table_name, g.column_name, g.geometry_type_name, g.srs_id FROM gpkg_contents c \
         JOIN gpkg_geometry_columns g ON g.table_name = c.table_name \
         WHERE lower(c.data_type) = 'features' ORDER BY c.rowid",
    )?;
    q.query_map([], |r| Ok(Layer { table: r.get(0)?, column: r.get(1)?, kind: r.get(2)?, srs_id: r.get(3)? }))?
        .collect()
}

/// The layer a footprint path asks for: the one it names (exactly, or
/// else in any case when only one matches), else the only polygon layer.
fn choose_layer<'a>(layers: &'a [Layer], want: Option<&str>, path: &Path) -> Result<&'a Layer> {
    let shown = path.display();
    let polygons: Vec<&Layer> = layers.iter().filter(|l| l.is_polygon()).collect();
    let list = |ls: &[&Layer]| ls.iter().map(|l| format!("`{}`", l.table)).collect::<Vec<_>>().join(", ");
    let offer = if polygons.is_empty() {
        "it has no polygon layer".to_string()
    } else {
        format!("its polygon layers are {}", list(&polygons))
    };
    match want {
        Some(name) => {
            let exact = layers.iter().find(|l| l.table == name);
            let loose: Vec<&Layer> = layers.iter().filter(|l| l.table.eq_ignore_ascii_case(name)).collect();
            match exact.or(if loose.len() == 1 { Some(loose[0]) } else { None }) {
                Some(l) if l.may_hold_polygons() => Ok(l),
                Some(l) => bail!("layer `{}` of {shown} holds {} geometries, not polygons; {offer}", l.table, l.kind),
                None => bail!("{shown} has no feature layer `{name}`; {offer}"),
            }
        }
        None => {
            let candidates: Vec<&Layer> =
                if polygons.is_empty() { layers.iter().filter(|l| l.may_hold_polygons()).collect() } else { polygons };
            match candidates[..] {
                [one] => Ok(one),
                [] => bail!(
                    "{shown} holds no polygon layer{}",
                    if layers.is_empty() {
                        " (no feature layer at all)".to_string()
                    } else {
                        format!(" (its feature layers: {})", list(&layers.iter().collect::<Vec<_>>()))
                    }
                ),
                [first, ..] => bail!(
                    "{shown} holds {} polygon layers ({}): name one after a `#`, e.g. `{shown}#{}`",
                    candidates.len(),
                    list(&candidates),
                    first.table
                ),
            }
        }
    }
}

/// How the positions of `srs_id` are read and the CRS's name (`EPSG:3857`):
/// `None` for the undefined geographic CRS (srs_id 0), whose positions
/// are guessed as GeoJSON's without `crs` are.
fn gpkg_frame(db: &rusqlite::Connection, srs_id: i64) -> Result<(Option<Frame>, Option<String>)> {
    use rusqlite::OptionalExtension as _;
    match srs_id {
        -1 => return Ok((Some(Frame::Metres), None)),
        0 => return Ok((None, None)),
        _ => {}
    }
    let row: Option<(String, String, i64, String)> = db
        .query_row(
            "SELECT srs_name, organization, organization_coordsys_id, definition FROM gpkg_spatial_ref_sys \
             WHERE srs_id = ?1",
            [srs_id],
            |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?, r.get(3)?)),
        )
        .optional()?;
    let Some((srs_name, org, org_id, definition)) = row else {
        bail!("srs_id {srs_id} is not in gpkg_spatial_ref_sys");
    };
    let code = if org.eq_ignore_ascii_case("EPSG") { u32::try_from(org_id).ok() } else { wkt_epsg(&definition) };
    let name = code.map_or_else(|| format!("{srs_name} ({org} {org_id})"), |c| format!("EPSG:{c}"));
    if let Some(frame) = code.and_then(frame_of_epsg) {
        return Ok((Some(frame), Some(name)));
    }
    let frame = match wkt_kind(&definition) {
        WktKind::Projected
            if definition.to_ascii_lowercase().contains("foot") || definition.to_ascii_lowercase().contains("feet") =>
        {
            bail!("{name} (\"{srs_name}\") measures in feet; genform reads metres")
        }
        WktKind::Projected | WktKind::Local => Frame::Metres,
        WktKind::Geographic => Frame::LonLat,
        WktKind::Other => bail!(
            "{name} (\"{srs_name}\") is neither geographic (longitude, latitude) nor projected in metres by its \
             definition `{}`",
            definition.chars().take(60).collect::<String>()
        ),
    };
    Ok((Some(frame), Some(name)))
}

/// What kind of CRS a WKT (1 or 2) definition describes.
#[derive(Clone, Copy, Debug, PartialEq)]
enum WktKind {
    /// Projected (easting, northing).
    Projected,
    /// Geographic in degrees (longitude, latitude).
    Geographic,
    /// A local or engineering frame.
    Local,
    /// Geocentric, vertical, undefined or unreadable.
    Other,
}

fn wkt_kind(definition: &str) -> WktKind {
    let d = definition.trim_start().to_ascii_uppercase();
    let starts = |keys: &[&str]| keys.iter().any(|k| d.starts_with(k));
    let has = |keys: &[&str]| keys.iter().any(|k| d.contains(k));
    let projected = ["PROJCS[", "PROJCRS[", "PROJECTEDCRS["];
    let geographic = ["GEOGCS[", "GEOGCRS[", "GEOGRAPHICCRS["];
    if starts(&projected) || (starts(&["COMPD_CS[", "COMPOUNDCRS["]) && has(&projected)) {
        WktKind::Projected
    } else if (starts(&geographic) || (starts(&["COMPD_CS[", "COMPOUNDCRS["]) && has(&geographic)))
        || (starts(&["GEODCRS[", "GEODETICCRS["]) && d.contains("ELLIPSOIDAL"))
    {
        if d.contains("DEGREE") { WktKind::Geographic } else { WktKind::Other }
    } else if starts(&["LOCAL_CS[", "ENGCRS[", "ENGINEERINGCRS["]) {
        WktKind::Local
    } else {
        WktKind::Other
    }
}

/// The EPSG code a WKT definition gives itself: its last `AUTHORITY`
/// (WKT 1) or `ID` (WKT 2), which belongs to the CRS as a whole.
fn wkt_epsg(definition: &str) -> Option<u32> {
    let d = definition.to_ascii_uppercase();
    let wkt1 = d.rfind("AUTHORITY[\"EPSG\",").map(|i| i + "AUTHORITY[\"EPSG\",".len());
    let wkt2 = d.rfind("ID[\"EPSG\",").map(|i| i + "ID[\"EPSG\",".len());
    let rest = d[wkt1.max(wkt2)?..].trim_start().trim_start_matches('"');
    rest[..rest.find(|c: char| !c.is_ascii_digit()).unwrap_or(rest.len())].parse().ok()
}

/// The lots of `layer`'s rows (by `fid`) and the features skipped.
fn gpkg_rows(db: &rusqlite::Connection, layer: &Layer) -> rusqlite::Result<(Vec<RawLot>, Vec<String>)> {
    use rusqlite::types::ValueRef;
    // The columns: the integer primary key is the fid, the others (but the
    // geometry) the properties.
    let mut fid = None;
    let mut props = Vec::new();
    {
        let mut q =
            db.prepare(&format!("SELECT name, type, pk FROM pragma_table_info({})", quoted_text(&layer.table)))?;
        let mut rows = q.query([])?;
        while let Some(r) = rows.next()? {
            let (name, kind, pk): (String, String, i64) = (r.get(0)?, r.get(1)?, r.get(2)?);
            if pk == 1 && kind.eq_ignore_ascii_case("INTEGER") {
                fid = Some(name);
            } else if name != layer.column {
                props.push(name);
            }
        }
    }
    let mut columns = vec![fid.as_deref().map_or_else(|| "NULL".to_string(), quoted), quoted(&layer.column)];
    columns.extend(props.iter().map(|p| quoted(p)));
    let order = if fid.is_some() { " ORDER BY 1" } else { "" };
    let sql = format!("SELECT {} FROM {}{order}", columns.join(", "), quoted(&layer.table));
    let mut q = db.prepare(&sql)?;
    let mut rows = q.query([])?;
    let (mut raw, mut skipped) = (Vec::new(), Vec::new());
    let mut k = 0usize;
    while let Some(r) = rows.next()? {
        let label = match r.get_ref(0)? {
            ValueRef::Integer(n) => format!("fid {n}"),
            _ => format!("feature {}", k + 1),
        };
        let mut map = serde_json::Map::new();
        for (i, name) in props.iter().enumerate() {
            let v = match r.get_ref(i + 2)? {
                ValueRef::Integer(n) => Value::from(n),
                ValueRef::Real(x) => serde_json::Number::from_f64(x).map_or(Value::Null, Value::Number),
                ValueRef::Text(t) => Value::String(String::from_utf8_lossy(t).into_owned()),
                ValueRef::Null | ValueRef::Blob(_) => continue,
            };
            map.insert(name.clone(), v);
        }
        let lot_props = props_of(Some(&Value::Object(map)), k);
        match r.get_ref(1)? {
            ValueRef::Blob(blob) => match gpkg_polygons(blob) {
                Ok(rings) => {
                    let many = rings.len() > 1;
                    for (i, ring) in rings.into_iter().enumerate() {
                        let name = if many { format!("{label}, polygon {}", i + 1) } else { label.clone() };
                        match ring {
                            Ok(xy) => raw.push(RawLot { xy, label: name, props: lot_props }),
                            Err(e) => skipped.push(format!("{name}: {e}")),
                        }
                    }
                }
                Err(e) => skipped.push(format!("{label}: {e}")),
            },
            ValueRef::Null => skipped.push(format!("{label} has no geometry (NULL)")),
            _ => skipped.push(format!("{label}: a geometry that is not a blob")),
        }
        k += 1;
        if raw.len() > MAX_FOOTPRINTS {
            break;
        }
    }
    Ok((raw, skipped))
}

/// The lines of a layer of streets (the parts of each LineString or
/// MultiLineString, other geometries and unreadable rows left out: a
/// street missing only leaves a lot without its street).
fn gpkg_lines(db: &rusqlite::Connection, layer: &Layer) -> rusqlite::Result<Vec<Vec<[f64; 2]>>> {
    let mut q = db.prepare(&format!("SELECT {} FROM {}", quoted(&layer.column), quoted(&layer.table)))?;
    let mut rows = q.query([])?;
    let mut out = Vec::new();
    while let Some(r) = rows.next()? {
        if let rusqlite::types::ValueRef::Blob(blob) = r.get_ref(0)?
            && let Some(wkb) = gpkg_wkb(blob).ok().and_then(|b| wkb::reader::read_wkb(b).ok())
        {
            wkb_lines(&wkb, &mut out);
        }
    }
    Ok(out)
}

/// The lines of `g` (LineStrings, the parts of MultiLineStrings and
/// collections), appended to `out`.
fn wkb_lines(g: &wkb::reader::Wkb<'_>, out: &mut Vec<Vec<[f64; 2]>>) {
    use geo_traits::{
        CoordTrait as _, GeometryCollectionTrait as _, GeometryTrait as _, GeometryType, LineStringTrait as _,
        MultiLineStringTrait as _,
    };
    let line = |l: &wkb::reader::LineString<'_>| -> Vec<[f64; 2]> {
        l.coords().map(|c| [c.x(), c.y()]).filter(|p| p.iter().all(|v| v.is_finite())).collect()
    };
    match g.as_type() {
        GeometryType::LineString(l) => out.push(line(l)),
        GeometryType::MultiLineString(m) => out.extend(m.line_strings().map(line)),
        GeometryType::GeometryCollection(c) => {
            for g in c.geometries() {
                wkb_lines(g, out);
            }
        }
        _ => {}
    }
}

/// An SQLite string literal.
fn quoted_text(text: &str) -> String {
    format!("'{}'", text.replace('\'', "''"))
}

/// The WKB of a GeoPackage geometry blob, after its header.
fn gpkg_wkb(blob: &[u8]) -> Result<&[u8], String> {
    // The header: "GP", version, flags, srs_id (4 bytes), then an envelope
    // of 0, 32, 48, 48 or 64 bytes (flags bits 1–3). Flags bit 4: empty;
    // bit 5: an extended geometry (not standard WKB); bit 0 orders only the
    // header's own numbers (the WKB carries its own byte order).
    if blob.len() < 8 || &blob[..2] != b"GP" {
        return Err("a geometry that is not GeoPackage binary (no `GP` header)".into());
    }
    let flags = blob[3];
    if flags & 0x20 != 0 {
        return Err("an extended GeoPackage geometry (not standard WKB)".into());
    }
    let envelope = match (flags >> 1) & 7 {
        0 => 0,
        1 => 32,
        2 | 3 => 48,
        4 => 64,
        code => return Err(format!("a geometry header with envelope code {code} (0–4)")),
    };
    if flags & 0x10 != 0 {
        return Err("an empty geometry".into());
    }
    blob.get(8 + envelope..).filter(|b| !b.is_empty()).ok_or_else(|| "a geometry cut short".to_string())
}

/// The outer rings of the polygons of a GeoPackage geometry blob (one per
/// polygon: a polygon's own error in its place), or why it has none.
fn gpkg_polygons(blob: &[u8]) -> Result<Vec<Result<Vec<[f64; 2]>>>, String> {
    let body = gpkg_wkb(blob)?;
    let wkb = wkb::reader::read_wkb(body).map_err(|e| format!("a geometry that is not WKB genform reads ({e})"))?;
    let mut out = Vec::new();
    wkb_polygons(&wkb, &mut out)?;
    if out.is_empty() {
        return Err("an empty geometry".into());
    }
    Ok(out)
}

/// The outer rings of `g`'s polygons, appended to `out`.
fn wkb_polygons(g: &wkb::reader::Wkb<'_>, out: &mut Vec<Result<Vec<[f64; 2]>>>) -> Result<(), String> {
    use geo_traits::{GeometryCollectionTrait as _, GeometryTrait as _, GeometryType, MultiPolygonTrait as _};
    match g.as_type() {
        GeometryType::Polygon(p) => out.push(wkb_ring(p)),
        GeometryType::MultiPolygon(m) => out.extend(m.polygons().map(|p| wkb_ring(p))),
        GeometryType::GeometryCollection(c) => {
            for g in c.geometries() {
                wkb_polygons(g, out)?;
            }
        }
        _ => return Err(format!("a {:?}, not a polygon", g.geometry_type())),
    }
    Ok(())
}

/// The outer ring of a WKB polygon as `[x, y]` positions.
fn wkb_ring(p: &wkb::reader::Polygon<'_>) -> Result<Vec<[f64; 2]>> {
    use geo_traits::{CoordTrait as _, LineStringTrait as _, PolygonTrait as _};
    let ring = p.exterior().context("an empty polygon")?;
    let pts: Vec<[f64; 2]> = ring.coords().map(|c| [c.x(), c.y()]).collect();
    if !pts.iter().flatten().all(|v| v.is_finite()) {
        bail!("a corner that is not a number");
    }
    ring_of(pts)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::footprints::{read_lots, split_layer, tests::degree_steps};
    use std::path::PathBuf;

    /// The real GeoPackage (momepy's `bubenec.gpkg`, see the README beside it).
    fn bubenec(name: &str) -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/bubenec").join(name)
    }

    /// Twice the signed area of a polygon (shoelace).
    fn area2(pts: &[[f64; 2]]) -> f64 {
        (0..pts.len())
            .map(|i| {
                let (a, b) = (pts[i], pts[(i + 1) % pts.len()]);
                a[0] * b[1] - b[0] * a[1]
            })
            .sum()
    }

    /// The outer rings of a GeoJSON FeatureCollection of Polygons, read
    /// here without genform's reader.
    fn geojson_rings(name: &str) -> Vec<Vec<[f64; 2]>> {
        let v: Value = serde_json::from_str(&std::fs::read_to_string(bubenec(name)).unwrap()).unwrap();
        v["features"]
            .as_array()
            .unwrap()
            .iter()
            .map(|f| {
                assert_eq!(f["geometry"]["type"], "Polygon");
                f["geometry"]["coordinates"][0]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|p| [p[0].as_f64().unwrap(), p[1].as_f64().unwrap()])
                    .collect()
            })
            .collect()
    }

    #[test]
    fn the_geopackage_plots_are_the_geojson_plots_at_the_same_areas() {
        let gpkg = read_lots(&bubenec("bubenec.gpkg#plots")).unwrap();
        assert_eq!(gpkg.lots.len(), 407, "{:?}", gpkg.skipped);
        assert!(gpkg.skipped.is_empty(), "{:?}", gpkg.skipped);
        assert!(gpkg.origin.as_deref().unwrap().ends_with("(read from EPSG:3857)"), "{:?}", gpkg.origin);
        assert_eq!(gpkg.lots[0].label, "fid 1");
        assert_eq!(gpkg.lots[406].props.index, 406.0);
        // Lot for lot, the GeoJSON reader's lots of the same file in
        // EPSG:3857 and in lon/lat agree with these to a centimetre.
        for name in ["plots_3857.geojson", "plots_lonlat.geojson"] {
            let json = read_lots(&bubenec(name)).unwrap();
            assert_eq!(json.lots.len(), 407);
            let worst = gpkg
                .lots
                .iter()
                .zip(&json.lots)
                .flat_map(|(a, b)| {
                    assert_eq!(a.corners.len(), b.corners.len(), "{}", a.label);
                    a.corners.iter().zip(&b.corners).map(|(p, q)| (p[0] - q[0]).hypot(p[1] - q[1]))
                })
                .fold(0.0, f64::max);
            // The lon/lat file's centre differs from the GeoPackage's by
            // its rounding (7 decimals), so its lots may sit a few mm apart.
            assert!(worst < 0.02, "{name}: a corner {worst} m from the GeoPackage's");
        }
        // Areas. The reference: each plot's area on the WGS 84 ellipsoid,
        // worked out here from the GeoPackage's own coordinates (spherical
        // Mercator undone, then a plane tangent to the ellipsoid at the
        // plot), without proj4rs.
        let db = rusqlite::Connection::open(bubenec("bubenec.gpkg")).unwrap();
        let mut q = db.prepare("SELECT geom FROM plots ORDER BY fid").unwrap();
        let truth: Vec<f64> = q
            .query_map([], |r| r.get::<_, Vec<u8>>(0))
            .unwrap()
            .map(|blob| ellipsoid_area(&mercator_ring(&blob.unwrap())))
            .collect();
        let (mut total, mut total_true, mut worst) = (0.0, 0.0, 0.0f64);
        for (lot, t) in gpkg.lots.iter().zip(&truth) {
            let a = area2(&lot.corners).abs() / 2.0;
            worst = worst.max((a - t).abs() / t);
            total += a;
            total_true += t;
        }
        let apart = (total / total_true - 1.0).abs();
        eprintln!(
            "areas: district {total:.2} m² vs {total_true:.2} m² on the ellipsoid, {apart:.1e} apart; worst plot {worst:.1e}"
        );
        assert!(worst < 1e-7, "a plot's area is {worst:e} of it from the ellipsoid's");
        assert!(apart < 1e-7, "the district's area: {total} m² vs {total_true} m²");
        // Against UTM 33N metres projected by PROJ (pyproj), read here:
        // UTM's scale at 14.40° E is k = 0.9996 (1 + (x/R)²/2), x the
        // distance to the zone's meridian, so a true area is a UTM area / k².
        // The file is rounded to centimetres: a plot's area may move by up
        // to half a centimetre times its perimeter.
        let utm = geojson_rings("plots_utm33n.geojson");
        assert_eq!(utm.len(), 407);
        let mut total_utm = 0.0;
        for (lot, ring) in gpkg.lots.iter().zip(&utm) {
            let easting = ring.iter().map(|p| p[0]).sum::<f64>() / ring.len() as f64;
            let x = (easting - 500_000.0) / 6_381_899.0;
            let k = 0.9996 * (1.0 + x * x / 2.0);
            let a_utm = area2(ring).abs() / 2.0 / (k * k);
            let a = area2(&lot.corners).abs() / 2.0;
            let perimeter: f64 = (0..ring.len())
                .map(|i| {
                    let (p, q) = (ring[i], ring[(i + 1) % ring.len()]);
                    (p[0] - q[0]).hypot(p[1] - q[1])
                })
                .sum();
            assert!((a - a_utm).abs() < 0.005 * perimeter, "{}: {a} m² vs {a_utm} m² (UTM)", lot.label);
            total_utm += a_utm;
        }
        let apart = (total / total_utm - 1.0).abs();
        eprintln!("areas: district {total:.2} m² vs {total_utm:.2} m² from UTM, {apart:.1e} apart");
        assert!(apart < 2e-5, "the district's area: {total} m² vs {total_utm} m² (UTM)");
    }

    /// The outer ring of a GeoPackage Polygon blob (little-endian WKB, as
    /// momepy's file has it) as longitude and latitude, undoing EPSG:3857.
    fn mercator_ring(blob: &[u8]) -> Vec<[f64; 2]> {
        let envelope = [0, 32, 48, 48, 64][usize::from((blob[3] >> 1) & 7)];
        let w = &blob[8 + envelope..];
        let u32_at = |i: usize| u32::from_le_bytes(w[i..i + 4].try_into().unwrap());
        let f64_at = |i: usize| f64::from_le_bytes(w[i..i + 8].try_into().unwrap());
        assert_eq!((w[0], u32_at(1)), (1, 3), "a little-endian Polygon");
        let r = 6_378_137.0f64;
        (0..u32_at(9) as usize)
            .map(|k| {
                let (x, y) = (f64_at(13 + 16 * k), f64_at(21 + 16 * k));
                [x / r, 2.0 * (y / r).exp().atan() - std::f64::consts::FRAC_PI_2]
            })
            .collect()
    }

    /// The area of a small ring of `[λ, φ]` (radians) on the WGS 84
    /// ellipsoid: its corners taken to Earth-centred x, y, z, then onto the
    /// plane tangent at their mean (east, north), where the shoelace
    /// measures it (the plane departs from the ellipsoid by (d/R)² ≈ 10⁻¹⁰
    /// over a plot d = 60 m across).
    fn ellipsoid_area(ring: &[[f64; 2]]) -> f64 {
        let (a, e2) = (6_378_137.0f64, 0.006_694_379_990_14f64);
        let ecef = |[l, p]: [f64; 2]| {
            let n = a / (1.0 - e2 * p.sin().powi(2)).sqrt();
            [n * p.cos() * l.cos(), n * p.cos() * l.sin(), n * (1.0 - e2) * p.sin()]
        };
        let k = ring.len() as f64;
        let (l0, p0) = (ring.iter().map(|p| p[0]).sum::<f64>() / k, ring.iter().map(|p| p[1]).sum::<f64>() / k);
        let o = ecef([l0, p0]);
        let east = [-l0.sin(), l0.cos(), 0.0];
        let north = [-p0.sin() * l0.cos(), -p0.sin() * l0.sin(), p0.cos()];
        let plane: Vec<[f64; 2]> = ring
            .iter()
            .map(|&p| {
                let v = ecef(p);
                let d = [v[0] - o[0], v[1] - o[1], v[2] - o[2]];
                let dot = |u: [f64; 3]| d[0] * u[0] + d[1] * u[1] + d[2] * u[2];
                [dot(east), dot(north)]
            })
            .collect();
        area2(&plane).abs() / 2.0
    }

    #[test]
    fn a_geopackage_of_several_layers_wants_one_named() {
        let whole = bubenec("bubenec.gpkg");
        let e = format!("{:#}", read_lots(&whole).unwrap_err());
        assert!(
            e.contains("holds 3 polygon layers (`tessellation`, `buildings`, `plots`): name one after a `#`, e.g. `")
                && e.contains("bubenec.gpkg#tessellation`"),
            "{e}"
        );
        let e = format!("{:#}", read_lots(&bubenec("bubenec.gpkg#roads")).unwrap_err());
        assert!(
            e.contains("has no feature layer `roads`; its polygon layers are `tessellation`, `buildings`, `plots`"),
            "{e}"
        );
        let e = format!("{:#}", read_lots(&bubenec("bubenec.gpkg#streets")).unwrap_err());
        assert!(e.contains("layer `streets` of") && e.contains("holds LINESTRING geometries, not polygons"), "{e}");
        let e = format!("{:#}", read_lots(&bubenec("bubenec.gpkg#dtm")).unwrap_err());
        assert!(e.contains("has no feature layer `dtm`"), "tiles are no feature layer: {e}");
        let set = read_lots(&bubenec("bubenec.gpkg#Buildings")).unwrap();
        assert_eq!(set.lots.len(), 144, "a layer's name in any case, when only one matches");
        assert_eq!(split_layer(Path::new("a/b.GPKG#x")), (PathBuf::from("a/b.GPKG"), Some("x".into())));
        assert_eq!(split_layer(Path::new("a/b.geojson#x")), (PathBuf::from("a/b.geojson#x"), None));
        assert_eq!(split_layer(Path::new("a/b.gpkg#")), (PathBuf::from("a/b.gpkg#"), None));
    }

    /// GeoPackage binary over little-endian WKB: `wkb` after a header
    /// with flags `flags` and `envelope` bytes of envelope.
    fn gp(flags: u8, envelope: usize, wkb: &[u8]) -> Vec<u8> {
        let mut b = vec![b'G', b'P', 0, flags];
        b.extend_from_slice(&4326i32.to_le_bytes());
        b.extend(std::iter::repeat_n(0u8, envelope));
        b.extend_from_slice(wkb);
        b
    }

    /// Little-endian WKB of a polygon of one ring, of type `code`, with
    /// `dims` numbers a position (the rest after x and y are 7).
    fn wkb_polygon(code: u32, dims: usize, ring: &[[f64; 2]]) -> Vec<u8> {
        let mut b = vec![1u8];
        b.extend_from_slice(&code.to_le_bytes());
        b.extend_from_slice(&1u32.to_le_bytes());
        b.extend_from_slice(&(ring.len() as u32).to_le_bytes());
        for p in ring {
            b.extend_from_slice(&p[0].to_le_bytes());
            b.extend_from_slice(&p[1].to_le_bytes());
            for _ in 2..dims {
                b.extend_from_slice(&7.0f64.to_le_bytes());
            }
        }
        b
    }

    /// A row of [`make_gpkg`]'s layer: geometry, `height`,
    /// `building:levels`, `building`.
    type Row<'a> = (Option<Vec<u8>>, Option<&'a str>, Option<i64>, Option<&'a str>);

    /// A GeoPackage at `path` with one layer `lots` of `kind` in `srs_id`
    /// (the spec's three CRS rows and `extra` as `(srs_id, org, code, wkt)`),
    /// its rows `(geometry, height, building:levels, building)`.
    fn make_gpkg(path: &Path, kind: &str, srs_id: i64, extra: &[(i64, &str, i64, &str)], rows: &[Row]) {
        let db = rusqlite::Connection::open(path).unwrap();
        db.execute_batch(
            "CREATE TABLE gpkg_spatial_ref_sys (srs_name TEXT, srs_id INTEGER PRIMARY KEY, organization TEXT,
               organization_coordsys_id INTEGER, definition TEXT, description TEXT);
             INSERT INTO gpkg_spatial_ref_sys VALUES ('Undefined cartesian SRS', -1, 'NONE', -1, 'undefined', NULL),
               ('Undefined geographic SRS', 0, 'NONE', 0, 'undefined', NULL),
               ('WGS 84 geodetic', 4326, 'EPSG', 4326, 'GEOGCS[\"WGS 84\",DATUM[\"WGS_1984\"],UNIT[\"degree\",0.0174532925199433]]', NULL);
             CREATE TABLE gpkg_contents (table_name TEXT PRIMARY KEY, data_type TEXT, identifier TEXT, srs_id INTEGER);
             CREATE TABLE gpkg_geometry_columns (table_name TEXT, column_name TEXT, geometry_type_name TEXT,
               srs_id INTEGER, z INTEGER, m INTEGER);
             CREATE TABLE lots (fid INTEGER PRIMARY KEY AUTOINCREMENT, geom BLOB, height TEXT,
               \"building:levels\" INTEGER, building TEXT, area REAL);",
        )
        .unwrap();
        for (id, org, code, wkt) in extra {
            db.execute(
                "INSERT INTO gpkg_spatial_ref_sys VALUES (?1, ?2, ?3, ?4, ?5, NULL)",
                rusqlite::params![format!("srs {id}"), id, org, code, wkt],
            )
            .unwrap();
        }
        db.execute("INSERT INTO gpkg_contents VALUES ('lots', 'features', 'lots', ?1)", [srs_id]).unwrap();
        db.execute(
            "INSERT INTO gpkg_geometry_columns VALUES ('lots', 'geom', ?1, ?2, 0, 0)",
            rusqlite::params![kind, srs_id],
        )
        .unwrap();
        for (g, h, l, b) in rows {
            db.execute(
                "INSERT INTO lots (geom, height, \"building:levels\", building, area) VALUES (?1, ?2, ?3, ?4, 1.5)",
                rusqlite::params![g, h, l, b],
            )
            .unwrap();
        }
    }

    const SQUARE: [[f64; 2]; 5] =
        [[13.400, 52.520], [13.401, 52.520], [13.401, 52.521], [13.400, 52.521], [13.400, 52.520]];

    #[test]
    fn a_geopackage_layer_in_degrees_gives_lots_with_properties_and_skips_bad_geometries() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("lots.gpkg");
        let shifted = |dx: f64| SQUARE.map(|[x, y]| [x + dx, y]);
        // A big-endian Polygon Z (ISO 1003) behind a 2D envelope, read as 2D.
        let mut big = vec![0u8];
        big.extend_from_slice(&1003u32.to_be_bytes());
        big.extend_from_slice(&1u32.to_be_bytes());
        big.extend_from_slice(&5u32.to_be_bytes());
        for p in shifted(0.002) {
            for v in [p[0], p[1], 3.0] {
                big.extend_from_slice(&v.to_be_bytes());
            }
        }
        let mut point = vec![1u8];
        point.extend_from_slice(&1u32.to_le_bytes());
        point.extend_from_slice(&13.4f64.to_le_bytes());
        point.extend_from_slice(&52.5f64.to_le_bytes());
        // An EWKB MultiPolygon with an M (flag 0x40000000) of two squares.
        let mut multi = vec![1u8];
        multi.extend_from_slice(&(6u32 | 0x4000_0000).to_le_bytes());
        multi.extend_from_slice(&2u32.to_le_bytes());
        multi.extend(wkb_polygon(3 | 0x4000_0000, 3, &shifted(0.004)));
        multi.extend(wkb_polygon(3 | 0x4000_0000, 3, &shifted(0.006)));
        make_gpkg(
            &path,
            "POLYGON",
            4326,
            &[],
            &[
                (Some(gp(0b0000_0011, 32, &wkb_polygon(3, 2, &SQUARE))), Some("12.5 m"), None, Some("apartments")),
                (Some(gp(0b0000_0010, 32, &big)), None, Some(4), Some("garage")),
                (None, Some("9"), None, None),
                (Some(gp(0b0001_0001, 0, &[])), None, None, None),
                (Some(gp(1, 0, &point)), None, None, None),
                (Some(gp(1, 0, &wkb_polygon(3, 2, &[SQUARE[0], SQUARE[1], SQUARE[0]]))), None, None, None),
                (Some(b"not a geometry".to_vec()), None, None, None),
                (Some(gp(1, 0, &[1, 3, 0, 0])), None, None, None),
                (Some(gp(1, 0, &multi)), None, None, None),
                (Some(gp(1, 0, &wkb_polygon(1003, 3, &shifted(0.008)))), None, None, None),
            ],
        );
        let set = read_lots(&path).unwrap();
        let labels: Vec<&str> = set.lots.iter().map(|l| l.label.as_str()).collect();
        assert_eq!(labels, ["fid 1", "fid 2", "fid 9, polygon 1", "fid 9, polygon 2", "fid 10"]);
        let (east, north) = degree_steps(52.5205);
        for lot in &set.lots {
            let c = &lot.corners;
            assert_eq!(c.len(), 4, "{}: closing corner dropped", lot.label);
            assert!((c[1][0] - c[0][0] - east).abs() < 0.01 && (c[0][1] - c[3][1] - north).abs() < 0.01, "{c:?}");
        }
        assert!(set.origin.as_deref().unwrap().starts_with("52.5205000°N 13.4045000°E"), "{:?}", set.origin);
        let p = set.lots[0].props;
        assert_eq!((p.height, p.levels, p.use_class, p.index), (12.5, 0.0, 1.0, 0.0));
        let p = set.lots[1].props;
        assert_eq!((p.height, p.levels, p.use_class, p.index), (0.0, 4.0, 5.0, 1.0));
        let skipped = set.skipped.join("\n");
        for why in [
            "fid 3 has no geometry (NULL)",
            "fid 4: an empty geometry",
            "fid 5: a Point, not a polygon",
            "fid 6: an outer ring of 2 corners (3 at least)",
            "fid 7: a geometry that is not GeoPackage binary",
            "fid 8: a geometry that is not WKB genform reads",
        ] {
            assert!(skipped.contains(why), "{why}:\n{skipped}");
        }
        assert_eq!(set.skipped.len(), 6, "{skipped}");
    }

    #[test]
    fn a_geopackage_crs_is_read_from_its_spatial_ref_sys() {
        let dir = tempfile::tempdir().unwrap();
        let utm = "PROJCS[\"WGS 84 / UTM zone 33N\",GEOGCS[\"WGS 84\",UNIT[\"degree\",0.01745]],UNIT[\"metre\",1],\
                   AUTHORITY[\"EPSG\",\"32633\"]]";
        let feet = "PROJCS[\"NAD83 / New York Long Island (ftUS)\",GEOGCS[\"NAD83\",UNIT[\"degree\",0.01745]],\
                    UNIT[\"US survey foot\",0.3048006096012192]]";
        let merc =
            "PROJCS[\"WGS 84 / Pseudo-Mercator\",GEOGCS[\"WGS 84\"],UNIT[\"metre\",1],AUTHORITY[\"EPSG\",\"3857\"]]";
        let ring = [[457500.4, 5550000.0], [457510.4, 5550000.0], [457510.4, 5550010.0], [457500.4, 5550010.0]];
        let row = |r: &[[f64; 2]]| (Some(gp(1, 0, &wkb_polygon(3, 2, r))), None, None, None);
        let path = dir.path().join("utm.gpkg");
        // Projected metres under another organisation's name, known by its WKT's AUTHORITY.
        make_gpkg(&path, "MULTIPOLYGON", 7, &[(7, "NONE", 7, utm)], &[row(&ring)]);
        let set = read_lots(&path).unwrap();
        assert_eq!(set.origin.as_deref(), Some("(457505, 5550005) of EPSG:32633"));
        assert!((set.lots[0].corners[0][0] + 4.6).abs() < 1e-6 && set.lots[0].corners[0][1] == 5.0);
        // Web Mercator by its WKT: unprojected, then read as degrees.
        let path = dir.path().join("merc.gpkg");
        let r = WEB_MERCATOR_R;
        let m = SQUARE.map(|[lon, lat]| {
            [r * lon.to_radians(), r * (std::f64::consts::FRAC_PI_4 + lat.to_radians() / 2.0).tan().ln()]
        });
        make_gpkg(&path, "POLYGON", 900, &[(900, "OTHER", 900, merc)], &[row(&m)]);
        let set = read_lots(&path).unwrap();
        let (east, _) = degree_steps(52.5205);
        let c = &set.lots[0].corners;
        assert!((c[1][0] - c[0][0] - east).abs() < 0.01, "{c:?}");
        assert!(set.origin.as_deref().unwrap().ends_with("(read from EPSG:3857)"), "{:?}", set.origin);
        // Undefined Cartesian: metres as they are.
        let path = dir.path().join("local.gpkg");
        make_gpkg(&path, "POLYGON", -1, &[], &[row(&[[0.0, 0.0], [10.0, 0.0], [10.0, 8.0]])]);
        let set = read_lots(&path).unwrap();
        assert_eq!(set.lots[0].corners, vec![[0.0, 0.0], [10.0, 0.0], [10.0, -8.0]]);
        assert!(set.origin.is_none());
        // Feet, a geocentric CRS and an srs_id without a row are refused.
        for (name, srs, extra, why) in [
            ("feet.gpkg", 2263, vec![(2263, "EPSG", 2263, feet)], "measures in feet; genform reads metres"),
            (
                "geocentric.gpkg",
                4978,
                vec![(4978, "EPSG", 4978, "GEOCCS[\"WGS 84\",DATUM[\"WGS_1984\"],UNIT[\"metre\",1]]")],
                "is neither geographic (longitude, latitude) nor projected in metres",
            ),
            ("missing.gpkg", 31, vec![], "srs_id 31 is not in gpkg_spatial_ref_sys"),
        ] {
            let path = dir.path().join(name);
            make_gpkg(&path, "POLYGON", srs, &extra, &[row(&ring)]);
            let e = format!("{:#}", read_lots(&path).unwrap_err());
            assert!(e.contains("layer `lots` of") && e.contains("has an unsupported CRS") && e.contains(why), "{e}");
        }
    }

    #[test]
    fn a_file_that_is_no_geopackage_says_so() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("lots.gpkg");
        std::fs::write(&path, "{\"type\": \"FeatureCollection\", \"features\": []}").unwrap();
        let e = format!("{:#}", read_lots(&path).unwrap_err());
        assert!(e.contains("lots.gpkg is not a GeoPackage: a GeoPackage is an SQLite database"), "{e}");
        std::fs::write(&path, "").unwrap();
        assert!(format!("{:#}", read_lots(&path).unwrap_err()).contains("is not a GeoPackage"));
        let e = format!("{:#}", read_lots(&dir.path().join("none.gpkg#lots")).unwrap_err());
        assert!(e.starts_with("cannot read footprints ") && e.contains("none.gpkg:"), "{e}");
        // An SQLite database of other tables.
        let db = dir.path().join("plain.gpkg");
        rusqlite::Connection::open(&db).unwrap().execute_batch("CREATE TABLE t (x INTEGER);").unwrap();
        let e = format!("{:#}", read_lots(&db).unwrap_err());
        assert!(e.contains("plain.gpkg is an SQLite database but not a GeoPackage: it has no `gpkg_contents`"), "{e}");
        // The real file cut short, and with its pages overwritten past the header.
        let real = std::fs::read(bubenec("bubenec.gpkg")).unwrap();
        for (name, bytes) in [
            ("cut.gpkg", real[..8192].to_vec()),
            ("scrambled.gpkg", {
                let mut b = real.clone();
                for (i, x) in b.iter_mut().enumerate().skip(100) {
                    *x = (i * 7919 % 251) as u8;
                }
                b
            }),
        ] {
            let path = dir.path().join(name);
            std::fs::write(&path, bytes).unwrap();
            let e = format!("{:#}", read_lots(Path::new(&format!("{}#plots", path.display()))).unwrap_err());
            assert!(e.contains(name) && !e.contains("panicked"), "{e}");
        }
    }

    #[test]
    fn plots_face_the_streets_of_the_street_layer() {
        // momepy's plots and streets: nearly every plot has a street within
        // reach, a few metres off its frontage (streets are centre lines).
        let set = read_lots(&bubenec("bubenec.gpkg#plots,streets")).unwrap();
        let d: Vec<f64> = set.lots.iter().filter(|l| l.props.street_edge >= 0.0).map(|l| l.props.street).collect();
        let mut sorted = d.clone();
        sorted.sort_by(f64::total_cmp);
        let median = sorted[sorted.len() / 2];
        eprintln!(
            "{} of {} plots face a street; distance median {median:.2}, max {:.2}",
            d.len(),
            set.lots.len(),
            sorted[sorted.len() - 1]
        );
        assert!(d.len() * 10 >= set.lots.len() * 9, "{} of {}", d.len(), set.lots.len());
        assert!(median > 1.0 && median < 20.0, "{median}");
        // Without the street layer, no lot has a street.
        let bare = read_lots(&bubenec("bubenec.gpkg#plots")).unwrap();
        assert!(bare.lots.iter().all(|l| l.props.street_edge == -1.0 && l.props.street == -1.0));
        // A street layer that is none, or not lines, says so.
        let e = format!("{:#}", read_lots(&bubenec("bubenec.gpkg#plots,roads")).unwrap_err());
        assert!(e.contains("no feature layer `roads` for the streets"), "{e}");
        let e = format!("{:#}", read_lots(&bubenec("bubenec.gpkg#plots,buildings")).unwrap_err());
        assert!(e.contains("not street lines"), "{e}");
    }
}
