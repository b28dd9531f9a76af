#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Writes the seed corpora of the fuzz targets into OUT/{MIF,TCK,TrackVis,SWC,TRX} from real files:
# nibabel's and DIPY's .trk/.tck files, Sightline's SWC test files, small TRX archives of
# nibabel's tracks as trx-python lays them out (every positions dtype, stored and deflated, dpv,
# dps, groups, dpg; one with the older one-offset-per-streamline layout), and small .mif/.mif.gz cut
# by MRtrix3's mrconvert from SH_DATA/small_64D_sh_tournier07.mif (the SHData fixture) in every
# datatype the reader supports, both byte orders and three stride layouts; coarse EMC-shaped CF
# netCDF models from Examples/Python/write_earth_model.py (classic and 64-bit offset formats,
# several conventions, fill values; not netCDF-4, whose HDF5 parser is not ours: see
# Documentation/reliability.md).
# Usage: fuzz-corpus.sh OUT SH_DATA
set -euo pipefail
out="$1"
sh_data="$2"
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
nibabel=/usr/lib/python3/dist-packages/nibabel/tests/data
dipy=/usr/lib/python3/dist-packages/dipy/data/files/minimal_bundles.zip
rm -rf "$out"
mkdir -p "$out"/{MIF,TCK,TrackVis,SWC,TRX,NetCDFSpherical}
cp "$nibabel"/*.trk "$out/TrackVis/"
cp "$nibabel"/*.tck "$out/TCK/"
cp "$root"/Testing/Data/SWC/*.swc "$out/SWC/"
/usr/bin/python3 - "$dipy" "$out/TrackVis" <<'PY'
import sys, zipfile
with zipfile.ZipFile(sys.argv[1]) as bundles:
    for name in bundles.namelist():
        if name.startswith("sub_1/") and name.endswith(".trk"):
            open(f"{sys.argv[2]}/dipy_{name[6:]}", "wb").write(bundles.read(name))
PY
/usr/bin/python3 - "$nibabel/complex.trk" "$out/TRX" <<'PY'
import json, sys, zipfile
import numpy as np
import nibabel as nib
tractogram = nib.streamlines.load(sys.argv[1]).tractogram
streamlines = tractogram.streamlines
lengths = np.array([len(s) for s in streamlines])
starts = np.concatenate([[0], np.cumsum(lengths)])
positions = np.concatenate(list(streamlines))
for n, (dtype, method, older) in enumerate([
        ("float16", zipfile.ZIP_STORED, False), ("float32", zipfile.ZIP_DEFLATED, False),
        ("float64", zipfile.ZIP_STORED, True), ("float32", zipfile.ZIP_STORED, False)]):
    members = {
        "header.json": json.dumps({"DIMENSIONS": [1, 1, 1], "VOXEL_TO_RASMM": np.eye(4).tolist(),
                                   "NB_VERTICES": int(starts[-1]),
                                   "NB_STREAMLINES": len(lengths)}).encode(),
        f"positions.3.{dtype}": positions.astype(dtype).tobytes(),
        "offsets.uint32" if older else "offsets.uint64":
            (starts[:-1].astype(np.uint32) if older else starts.astype(np.uint64)).tobytes(),
        "groups/first.uint32": np.array([0], np.uint32).tobytes(),
        "dpg/first/mean.2.float32": np.array([1, 2], np.float32).tobytes(),
    }
    for key, values in tractogram.data_per_point.items():
        values = np.concatenate(list(values))
        members[f"dpv/{key}.{values.shape[1]}.float32" if values.shape[1] > 1
                else f"dpv/{key}.float32"] = values.astype(np.float32).tobytes()
    for key, values in tractogram.data_per_streamline.items():
        members[f"dps/{key}.{values.shape[1]}.float64" if values.shape[1] > 1
                else f"dps/{key}.float64"] = values.astype(np.float64).tobytes()
    with zipfile.ZipFile(f"{sys.argv[2]}/complex_{n}.trx", "w", compression=method) as archive:
        for name, data in members.items():
            archive.writestr(name, data)
PY
/usr/bin/python3 - "$root/Examples/Python" "$out/NetCDFSpherical" <<'PY'
import sys
sys.path.insert(0, sys.argv[1])
import write_earth_model as model
out = sys.argv[2]
model.write_model(f"{out}/emc_classic.nc", step=30.0, file_format="NETCDF3_CLASSIC")
model.write_model(f"{out}/emc_64bit.nc", step=45.0, file_format="NETCDF3_64BIT_OFFSET",
                  depth_units="m", latitude_descending=True, longitudes="360",
                  order=("latitude", "longitude", "depth"))
model.write_model(f"{out}/radius_regional.nc", step=10.0, file_format="NETCDF3_CLASSIC",
                  vertical="radius", region=(-30.0, 30.0, 150.0, 210.0),
                  missing=lambda d, la, lo: la > 15)
PY
source="$sh_data/small_64D_sh_tournier07.mif"
n=0
for type in int8 uint8 int16le int16be uint16le uint16be int32le int32be uint32le uint32be \
            float32le float32be float64le float64be; do
  for strides in 1,2,3,4 -2,3,-4,1 4,-3,2,1; do
    ext=mif
    [ $((n % 2)) -eq 1 ] && ext=mif.gz
    mrconvert -quiet -force "$source" -coord 0 0:1 -coord 1 0:2 -coord 2 0:1 -coord 3 0:5 \
      -datatype "$type" -strides "$strides" "$out/MIF/${type}_${strides//,/_}.$ext"
    n=$((n + 1))
  done
done
echo "seeds: $(ls "$out/MIF" | wc -l) MIF, $(ls "$out/TCK" | wc -l) TCK," \
  "$(ls "$out/TrackVis" | wc -l) TrackVis, $(ls "$out/SWC" | wc -l) SWC, $(ls "$out/TRX" | wc -l) TRX," \
  "$(ls "$out/NetCDFSpherical" | wc -l) NetCDFSpherical"
