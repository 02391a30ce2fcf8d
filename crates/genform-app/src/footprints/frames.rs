//! What every footprint reader shares: how positions are read (longitude
//! and latitude, Web Mercator, metres) and placed about a local origin, a
//! feature's properties, a ring's corners (see the parent module).

use anyhow::{Result, bail};
use genform_shape::{FootprintLot, FootprintSet as Footprints, LotProps};
use glam::DVec2;
use serde_json::Value;
use std::path::Path;

/// Most footprints one file may give (each is a whole derivation).
pub const MAX_FOOTPRINTS: usize = 100_000;

/// Metric footprints farther than this from the origin (metres) are
/// re-centred on their bounding box.
pub(super) const FAR: f64 = 10_000.0;

/// Mean radius of EPSG:3857's sphere (metres).
pub(super) const WEB_MERCATOR_R: f64 = 6_378_137.0;

/// Moves metric lots lying farther than [`FAR`] from the origin so that the
/// centre of their bounding box, rounded to whole metres, is the origin;
/// that centre in world `(x, z)`, if moved.
pub(super) fn recentre(lots: &mut [FootprintLot]) -> Option<[f64; 2]> {
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
pub(super) fn bounds(points: impl Iterator<Item = [f64; 2]>) -> Option<([f64; 2], [f64; 2])> {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in points {
        for i in 0..2 {
            lo[i] = lo[i].min(p[i]);
            hi[i] = hi[i].max(p[i]);
        }
    }
    lo[0].is_finite().then_some((lo, hi))
}

/// A lot as the file gives it: `[x, y]` positions (y north).
pub(super) struct RawLot {
    pub(super) xy: Vec<[f64; 2]>,
    pub(super) label: String,
    pub(super) props: LotProps,
}

/// How a footprint file's positions are to be read.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Frame {
    /// WGS 84 longitude and latitude, degrees.
    LonLat,
    /// EPSG:3857 pseudo-metres.
    WebMercator,
    /// Metres of a projected CRS or a local frame.
    Metres,
}

/// The error of a file none of whose lots is usable: the first reasons.
pub(super) fn no_usable(path: &Path, skipped: &[String]) -> anyhow::Error {
    let n = skipped.len();
    let shown: Vec<&str> = skipped.iter().take(3).map(String::as_str).collect();
    anyhow::anyhow!(
        "{} holds no usable footprint: {}{}",
        path.display(),
        shown.join("; "),
        if n > 3 { format!(" (and {} more)", n - 3) } else { String::new() }
    )
}

