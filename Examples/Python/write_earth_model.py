#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Writes a synthetic seismic tomography model as CF netCDF, shaped like the files of IRIS's
Earth Model Collection (EMC): variables over (depth, latitude, longitude) with `units`,
`positive: down`, `_FillValue`, and the global attributes EMC files carry.

The model is analytic, so tests know every node's value: a shear-velocity perturbation dvs
(percent) with two slow piles at the base of the mantle, a fast subducting slab (a dipping band
under the Pacific, crossing the 180-degree meridian) and a slow plume (a column under a
hotspot), and the absolute vs (km/s) of a layered reference.

The same model can be written in every convention the reader accepts: depth in km or m, or a
radius; latitude ascending or descending; longitudes in [-180, 180) or [0, 360); any axis
order; a regional window; nodes missing (fill values).

Usage: /usr/bin/python3 write_earth_model.py OUTPUT.nc [--step DEGREES] [--classic]
"""
import argparse

import numpy as np

EARTH_KM = 6371.0
DEPTHS_KM = np.array([0.0, 50, 100, 150, 200, 300, 410, 520, 670, 800, 1000, 1300, 1600, 2000,
                      2400, 2700, 2891])


def reference_vs(depth_km):
    """A layered reference: crust, upper mantle, transition zone, lower mantle (km/s)."""
    depth_km = np.asarray(depth_km, dtype=float)
    return np.select([depth_km < 35, depth_km < 410, depth_km < 670],
                     [3.6, 4.5 + 0.001 * depth_km, 5.0 + 0.001 * (depth_km - 410)],
                     6.2 + 0.0004 * (depth_km - 670))


def dvs(depth_km, latitude, longitude):
    """The perturbation in percent at nodes (arrays broadcast): two slow piles at the base of
    the mantle (a degree-2 pattern under Africa and the Pacific), a fast slab and a slow
    plume."""
    depth_km, latitude, longitude = np.broadcast_arrays(
        np.asarray(depth_km, float), np.asarray(latitude, float), np.asarray(longitude, float))
    east = np.mod(longitude, 360.0)  # 0..360: the slab crosses 180
    lat, lon = np.radians(latitude), np.radians(east)
    # Piles: slow where cos(2 (lon - 20 E)) > 0.3, from 2000 km down, strongest at the base.
    pattern = np.clip((np.cos(2 * (lon - np.radians(20.0))) * np.cos(lat) ** 2 - 0.3) / 0.7, 0, 1)
    piles = -2.5 * pattern * np.clip((depth_km - 2000.0) / 891.0, 0.0, 1.0)
    # The slab: a fast band, latitude -25..25, dipping 20 degrees west from a trench at 190 E
    # down to 700 km (it crosses the 180-degree meridian).
    along = (190.0 - east) * 111.2  # km west of the trench, roughly
    slab = np.where((np.abs(latitude) <= 25) & (along >= -1) & (depth_km <= 700) &
                    (np.abs(depth_km - 0.364 * along) <= 80), 2.0, 0.0)
    # The plume: a slow column within 8 degrees (great-circle) of 20 N, 300 E, at every depth.
    lat0, lon0 = np.radians(20.0), np.radians(300.0)
    cos_distance = np.sin(lat) * np.sin(lat0) + np.cos(lat) * np.cos(lat0) * np.cos(lon - lon0)
    plume = np.where(cos_distance >= np.cos(np.radians(8.0)), -3.0, 0.0)
    return piles + slab + plume


def write_model(path, field=dvs, step=5.0, depth_units="km", vertical="depth", latitude_descending=False,
                longitudes="-180", order=("depth", "latitude", "longitude"), region=None,
                missing=None, file_format="NETCDF4", fill_value=99999.0):
    """Writes the model (`field`(depth_km, latitude, longitude) as dvs, and vs from it);
    returns the node coordinates as (depth_km, latitude, longitude).

    vertical: "depth" (positive down) or "radius" (positive up); depth_units: "km" or "m";
    longitudes: "-180" ([-180, 180)) or "360" ([0, 360)); region: (lat_min, lat_max,
    east_min, east_max) with east in 0..360 (may pass 360); missing: a function
    (depth_km, lat, lon) -> bool of nodes written as fill values."""
    import netCDF4  # python3-netcdf4

    if region is None:
        latitude = np.arange(-90.0, 90.0 + step / 2, step)
        east = np.arange(0.0, 360.0 - step / 2, step)
    else:
        latitude = np.arange(region[0], region[1] + step / 2, step)
        east = np.arange(region[2], region[3] + step / 2, step)
    if latitude_descending:
        latitude = latitude[::-1]
    longitude = np.mod(east, 360.0)
    if longitudes == "-180":
        longitude = np.where(longitude >= 180.0, longitude - 360.0, longitude)
    if region is None:
        longitude = np.sort(longitude)
    depth = DEPTHS_KM
    coordinates = {"depth": depth, "latitude": latitude, "longitude": longitude}

    data = netCDF4.Dataset(path, "w", format=file_format)
    data.Conventions = "CF-1.0"
    data.title = "Sightline synthetic tomography model (analytic)"
    data.id = "sightline-synthetic"
    data.geospatial_vertical_positive = "down" if vertical == "depth" else "up"
    for name in order:
        data.createDimension(name, len(coordinates[name]))
    var = data.createVariable("depth", "f4", ("depth",))
    if vertical == "depth":
        var.long_name = "depth below earth surface"
        var.positive = "down"
        var.units = depth_units
        var[:] = depth * (1000.0 if depth_units == "m" else 1.0)
    else:
        var.long_name = "radius from the centre of the earth"
        var.positive = "up"
        var.units = depth_units
        var[:] = (EARTH_KM - depth) * (1000.0 if depth_units == "m" else 1.0)
    var.axis = "Z"
    var = data.createVariable("latitude", "f4", ("latitude",))
    var.long_name, var.units, var.standard_name = "Latitude; positive north", "degrees_north", "latitude"
    var[:] = latitude
    var = data.createVariable("longitude", "f4", ("longitude",))
    var.long_name, var.units, var.standard_name = "Longitude; positive east", "degrees_east", "longitude"
    var[:] = longitude

    grids = np.meshgrid(*(coordinates[name] for name in order), indexing="ij")
    nodes = dict(zip(order, grids))
    for name, values, units in (
        ("dvs", field(nodes["depth"], nodes["latitude"], nodes["longitude"]), "percent"),
        ("vs", reference_vs(nodes["depth"]) * (1 + 0.01 * field(
            nodes["depth"], nodes["latitude"], nodes["longitude"])), "km.s-1"),
    ):
        var = data.createVariable(name, "f4", order, fill_value=fill_value)
        var.units = units
        var.long_name = {"dvs": "Shear-velocity perturbation", "vs": "Shear velocity"}[name]
        values = np.ma.masked_array(values.astype(np.float32))
        if missing is not None:
            values[missing(nodes["depth"], nodes["latitude"], nodes["longitude"])] = np.ma.masked
        var[:] = values
    data.close()
    return depth, latitude, longitude


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("output", help="the .nc file to write")
    parser.add_argument("--step", type=float, default=2.0, help="degrees between nodes (2)")
    parser.add_argument("--classic", action="store_true", help="netCDF-3 classic format")
    args = parser.parse_args()
    write_model(args.output, step=args.step,
                file_format="NETCDF3_CLASSIC" if args.classic else "NETCDF4")
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
