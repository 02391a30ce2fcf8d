//! Building footprints from GeoJSON, GeoPackage or OBJ: the lots a shape
//! grammar is derived on, one derivation per polygon (`footprints "…";` in
//! a `.sg` file, or `genform sample --footprints FILE`). [`read_lots`]
//! picks the reader by the file's extension (`.obj`, `.gpkg`, else
//! GeoJSON).
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
//! GeoPackage (OGC 12-128, an SQLite file; [`read_gpkg`]): one feature
//! layer (a `features` row of `gpkg_contents`, its geometry column from
//! `gpkg_geometry_columns`) — the one named after a `#` in the path
//! (`lots.gpkg#buildings`, see [`split_layer`]), else the file's only
//! POLYGON or MULTIPOLYGON layer (several are an error that lists them;
//! point and line layers are never lots). Each row is a feature: its
//! Polygon, each polygon of its MultiPolygon (Z and M dropped) is a lot
//! named by its `fid`, and its other TEXT, INTEGER and REAL columns are its
//! properties, read as GeoJSON's are. The layer's `srs_id` says how
//! positions are read, by the same three ways: EPSG:4326 (and the other
//! geographic CRSs) as longitude and latitude, EPSG:3857 as Web Mercator,
//! projected CRSs in metres, `srs_id` −1 (undefined Cartesian) as metres
//! and 0 (undefined geographic) guessed as GeoJSON without `crs` is; a
//! CRS in feet, geocentric or unknown is an error.
//!
//! Local origin: geographic footprints are built about their centre (the
//! tangent point); metric ones farther than 10 km from the origin are
//! moved so that the centre of their bounding box, rounded to whole
//! metres, is the origin — at 6·10⁶ m an f32 scene would round every
//! vertex to 0.5 m. [`Footprints::origin`] says where the origin lies, in
//! the file's terms. OBJ files are re-centred by the same rule.
//!
//! A feature genform cannot use (a position that is no pair of numbers, a
//! ring of under three corners; in a GeoPackage also a NULL, empty or
//! unreadable geometry, or one that is no polygon) is skipped with a
//! warning naming it ([`Footprints::skipped`]); a file that is not GeoJSON
//! (not a GeoPackage, for `.gpkg`) is an error.

mod frames;
mod geojson;
mod gpkg;
mod obj;

use anyhow::Result;
pub use genform_shape::FootprintSet as Footprints;
pub use geojson::read_geojson;
pub use gpkg::read_gpkg;
pub use obj::read_obj;
use std::path::{Path, PathBuf};

/// The lots of the footprint file at `path` (OBJ or GeoPackage when its
/// extension says so, else GeoJSON; `lots.gpkg#LAYER` names a GeoPackage
/// layer), centred on a local origin, with what was skipped.
pub fn read_lots(path: &Path) -> Result<Footprints> {
    let (file, layer) = split_layer(path);
    let ext = |e: &str| file.extension().is_some_and(|x| x.eq_ignore_ascii_case(e));
    if ext("gpkg") {
        read_gpkg(&file, layer.as_deref())
    } else if ext("obj") {
        read_obj(&file)
    } else {
        read_geojson(&file)
    }
}

/// A footprint path as the user writes it, split into the file and the
/// GeoPackage layer named after its last `#`: `lots.gpkg#buildings` is
/// layer `buildings` of `lots.gpkg`. Only a `.gpkg` file takes a layer
/// (any other path, and `lots.gpkg#` with no name, is the file as given),
/// so GeoJSON and OBJ paths are never split.
pub fn split_layer(path: &Path) -> (PathBuf, Option<String>) {
    let Some(text) = path.to_str() else { return (path.to_path_buf(), None) };
    match text.rsplit_once('#') {
        Some((file, layer))
            if !layer.is_empty()
                && !layer.contains(['/', '\\'])
                && file.len() > 5
                && file.is_char_boundary(file.len() - 5)
                && file[file.len() - 5..].eq_ignore_ascii_case(".gpkg") =>
        {
            (PathBuf::from(file), Some(layer.to_string()))
        }
        _ => (path.to_path_buf(), None),
    }
}

/// [`read_lots`] as bare corner lists, the skipped lots warned about.
pub fn read_footprints(path: &Path) -> Result<Vec<Vec<[f64; 2]>>> {
    let set = read_lots(path)?;
    for why in &set.skipped {
        crate::notes::warn(&format!("warning: {}: {why}; skipped", path.display()));
    }
    Ok(set.lots.into_iter().map(|l| l.corners).collect())
}

#[cfg(test)]
mod tests {
    use super::frames::{WEB_MERCATOR_R, number, use_class};
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
    pub(super) fn degree_steps(lat: f64) -> (f64, f64) {
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

    #[test]
    fn line_features_are_streets_a_lot_faces() {
        let lot = r#"{"type": "Feature", "properties": {}, "geometry": {"type": "Polygon",
            "coordinates": [[[0, 0], [10, 0], [10, 10], [0, 10], [0, 0]]]}}"#;
        let south = r#"{"type": "Feature", "properties": {"highway": "residential"}, "geometry":
            {"type": "LineString", "coordinates": [[-20, -5], [30, -5]]}}"#;
        let east = r#"{"type": "Feature", "properties": {}, "geometry":
            {"type": "MultiLineString", "coordinates": [[[13, -20], [13, 30]]]}}"#;
        let fc = |parts: &[&str]| format!(r#"{{"type": "FeatureCollection", "features": [{}]}}"#, parts.join(","));
        // Metres (a `crs` that is no geographic one).
        let metres =
            |t: String| t.replacen('{', r#"{"crs": {"type": "name", "properties": {"name": "EPSG:32633"}},"#, 1);
        let one = read(&metres(fc(&[lot, south]))).unwrap();
        assert_eq!(one.lots.len(), 1, "the street is no lot");
        let p = one.lots[0].props;
        assert_eq!((p.street_edge, p.street), (0.0, 5.0));
        // The nearer street wins: the east one, 3 m off edge 1.
        let two = read(&metres(fc(&[lot, south, east]))).unwrap();
        let p = two.lots[0].props;
        assert_eq!((p.street_edge, p.street), (1.0, 3.0));
        // No street within reach: none.
        let far = south.replace("-5]", "-500]");
        let p = read(&metres(fc(&[lot, &far]))).unwrap().lots[0].props;
        assert_eq!((p.street_edge, p.street), (-1.0, -1.0));
    }
}
