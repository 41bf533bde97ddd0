#!/bin/bash
# Builds every libFuzzer target (tests/fuzz/, Clang + -DMESHLESS_BUILD_FUZZ=ON) and runs each for
# SECONDS seconds (default 60) on a seed corpus: small inputs generated here plus files of
# ../shared/data referenced by path (read into the corpus folder under the build folder; nothing is
# copied into the repository). Findings (crash-*, leak-*, timeout-*, oom-*) land in
# BUILD/fuzz-out/NAME/; the script exits 1 when any target found something (and prints the tail of
# its log: the report and the input that triggered it).
#   scripts/fuzz.sh [SECONDS] [BUILD_DIR] [TARGET...]
# Needs clang-14 and libclang-rt-14-dev (Debian). Example: scripts/fuzz.sh 30 build-fuzz fuzz_nrrd fuzz_slc
# BUILD_DIR may also be an existing sanitizer-tier folder configured with -DMESHLESS_BUILD_FUZZ=ON
# (scripts/setup.sh test/sanitize do that with Clang and run every target FUZZ_SECONDS each).
set -uo pipefail
secs=${1:-60}
build=$(realpath -m "${2:-build-fuzz}")
shift $(( $# > 2 ? 2 : $# ))
root=$(cd "$(dirname "$0")/.." && pwd)
data=${MESHLESS_DATA:-$root/../shared/data}
all=(fuzz_ply fuzz_multiblock fuzz_field_file fuzz_raw_sidecar fuzz_nrrd fuzz_mha fuzz_vtk_legacy fuzz_vti fuzz_vtkjs
     fuzz_slc fuzz_nifti fuzz_nifti_gz fuzz_voreen fuzz_npy_volume fuzz_plot3d fuzz_vtp fuzz_oriented_vtp fuzz_vts fuzz_vtu fuzz_csv fuzz_npy fuzz_points_raw
     fuzz_point_stream fuzz_sample_cells fuzz_mlb fuzz_mls fuzz_png fuzz_cluster_tree_file fuzz_point_store
     fuzz_positions fuzz_dicom fuzz_dicom_rle fuzz_zarr fuzz_hdf5)
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=("${all[@]}")

if [ ! -f "$build/build.ninja" ]; then
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_C_COMPILER=clang-14 \
        -DMESHLESS_BUILD_FUZZ=ON -DMESHLESS_BUILD_TESTS=OFF -DCMAKE_BUILD_TYPE=RelWithDebInfo || exit 2
fi
# fuzz_dicom exists only in a build with the DICOM reader (GDCM found: MESHLESS_WITH_DICOM)
if ! grep -q '^MESHLESS_WITH_DICOM:BOOL=ON' "$build/CMakeCache.txt" 2>/dev/null; then
  kept=()
  for t in "${targets[@]}"; do [ "$t" = fuzz_dicom ] && echo "fuzz.sh: $build has no DICOM reader: fuzz_dicom left out" >&2 || kept+=("$t"); done
  targets=("${kept[@]}")
fi
# fuzz_hdf5 exists only in a build with the HDF5 reader (libhdf5 found: MESHLESS_WITH_HDF5)
if ! grep -q '^MESHLESS_WITH_HDF5:BOOL=ON' "$build/CMakeCache.txt" 2>/dev/null; then
  kept=()
  for t in "${targets[@]}"; do [ "$t" = fuzz_hdf5 ] && echo "fuzz.sh: $build has no HDF5 reader: fuzz_hdf5 left out" >&2 || kept+=("$t"); done
  targets=("${kept[@]}")
fi
cmake --build "$build" --target "${targets[@]}" || exit 2

seeds=$build/fuzz-seeds
rm -rf "$seeds"
mkdir -p "$seeds"
seed() {  # seed TARGET NAME: stdin -> a seed file (at most 64 KiB)
  mkdir -p "$seeds/$1"
  head -c 65536 > "$seeds/$1/$2"
}
have() { [ -f "$data/$1" ]; }
gz() { gzip -9 -c; }
z64() { head -c "$1" /dev/zero; }

printf 'ObjectFileName: v.raw\nResolution: 4 4 2\nSliceThickness: 1 1 1\nFormat: UCHAR\n\0' | cat - <(z64 32) | seed fuzz_raw_sidecar small
printf 'ObjectFileName: w.raw\nResolution: 4 2 2\nSliceThickness: 1 2 1\nFormat: USHORT\n\0' | cat - <(z64 32) | seed fuzz_voreen small
# RLE Lossless items: 4 pixels, 1 byte a sample; an empty offset table, one fragment (header, a literal run)
{ printf '\x04\x00\x00\xfe\xff\x00\xe0\x00\x00\x00\x00\xfe\xff\x00\xe0\x46\x00\x00\x00\x01\x00\x00\x00\x40\x00\x00\x00';
  z64 56; printf '\x03\x01\x02\x03\x04\x00\xfe\xff\xdd\xe0\x00\x00\x00\x00'; } | seed fuzz_dicom_rle literal
have bucky/Bucky_32x32x32_uint8.dat && seed fuzz_voreen bucky < "$data/bucky/Bucky_32x32x32_uint8.dat"
{ printf 'NRRD0004\ntype: uint8\ndimension: 3\nsizes: 4 4 2\nspacings: 1 1 2\nencoding: raw\n\n'; z64 32; } | seed fuzz_nrrd raw
{ printf 'NRRD0005\ntype: short\ndimension: 3\nsizes: 2 2 2\nendian: big\nspace directions: (1,0,0) (0,1,0) (0,0,1)\nspace origin: (0,0,0)\nencoding: gzip\n\n'; z64 16 | gz; } | seed fuzz_nrrd gzip
{ printf 'NRRD0004\ntype: float\ndimension: 3\nsizes: 2 2 1\nencoding: ascii\n\n1 2 3 4\n'; } | seed fuzz_nrrd ascii
have vtk_headsq/quarter.nhdr && seed fuzz_nrrd quarter < "$data/vtk_headsq/quarter.nhdr"
{ printf 'ObjectType = Image\nNDims = 3\nDimSize = 4 4 2\nElementSpacing = 1 1 2\nOffset = 0 0 0\nElementType = MET_UCHAR\nElementDataFile = LOCAL\n'; z64 32; } | seed fuzz_mha raw
{ printf 'ObjectType = Image\nNDims = 3\nDimSize = 2 2 2\nElementType = MET_SHORT\nCompressedData = True\nElementDataFile = LOCAL\n'; z64 16 | gz; } | seed fuzz_mha gzip
have vtk_HeadMRVolume/HeadMRVolume.mhd && seed fuzz_mha headmr < "$data/vtk_HeadMRVolume/HeadMRVolume.mhd"
{ printf '# vtk DataFile Version 3.0\nt\nBINARY\nDATASET STRUCTURED_POINTS\nDIMENSIONS 4 4 2\nSPACING 1 1 1\nORIGIN 0 0 0\nPOINT_DATA 32\nSCALARS s unsigned_char 1\nLOOKUP_TABLE default\n'; z64 32; } | seed fuzz_vtk_legacy binary
{ printf '# vtk DataFile Version 3.0\nt\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2 2 1\nSPACING 1 1 1\nORIGIN 0 0 0\nPOINT_DATA 4\nFIELD f 1\ns 1 4 float\n1 2 3 4\n'; } | seed fuzz_vtk_legacy ascii
have vtk_ironProt/ironProt.vtk && seed fuzz_vtk_legacy ironprot < "$data/vtk_ironProt/ironProt.vtk"
for f in amr/chombo3d/chombo3d_9.vti amr/HierarchicalBoxDataset.v1.1/HierarchicalBoxDataset.v1.1_0.vti vtk_hydrogen/hydrogen.vti; do
  have "$f" && seed fuzz_vti "$(basename "$f")" < "$data/$f"
done
printf '<?xml version="1.0"?>\n<VTKFile type="ImageData" version="0.1" byte_order="LittleEndian">\n<ImageData WholeExtent="0 1 0 1 0 0" Origin="0 0 0" Spacing="1 1 1">\n<Piece Extent="0 1 0 1 0 0">\n<PointData Scalars="s">\n<DataArray type="Float32" Name="s" format="ascii">1 2 3 4</DataArray>\n</PointData>\n</Piece>\n</ImageData>\n</VTKFile>\n' | seed fuzz_vti ascii
{ printf '{"vtkClass":"vtkImageData","extent":[0,3,0,3,0,1],"spacing":[1,1,1],"origin":[0,0,0],"pointData":{"arrays":[{"data":{"dataType":"Uint8Array","numberOfComponents":1,"size":32,"ref":{"id":"s","basepath":"data","encode":"LittleEndian","registration":"setScalars"}}}]}}\0'; z64 32 | gz; } | seed fuzz_vtkjs small
have vtkjs_LIDC2/LIDC2.vti/index.json && { cat "$data/vtkjs_LIDC2/LIDC2.vti/index.json"; printf '\0'; z64 64 | gz; } | seed fuzz_vtkjs lidc2
{ printf '11111\n4 4 2 8\n1 1 1\n0 0 0 1\n0 0 X\n'; for z in 1 2; do printf '4 X'; printf '\x10\x05\x00\x00'; done; } | seed fuzz_slc rle
{ printf '11111\n2 2 2 8\n1 1 2\n0 0 0 0\n1 1 X\x01\x02\x03'; for z in 1 2; do printf '4 X'; printf '\x01\x02\x03\x04'; done; } | seed fuzz_slc raw
for f in nut.slc sphere.slc; do have "vtk_slc/$f" && seed fuzz_slc "$f" < "$data/vtk_slc/$f"; done
python3 - "$seeds" <<'EOF'
import gzip, os, struct, sys
d = sys.argv[1]
h = bytearray(352)
struct.pack_into('<i', h, 0, 348)
struct.pack_into('<8h', h, 40, 3, 4, 4, 2, 1, 1, 1, 1)
struct.pack_into('<hh', h, 70, 2, 8)
struct.pack_into('<4f', h, 76, 1, 1, 1, 2)
struct.pack_into('<fff', h, 108, 352, 1, 0)
struct.pack_into('<hh', h, 252, 0, 1)
struct.pack_into('<4f', h, 280, 1, 0, 0, 5)
h[344:348] = b'n+1\0'
nii = bytes(h) + bytes(range(32))
for t, data in (('fuzz_nifti', nii), ('fuzz_nifti_gz', gzip.compress(nii))):
    os.makedirs(os.path.join(d, t), exist_ok=True)
    open(os.path.join(d, t, 'small'), 'wb').write(data)
hdr = "{'descr': '<f4', 'fortran_order': False, 'shape': (3, 4), }"
hdr += ' ' * ((64 - (10 + len(hdr) + 1) % 64) % 64) + '\n'
npy = b'\x93NUMPY\x01\x00' + struct.pack('<H', len(hdr)) + hdr.encode() + struct.pack('<12f', *range(12))
os.makedirs(os.path.join(d, 'fuzz_npy'), exist_ok=True)
open(os.path.join(d, 'fuzz_npy', 'small'), 'wb').write(npy)
for name, descr, order in (('c', '<i2', 'False'), ('f', '>f4', 'True')):  # 3-D arrays: volumes
    hdr = "{'descr': '%s', 'fortran_order': %s, 'shape': (2, 3, 4), }" % (descr, order)
    hdr += ' ' * ((64 - (10 + len(hdr) + 1) % 64) % 64) + '\n'
    vol = b'\x93NUMPY\x01\x00' + struct.pack('<H', len(hdr)) + hdr.encode() + bytes(range(24 * int(descr[2])))
    for t in ('fuzz_npy_volume', 'fuzz_npy'):
        os.makedirs(os.path.join(d, t), exist_ok=True)
        open(os.path.join(d, t, 'volume_' + name), 'wb').write(vol)
EOF
# Zarr stores: the .zarray, a NUL, chunk 0.0.0 (uncompressed, zlib, zstd; a 4x4x2 array in one chunk)
zarray() { printf '{"zarr_format": 2, "shape": [2, 4, 4], "chunks": [%s], "dtype": "%s", "compressor": %s, "fill_value": 0, "filters": null, "order": "%s"}\0' "$@"; }
{ zarray "2, 4, 4" "|u1" null C; z64 32; } | seed fuzz_zarr raw
{ zarray "2, 4, 4" "<i2" '{"id": "zlib", "level": 1}' F; z64 64 | python3 -c 'import sys, zlib; sys.stdout.buffer.write(zlib.compress(sys.stdin.buffer.read()))'; } | seed fuzz_zarr zlib
{ zarray "1, 2, 4" ">f4" '{"id": "gzip", "level": 1}' C; z64 32 | gz; } | seed fuzz_zarr gzip
command -v zstd >/dev/null && { zarray "2, 4, 4" "<u2" '{"id": "zstd", "level": 1}' C; z64 64 | zstd -q -c; } | seed fuzz_zarr zstd
# HDF5 files (python3-h5py, when installed): a 4x4x2 volume contiguous, and chunked with deflate and shuffle
/usr/bin/python3 - "$seeds/fuzz_hdf5" <<'EOF' 2>/dev/null || true
import os, sys
import numpy as np, h5py
os.makedirs(sys.argv[1], exist_ok=True)
v = (np.arange(32, dtype=np.uint16) * 7).reshape(2, 4, 4)
with h5py.File(os.path.join(sys.argv[1], "contiguous"), "w", libver="earliest") as f:
    d = f.create_dataset("v", data=v.astype(np.uint8))
    d.attrs["spacing"] = [1.0, 1.0, 2.0]
with h5py.File(os.path.join(sys.argv[1], "deflate"), "w", libver="earliest") as f:
    f.create_dataset("g/v", data=v.astype(">i2"), chunks=(1, 2, 4), compression="gzip", shuffle=True)
EOF
have mni152_brain/avg152T1_RL_nifti.nii.gz && seed fuzz_nifti_gz mni < "$data/mni152_brain/avg152T1_RL_nifti.nii.gz"
have scattered/dark_matter_halo/halo_low_res.npy && seed fuzz_npy halo < "$data/scattered/dark_matter_halo/halo_low_res.npy"
have plot3d/mbwavelet_ascii.xyz && { cat "$data/plot3d/mbwavelet_ascii.xyz"; printf '\0'; cat "$data/plot3d/mbwavelet_ascii.q"; } | seed fuzz_plot3d mbwavelet
have plot3d/multi-bin.xyz && seed fuzz_plot3d multibin < "$data/plot3d/multi-bin.xyz"
have scattered/probes/probes.vtp && seed fuzz_vtp probes < "$data/scattered/probes/probes.vtp"
# oriented points (splat's .vtp): a small isosurface written by this build, and one by hand in ascii
printf '<?xml version="1.0"?>\n<VTKFile type="PolyData" version="0.1" byte_order="LittleEndian">\n<PolyData>\n<Piece NumberOfPoints="2">\n<PointData Normals="Normals">\n<DataArray type="Float32" Name="Normals" NumberOfComponents="3" format="ascii">0 0 1 1 0 0</DataArray>\n<DataArray type="Float32" Name="radius" format="ascii">0.5 0.5</DataArray>\n<DataArray type="Float32" Name="value" format="ascii">1 1</DataArray>\n</PointData>\n<Points>\n<DataArray type="Float32" NumberOfComponents="3" format="ascii">0 0 0 1 0 0</DataArray>\n</Points>\n</Piece>\n</PolyData>\n</VTKFile>\n' | seed fuzz_oriented_vtp ascii
otmp=$(mktemp -d)
if [ -x "$build/cli/meshless" ] && /usr/bin/python3 -c 'import sys
n = 10
sys.stdout.buffer.write(bytes(min(255, int(40 * ((x - 4.5) ** 2 + (y - 4.5) ** 2 + (z - 4.5) ** 2) ** 0.5)) for z in range(n) for y in range(n) for x in range(n)))' > "$otmp/s_10x10x10_uint8.raw" &&
   "$build/cli/meshless" isosurface "$otmp/s_10x10x10_uint8.raw" --iso 100.5 -o "$otmp/s.vtp" 2>/dev/null; then
  seed fuzz_oriented_vtp zlib < "$otmp/s.vtp"
fi
rm -rf "$otmp"
for i in 0 1; do have "plot3d/multicomb_$i.vts" && seed fuzz_vts "comb$i" < "$data/plot3d/multicomb_$i.vts"; done
# .vtu seeds: one node set with one tetrahedron, ascii and zlib-compressed appended (VTK's writer when
# python3-vtk9 is installed)
printf '<?xml version="1.0"?>\n<VTKFile type="UnstructuredGrid" version="0.1" byte_order="LittleEndian">\n<UnstructuredGrid>\n<Piece NumberOfPoints="4" NumberOfCells="1">\n<PointData Scalars="s">\n<DataArray type="Float32" Name="s" format="ascii">1 2 3 4</DataArray>\n</PointData>\n<Points>\n<DataArray type="Float32" NumberOfComponents="3" format="ascii">0 0 0 1 0 0 0 1 0 0 0 1</DataArray>\n</Points>\n<Cells>\n<DataArray type="Int64" Name="connectivity" format="ascii">0 1 2 3</DataArray>\n<DataArray type="Int64" Name="offsets" format="ascii">4</DataArray>\n<DataArray type="UInt8" Name="types" format="ascii">10</DataArray>\n</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n' | seed fuzz_vtu ascii
vtmp=$(mktemp -d)
if /usr/bin/python3 -c 'import vtk
p = vtk.vtkPoints(); s = vtk.vtkFloatArray(); s.SetName("s")
for i in range(8): p.InsertNextPoint(i % 2, i // 2 % 2, i // 4); s.InsertNextValue(i)
g = vtk.vtkUnstructuredGrid(); g.SetPoints(p); g.GetPointData().SetScalars(s)
w = vtk.vtkXMLUnstructuredGridWriter(); w.SetInputData(g); w.SetFileName("'"$vtmp"'/z.vtu")
w.SetDataModeToAppended(); w.SetCompressorTypeToZLib(); w.Write()' 2>/dev/null; then
  seed fuzz_vtu zlib < "$vtmp/z.vtu"
fi
rm -rf "$vtmp"
have scattered/sparsePoints.txt && seed fuzz_csv sparse < "$data/scattered/sparsePoints.txt"
have scattered/gravi.txt && head -c 2000 "$data/scattered/gravi.txt" | seed fuzz_csv gravi
printf 'x,y,z,value\n0,0,0,1\n1,0,0,2\n0,1,0,3\n0,0,1,4\n' | seed fuzz_csv small
printf 'x,y,z\n# probe positions\n0,0,0\n1.5;2\t3\n\n-4 5e-3 6 extra\n' | seed fuzz_positions small
have scattered/Particles.raw && seed fuzz_points_raw particles < "$data/scattered/Particles.raw"
have bucky/Bucky_32x32x32_uint8.raw && head -c 4096 "$data/bucky/Bucky_32x32x32_uint8.raw" | seed fuzz_points_raw volume
# DICOM slices written by pydicom (tests/formats/make_dicom_series.py; skipped without python3-pydicom)
dtmp=$(mktemp -d)
if /usr/bin/python3 "$root/tests/formats/make_dicom_series.py" rle "$dtmp/s" 2>/dev/null; then
  seed fuzz_dicom plain < "$dtmp/s/plain/slice0000.dcm"
  seed fuzz_dicom rle < "$dtmp/s/rle/slice0000.dcm"
fi
rm -rf "$dtmp"
# the stream, store, PLY, PNG, .mlf and .mlh formats: written by a meshless binary when one is built
# (MESHLESS_EXE, else the one of BUILD_DIR, else the one of build/; optional)
exe=${MESHLESS_EXE:-$build/cli/meshless}
[ -x "$exe" ] || exe=$root/build/cli/meshless
if [ -x "$exe" ] && have fuel/fuel_64x64x64_uint8.raw && have bucky/Bucky_32x32x32_uint8.raw; then
  tmp=$(mktemp -d)
  bucky=$data/bucky/Bucky_32x32x32_uint8.raw
  "$exe" isosurface "$data/fuel/fuel_64x64x64_uint8.raw" --iso 100 -o - 2>/dev/null | head -c 65536 | seed fuzz_point_stream fuel
  # a sample stream (cell-indexed frames), and its first DATA frame as the decoder's input: u32 count, payload
  "$exe" generate "$data/fuel/fuel_64x64x64_uint8.raw" --iso 100 -o "$tmp/s.mls" 2>/dev/null &&
    head -c 65536 "$tmp/s.mls" | seed fuzz_point_stream samples &&
    u32() { od -An -tu4 -j "$1" -N 4 "$tmp/s.mls" | tr -d ' '; } &&
    at=$(( 64 + $(u32 56) )) &&
    { head -c $(( at + 20 )) "$tmp/s.mls" | tail -c 4; head -c $(( at + 32 + $(u32 $(( at + 24 ))) )) "$tmp/s.mls" | tail -c "$(u32 $(( at + 24 )))"; } |
    seed fuzz_sample_cells fuel
  "$exe" convert "$bucky" -o "$tmp/b.mlb" >/dev/null 2>&1 && seed fuzz_mlb bucky < "$tmp/b.mlb"
  "$exe" sample "$bucky" --count 200 -o "$tmp/s.ply" >/dev/null 2>&1 && seed fuzz_ply sample < "$tmp/s.ply"
  "$exe" convert "$tmp/s.ply" -o "$tmp/s.mlc" --brick-points 16 >/dev/null 2>&1 && seed fuzz_point_store sample < "$tmp/s.mlc"
  "$exe" render "$bucky" --size 16x16 -o "$tmp/r.png" >/dev/null 2>&1 && seed fuzz_png bucky < "$tmp/r.png"
  for m in 0 3; do
    "$exe" hierarchy "$bucky" --max-splits $m -o "$tmp/t$m.mlh" >/dev/null 2>&1 && seed fuzz_cluster_tree_file "t$m" < "$tmp/t$m.mlh"
  done
  # version 3: with certified errors
  "$exe" hierarchy "$bucky" --max-splits 40 --certify 0.0001,0.001 -o "$tmp/tc.mlh" >/dev/null 2>&1 && seed fuzz_cluster_tree_file tc < "$tmp/tc.mlh"
  if have scattered/sparsePoints.txt; then
    for k in rbf-grid mpu; do
      "$exe" fit "$data/scattered/sparsePoints.txt" --field $k -o "$tmp/$k.mlf" >/dev/null 2>&1 && seed fuzz_field_file "$k" < "$tmp/$k.mlf"
    done
  fi
  rm -rf "$tmp"
fi
for t in "${all[@]}"; do mkdir -p "$seeds/$t"; done

status=0
for t in "${targets[@]}"; do
  exe_t=$(find "$build/tests/fuzz" -maxdepth 1 -name "$t" -type f | head -1)
  [ -n "$exe_t" ] || { echo "$t: not built"; status=1; continue; }
  out=$build/fuzz-out/$t
  mkdir -p "$out/corpus"
  mkdir -p "$seeds/$t"
  # -seed: a fixed sequence of inputs (FUZZ_SEED, default 1), so a short CI run replays a prefix of what a
  # longer run with the same seed already explored; FUZZ_SEED=0 lets libFuzzer pick one
  # the header fields that name files, path references out of a header's folder, huge and non-finite numbers
  dict=$root/tests/fuzz/fuzz.dict
  # fuzz_hdf5: libhdf5 (Debian's, not ours) sizes its metadata buffers from the file and checks what
  # malloc returns; an absurd claim (beyond ASan's 1 TiB) is a NULL there, handled as an error, as
  # in every build without the sanitizer: ASan returns NULL too instead of aborting
  asan_t=${ASAN_OPTIONS:-}
  [ "$t" = fuzz_hdf5 ] && asan_t="${asan_t:+$asan_t:}allocator_may_return_null=1"
  (cd "$out" && ASAN_OPTIONS="$asan_t" "$exe_t" corpus "$seeds/$t" -seed="${FUZZ_SEED:-1}" -max_total_time="$secs" -rss_limit_mb=2048 \
        -malloc_limit_mb=1024 -timeout=10 -max_len=65536 -print_final_stats=1 -dict="$dict" > log.txt 2>&1)
  rc=$?
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$out/log.txt" | grep -o '[0-9]*$')
  findings=$(ls "$out" | grep -E '^(crash|leak|timeout|oom|slow-unit)-' | wc -l)
  echo "$t: rc=$rc runs=${runs:-?} findings=$findings (log: $out/log.txt)"
  if [ "$rc" -ne 0 ] || [ "$findings" -ne 0 ]; then
    status=1
    tail -n 60 "$out/log.txt" | sed "s/^/  $t| /"   # the report (stack, input) for a CI log
  fi
done
exit $status
