#!/usr/bin/env bash
# Device run: the compute rasteriser's workgroups list their large triangles' tiles together
# (an invocation a tile, not one invocation a triangle) and list empty the tiles a triangle
# cannot touch, and its triangles and tiles are timed as two graph passes (`compute raster`,
# `compute raster tiles`): `after` (this change) against `before` (21aa181). The `queue-*` CSVs
# are this script's run of an earlier build that also shaded a pixel's further triangles as a
# workgroup (`shading-queue.patch`, reverted: slower). Both binaries, both
# visibility paths, alternated twice in one call: the courtyard at MSAA 1, 4 and 8,
# DamagedHelmet and the city of 20,000 instances at MSAA 4; 1080p, 4,096 lights. Then the
# courtyard at MSAA 4 with the scalarized variants (`--scalarize on`), and both rasters' frames
# as images, new binary only.
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
for b in before after; do
  xz -dc target-device/xtask-$b.xz > /tmp/xtask-$b && chmod +x /tmp/xtask-$b
done
/tmp/xtask-after info 2>&1 | head -5
common="--sizes 1920x1080 --tiles 16 --lights 4096 --frames 30 --warmup 8 --cell-budget 2 --paths visibility,visibility-compute"
args() {
  case $1 in
    courtyard) echo "--msaa 1,4,8" ;;
    helmet) echo "--msaa 4 --no-demo-scene --scene target-device/DamagedHelmet.glb" ;;
    city) echo "--msaa 4 --no-demo-scene --scene city:20000" ;;
  esac
}
res=/tmp/res; mkdir -p $res
for round in 1 2; do
  for b in before after; do
    for scene in courtyard helmet city; do
      name=$b-$scene-$round
      /tmp/xtask-$b bench $common --scalarize off $(args $scene) --out /tmp/$name 2>&1 | tail -1
      mkdir -p $res/$name && cp /tmp/$name/bench.csv $res/$name/
    done
  done
done
/tmp/xtask-after bench $common --scalarize on --msaa 4 --out /tmp/scalarized 2>&1 | tail -1
mkdir -p $res/scalarized && cp /tmp/scalarized/bench.csv $res/scalarized/
for raster in hardware compute; do
  /tmp/xtask-after render --path visibility --vis-raster $raster --msaa 4 \
    --size 1920x1080 --lights 4096 --out $res/courtyard-$raster.png 2>&1 | tail -1
done
tar czf $OUT/results.tgz -C $res .