/// Lots at the file's `[x, y]` positions (y north) read as `frame` says,
/// in world `(x, z)` metres about a local origin, and that origin in the
/// file's terms (`crs` names the CRS of metric positions); lots that
/// cannot be projected join `skipped`.
pub(super) fn place(
    raw: Vec<RawLot>,
    frame: Frame,
    crs: Option<&str>,
    skipped: &mut Vec<String>,
) -> Result<(Vec<FootprintLot>, Option<String>)> {
    Ok(match frame {
        Frame::Metres => {
            let mut lots: Vec<FootprintLot> = raw
                .into_iter()
                .map(|r| FootprintLot {
                    corners: r.xy.iter().map(|&[x, y]| [x, -y]).collect(),
                    label: r.label,
                    props: r.props,
                })
                .collect();
            let of = crs.map_or(String::new(), |c| format!(" of {c}"));
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
    })
}

/// The EPSG code in a CRS name: `EPSG:3857`, `urn:ogc:def:crs:EPSG::3857`.
pub(super) fn epsg_code(name: &str) -> Option<u32> {
    let upper = name.to_ascii_uppercase();
    if !upper.contains("EPSG") {
        return None;
    }
    upper.rsplit(':').next()?.trim().parse().ok()
}

/// The frame of the EPSG codes genform knows by number: Web Mercator's,
/// and the geographic CRSs of WGS 84, ETRS89 and NAD83 (the same to a
/// metre, and a footprint's shape the same to far less).
pub(super) fn frame_of_epsg(code: u32) -> Option<Frame> {
    match code {
        3857 | 900913 | 3785 | 102100 | 102113 => Some(Frame::WebMercator),
        4326 | 4258 | 4269 | 4979 => Some(Frame::LonLat),
        _ => None,
    }
}

pub(super) fn frame_of(crs: Option<&str>, raw: &[RawLot]) -> Frame {
    match crs {
        Some(name) => {
            let upper = name.to_ascii_uppercase();
            match epsg_code(name).and_then(frame_of_epsg) {
                Some(frame) => frame,
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
pub(super) fn web_mercator_to_lonlat([x, y]: [f64; 2]) -> [f64; 2] {
    let lon = (x / WEB_MERCATOR_R).to_degrees();
    let lat = (2.0 * (y / WEB_MERCATOR_R).exp().atan() - std::f64::consts::FRAC_PI_2).to_degrees();
    [lon, lat]
}

/// Projects longitude/latitude lots onto a transverse Mercator tangent to
/// their bounding box's centre: the lots in world `(x, z)` metres, the
/// centre in words, and the lots skipped (positions off the globe).
pub(super) fn project_lonlat(raw: Vec<RawLot>) -> Result<(Vec<FootprintLot>, String, Vec<String>)> {
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

pub(super) fn extent(lot: &[[f64; 2]]) -> f64 {
    bounds(lot.iter().copied()).map_or(0.0, |(lo, hi)| (hi[0] - lo[0]).max(hi[1] - lo[1]))
}

/// A number, or the number a string begins with (`"12"`, `"12.5 m"`,
/// `"40 ft"` and `"40'"` in feet are metres ×0.3048).
pub(super) fn number(v: &Value) -> Option<f64> {
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
pub(super) fn props_of(props: Option<&Value>, index: usize) -> LotProps {
    let get = |k: &str| props.and_then(|p| p.get(k)).and_then(number).unwrap_or(0.0);
    let levels = props.and_then(|p| p.get("building:levels").or_else(|| p.get("levels"))).and_then(number);
    LotProps {
        height: get("height"),
        min_height: get("min_height"),
        levels: levels.unwrap_or(0.0),
        use_class: props.and_then(|p| p.get("building")).and_then(Value::as_str).map_or(0.0, use_class),
        index: index as f64,
        ..LotProps::default()
    }
}

/// A ring's positions without the closing repeat of the first one; an
/// error when under three corners are left.
pub(super) fn ring_of(mut pts: Vec<[f64; 2]>) -> Result<Vec<[f64; 2]>> {
    if pts.len() > 1 && pts.first() == pts.last() {
        pts.pop();
    }
    if pts.len() < 3 {
        bail!("an outer ring of {} corners (3 at least)", pts.len());
    }
    Ok(pts)
}

/// How far (metres) from the middle of a lot's edge, along its outward
/// normal, a street line is still the lot's street: a plot's frontage lies
/// a few metres from the street's centre line, a building's a few more.
pub(super) const STREET_REACH: f64 = 60.0;

/// Sets each lot's street edge and distance ([`LotProps::street_edge`],
/// [`LotProps::street`]) from the street lines `streets` (positions as the
/// lots', read as `frame` says): the edge whose outward normal, cast from
/// its middle, meets a street nearest (within [`STREET_REACH`]); of two
/// within a metre of each other, the longer. Edges under half a metre are
/// left out (a jog in the outline faces nothing).
/// The lots read from `at` (and the lots `skipped` there), their street
/// edges found and placed in `frame`: what every reader ends with.
pub(super) fn finish(
    at: &Path,
    mut raw: Vec<RawLot>,
    mut skipped: Vec<String>,
    streets: &[Vec<[f64; 2]>],
    frame: Frame,
    crs: Option<&str>,
) -> Result<Footprints> {
    face_streets(&mut raw, streets, frame);
    let (lots, origin) = place(raw, frame, crs, &mut skipped)?;
    if lots.is_empty() && !skipped.is_empty() {
        bail!("{} holds no usable footprint: {}", at.display(), skipped[0]);
    }
    Ok(Footprints { lots, origin, skipped })
}

pub(super) fn face_streets(raw: &mut [RawLot], streets: &[Vec<[f64; 2]>], frame: Frame) {
    let Some((lo, hi)) = bounds(raw.iter().flat_map(|r| r.xy.iter().copied())) else { return };
    // Local metres about the lots' middle: the directions are what matter,
    // and both these maps keep angles there.
    let mid = (lo[1] + hi[1]) / 2.0;
    let (sx, sy) = match frame {
        Frame::Metres => (1.0, 1.0),
        Frame::LonLat => (111_320.0 * mid.to_radians().cos(), 110_574.0),
        Frame::WebMercator => {
            let c = web_mercator_to_lonlat([0.0, mid])[1].to_radians().cos();
            (c, c)
        }
    };
    let at = |p: [f64; 2]| DVec2::new(p[0] * sx, p[1] * sy);
    let segments: Vec<(DVec2, DVec2)> =
        streets.iter().flat_map(|l| l.windows(2).map(|w| (at(w[0]), at(w[1])))).filter(|(a, b)| a != b).collect();
    if segments.is_empty() {
        return;
    }
    for r in raw.iter_mut() {
        let pts: Vec<DVec2> = r.xy.iter().map(|p| at(*p)).collect();
        let n = pts.len();
        let twice: f64 = (0..n).map(|i| pts[i].perp_dot(pts[(i + 1) % n])).sum();
        let mut best: Option<(f64, f64, usize)> = None;
        for k in 0..n {
            let (a, b) = (pts[k], pts[(k + 1) % n]);
            let len = a.distance(b);
            if len < 0.5 {
                continue;
            }
            let d = (b - a) / len;
            let out = if twice > 0.0 { DVec2::new(d.y, -d.x) } else { DVec2::new(-d.y, d.x) };
            let m = (a + b) * 0.5;
            let hit = segments.iter().filter_map(|&(s0, s1)| ray_hit(m, out, s0, s1)).fold(f64::INFINITY, f64::min);
            if hit > STREET_REACH {
                continue;
            }
            let better = match best {
                None => true,
                Some((t, l, _)) => hit < t - 1.0 || ((hit - t).abs() <= 1.0 && len > l),
            };
            if better {
                best = Some((hit, len, k));
            }
        }
        if let Some((t, _, k)) = best {
            r.props.street = t;
            r.props.street_edge = k as f64;
        }
    }
}

/// Where the ray from `m` along the unit `dir` meets the segment `s0`–`s1`:
/// its distance, if ahead.
fn ray_hit(m: DVec2, dir: DVec2, s0: DVec2, s1: DVec2) -> Option<f64> {
    let e = s1 - s0;
    let den = dir.perp_dot(e);
    if den.abs() <= 1e-12 * e.length() {
        return None;
    }
    let w = s0 - m;
    let t = w.perp_dot(e) / den;
    let u = w.perp_dot(dir) / den;
    (t > 0.0 && (0.0..=1.0).contains(&u)).then_some(t)
}
