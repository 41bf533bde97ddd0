#!/bin/bash
# Seeds for tests/fuzz/fuzz_multiblock.cpp from ../shared/data: "MODE COLLECTION \0 PIECE" inputs
# (see the fuzz target's header). Usage: scripts/fuzz_multiblock_seeds.sh CORPUS_DIR [DATA_DIR]
set -euo pipefail
out=${1:?usage: $0 CORPUS_DIR [DATA_DIR]}
data=${2:-$(dirname "$0")/../../shared/data}
mkdir -p "$out"
amr=$data/amr
# 0: the v1.1 hierarchy cut to its level-0 box, naming p.vti
{ printf '\000'
  printf '<VTKFile type="vtkOverlappingAMR" version="1.1" byte_order="LittleEndian">\n'
  printf '<vtkOverlappingAMR origin="-1.75 -1.25 0" grid_description="XYZ">\n'
  printf '<Block level="0" spacing="0.833333 0.833333 0.666667">\n'
  printf '<DataSet index="0" amr_box="0 3 0 2 0 2" file="p.vti"/>\n</Block>\n</vtkOverlappingAMR>\n</VTKFile>\n'
  printf '\000'; cat "$amr/HierarchicalBoxDataset.v1.1/HierarchicalBoxDataset.v1.1_0.vti"; } > "$out/seed-vthb"
# 1: the chombo 0.1 .vtm cut to its level-0 box (zlib-compressed base64 piece)
{ printf '\001'
  sed -e '/group="[12]"/d' -e 's/file="chombo3d_0.vti"/file="p.vti"/' "$amr/chombo3d/chombo3d.vtm"
  printf '\000'; cat "$amr/chombo3d/chombo3d_0.vti"; } > "$out/seed-vtm-amr"
# 1: a vtkMultiBlockDataSet naming a .vts piece (appended raw data)
{ printf '\001'
  printf '<VTKFile type="vtkMultiBlockDataSet" version="1.0"><vtkMultiBlockDataSet>\n'
  printf '<Block index="0"><DataSet index="0" name="comb" file="p.vts"/></Block>\n</vtkMultiBlockDataSet></VTKFile>\n'
  printf '\000'; cat "$data/plot3d/multicomb_0.vts"; } > "$out/seed-vtm"
# 2: a .vts read directly (its own NUL bytes end the head: the appended data is cut, a truncation case)
{ printf '\002'; cat "$data/plot3d/multicomb_1.vts"; } > "$out/seed-vts"
# 3: an ASCII PLOT3D multi-grid pair
{ printf '\003'; cat "$data/plot3d/mbwavelet_ascii.xyz"; printf '\000'; cat "$data/plot3d/mbwavelet_ascii.q"; } > "$out/seed-plot3d"
ls -l "$out"
