import sqlite3, struct, json
from shapely import wkb
from shapely.geometry import mapping
from shapely.ops import transform
from pyproj import Transformer
c = sqlite3.connect("mw/momepy/datasets/bubenec.gpkg")
rows = c.execute("select fid, geom, ID, TYPPPD_KOD from plots order by fid").fetchall()
def geom(blob):
    flags = blob[3]; env = [0, 32, 48, 48, 64][(flags >> 1) & 7]
    return wkb.loads(bytes(blob[8 + env:]))
to_ll = Transformer.from_crs(3857, 4326, always_xy=True)
to_utm = Transformer.from_crs(4326, 32633, always_xy=True)
def rnd(g, n):
    return transform(lambda x, y, z=None: (round(x, n) if False else x, y), g)
def fc(feats, crs=None, name=""):
    d = {"type": "FeatureCollection", "name": name}
    if crs: d["crs"] = {"type": "name", "properties": {"name": crs}}
    d["features"] = feats
    return d
def coords(g, nd):
    m = mapping(g)
    def r(x):
        if isinstance(x, (list, tuple)) and x and isinstance(x[0], (int, float)):
            return [round(x[0], nd), round(x[1], nd)]
        return [r(y) for y in x]
    return {"type": m["type"], "coordinates": r(m["coordinates"])}
out = {"3857": [], "ll": [], "utm": []}
bad = 0
for fid, blob, pid, typ in rows:
    g = geom(blob)
    if not g.is_valid: bad += 1
    props = {"id": int(fid), "parcel": pid, "type": typ}
    ll = transform(to_ll.transform, g)
    utm = transform(to_utm.transform, ll)
    out["3857"].append({"type": "Feature", "properties": props, "geometry": coords(g, 2)})
    out["ll"].append({"type": "Feature", "properties": props, "geometry": coords(ll, 7)})
    out["utm"].append({"type": "Feature", "properties": props, "geometry": coords(utm, 2)})
print(len(rows), "invalid", bad)
D = "/work/main/crates/genform-app/tests/data/bubenec/"
json.dump(fc(out["ll"], None, "bubenec_plots"), open(D + "plots_lonlat.geojson", "w"), separators=(",", ":"))
json.dump(fc(out["utm"], "urn:ogc:def:crs:EPSG::32633", "bubenec_plots"), open(D + "plots_utm33n.geojson", "w"), separators=(",", ":"))
json.dump(fc(out["3857"], "urn:ogc:def:crs:EPSG::3857", "bubenec_plots"), open(D + "plots_3857.geojson", "w"), separators=(",", ":"))
from collections import Counter
print(Counter(type(geom(b)).__name__ for _, b, _, _ in rows), max(len(geom(b).exterior.coords) if geom(b).geom_type=="Polygon" else 0 for _, b, _, _ in rows))
