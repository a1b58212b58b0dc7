#!/usr/bin/env bash
# Device run: the compute rasteriser (`--compute-raster AREA`) beside the visibility path's
# raster pass, both timed in the same frames, on the courtyard and the city of 20,000
# instances at MSAA 1, 4 and 8; AREA 64 and 256 (pixel boxes up to that rasterised by one
# invocation, larger ones by 16x16 tiles) and 0 (every triangle by tiles).
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
xz -dc target-device/xtask-after.xz > /tmp/xtask && chmod +x /tmp/xtask
/tmp/xtask info 2>&1 | head -12
common="--sizes 1920x1080 --tiles 16 --msaa 1,4,8 --lights 4096 --paths visibility --scalarize off --frames 30 --warmup 8 --cell-budget 2"
run() {
  name=$1; shift
  /tmp/xtask bench $common "$@" --out /tmp/$name 2>&1 | tail -4
  mkdir -p $OUT/$name
  cp /tmp/$name/bench.csv $OUT/$name/ 2>/dev/null
}
for area in 64 256 0; do
  run courtyard-$area --compute-raster $area
  run city-$area --no-demo-scene --scene city:20000 --compute-raster $area
done
run city-64-no-occlusion --no-demo-scene --scene city:20000 --compute-raster 64 --no-occlusion
