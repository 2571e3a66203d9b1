"""Prints tests/fixed_truth_maps.inc: for every world map row of the projections' case tables, three
(lon, lat) -> pixel values on a 1500x1100 frame, from PROJ (pyproj, a sphere of radius 1) and the
frame convention (map_frame.hpp: the outline's bounding box fills the frame with aspect=stretch, or
is widened about its centre to square pixels with aspect=keep, north up). The box is PROJ's
outline: the meridians 180 degrees from the central one and the parallels at lat_max, with the
equator and the central meridian, sampled densely (transverse Mercator: |X| <= atanh(sin x_max), |Y| <= pi). Run once, committed: the quick
C++ loop then holds fixed values that no round trip can agree with by being wrong both ways.

    .venv/bin/python scripts/fixed_truth.py > tests/fixed_truth_maps.inc
"""
import math

import numpy as np
import pyproj

SIZE = (1500, 1100)
ROWS = ["aitoff", "aitoff:aspect=stretch", "aitoff:lon0=45", "bonne", "bonne:aspect=stretch", "bonne:phi1=-30,lon0=10",
        "bonne:phi1=-45", "bonne:phi1=45", "bonne:phi1=5.7", "bonne:phi1=89.99", "cylindrical-equal-area",
        "cylindrical-equal-area:lat_ts=-89.9,aspect=stretch", "cylindrical-equal-area:lat_ts=45", "eckert-greifendorff",
        "eckert-greifendorff:aspect=stretch", "hammer", "hammer:aspect=stretch", "hammer:w=0.9", "mercator",
        "mercator:aspect=stretch", "mercator:lat_max=89.999", "miller", "miller:lat_max=60,lon0=-120", "mollweide",
        "mollweide:aspect=stretch", "mollweide:lon0=-75", "sinusoidal", "transverse-mercator",
        "transverse-mercator:aspect=stretch", "transverse-mercator:x_max=3,lon0=9", "transverse-mercator:x_max=89.999"]
PROJ = {"aitoff": "+proj=aitoff", "bonne": "+proj=bonne", "cylindrical-equal-area": "+proj=cea", "eckert-greifendorff":
        "+proj=hammer +W=0.25", "hammer": "+proj=hammer", "mercator": "+proj=merc", "miller": "+proj=mill",
        "mollweide": "+proj=moll", "sinusoidal": "+proj=sinu", "transverse-mercator": "+proj=tmerc"}


def parse(spec):
    name, _, rest = spec.partition(":")
    keys = dict(kv.split("=") for kv in rest.split(",") if kv)
    return name, keys


def forward(proj, lon, lat, lon0=0.0):
    lon = np.clip(np.asarray(lon, float) - lon0, -180, 180)  # at +-180 exactly: the outline's two sides
    t = pyproj.Transformer.from_crs(pyproj.CRS(f"+R=1 {proj}"), pyproj.CRS("+proj=longlat +R=1"), always_xy=True)
    x, y = t.transform(lon, np.asarray(lat, float), direction="INVERSE")
    return np.asarray(x), np.asarray(y)


def frame_of(spec, size=SIZE):
    """(proj string, lon0, the frame's map: (lon, lat) arrays -> pixel x, y arrays) for a map spec."""
    name, k = parse(spec)
    lon0 = float(k.get("lon0", 0))
    proj = PROJ[name]  # longitudes are given relative to lon0 (PROJ wraps absolute ones before +lon_0)
    if name == "bonne":
        proj += f" +lat_1={float(k.get('phi1', 45))!r}"
    if name == "cylindrical-equal-area" and "lat_ts" in k:
        proj += f" +lat_ts={k['lat_ts']}"
    if name == "hammer" and "w" in k:
        proj += f" +W={k['w']}"
    lat_max = float(k.get("lat_max", 85.0511287798066 if name == "mercator" else 90))
    if name == "transverse-mercator":
        x_max = math.radians(float(k.get("x_max", 85.0511287798066)))
        box = (-math.atanh(math.sin(x_max)), math.atanh(math.sin(x_max)), -math.pi, math.pi)
    else:
        t = np.linspace(-1, 1, 400001)
        # the outline, and the equator and central meridian (where an outline folds inwards, as
        # Hammer-Wagner's for W > 1/2, the box's sides lie inside it)
        lons = np.concatenate([lon0 + 180 * t, lon0 + 180 * t, np.full_like(t, lon0 - 180), np.full_like(t, lon0 + 180),
                               lon0 + 180 * t, np.full_like(t, lon0)])
        lats = np.concatenate([np.full_like(t, -lat_max), np.full_like(t, lat_max), lat_max * t, lat_max * t,
                               np.zeros_like(t), lat_max * t])
        X, Y = forward(proj, lons, lats, lon0)
        ok = np.isfinite(X) & np.isfinite(Y)
        box = (X[ok].min(), X[ok].max(), Y[ok].min(), Y[ok].max())
    (x0, x1, y0, y1), (w, h) = box, size
    sx, sy = w / (x1 - x0), h / (y1 - y0)
    if k.get("aspect", "keep") == "keep":
        sx = sy = min(sx, sy)

    def pixels(lon, lat):
        lon = (np.asarray(lon, float) - lon0 + 180) % 360 - 180 + lon0
        X, Y = forward(proj, lon, lat, lon0)
        return w / 2 + sx * (X - (x0 + x1) / 2), h / 2 - sy * (Y - (y0 + y1) / 2)

    return proj, lon0, pixels


def row(spec):
    name, k = parse(spec)
    _, lon0, pixels = frame_of(spec)
    if name == "transverse-mercator":
        x_max = float(k.get("x_max", 85.0511287798066))
        points = [(lon0 + 0.3 * x_max, 20.0), (lon0 - 0.5 * x_max, -70.0), (lon0 + 180 - 0.3 * x_max, 40.0)]
    else:
        lat_max = float(k.get("lat_max", 85.0511287798066 if name == "mercator" else 90))
        points = [(lon0 + 30.0, 0.4 * lat_max), (lon0 - 150.0, -0.7 * lat_max), (lon0 + 100.0, 0.9 * lat_max)]
    out = []
    for lon, lat in points:
        px, py = pixels([lon], [lat])
        out.append(f"    {{\"{spec}\", {lon!r}, {lat!r}, {float(px[0])!r}, {float(py[0])!r}}},")
    return out


def main():
    print(f"// Generated by scripts/fixed_truth.py from PROJ {pyproj.proj_version_str} (pyproj {pyproj.__version__}); "
          f"frame {SIZE[0]}x{SIZE[1]}.")
    print("// spec, longitude, latitude (degrees), pixel x, y (panoproj's convention: centres at i + 0.5)")
    for spec in ROWS:
        print("\n".join(row(spec)))


if __name__ == "__main__":
    main()
