#!/usr/bin/env bash
# Device run: the compute rasteriser rasterises only the slots scene culling keeps, once for each
# half of occlusion culling, as the hardware raster draws them: `after` (this change) against
# `before` (e0139bc, which rasterised every opaque triangle in the first half). Both binaries,
# the compute rasteriser's visibility path, alternated twice in one call: the city of 20,000
# instances at MSAA 1 and 4, the courtyard at MSAA 4 and DamagedHelmet at MSAA 4; 1080p, 4,096
# lights. Then the hardware raster's frame of the new binary on each scene, for the table, and
# the city's frames of both rasters as images.
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
for b in before after; do
  xz -dc target-device/xtask-$b.xz > /tmp/xtask-$b && chmod +x /tmp/xtask-$b
done
/tmp/xtask-after info 2>&1 | head -5
common="--sizes 1920x1080 --tiles 16 --lights 4096 --frames 30 --warmup 8 --cell-budget 2 --scalarize off"
args() {
  case $1 in
    city) echo "--msaa 1,4 --no-demo-scene --scene city:20000" ;;
    courtyard) echo "--msaa 4" ;;
    helmet) echo "--msaa 4 --no-demo-scene --scene target-device/DamagedHelmet.glb" ;;
  esac
}
res=/tmp/res; mkdir -p $res
# A throw-away cell first: the first configuration of a call runs with the clocks still low.
/tmp/xtask-after bench $common --paths visibility-compute --msaa 4 --out /tmp/warm 2>&1 | tail -1
for round in 1 2; do
  for b in before after; do
    for scene in city courtyard helmet; do
      name=$b-$scene-$round
      /tmp/xtask-$b bench $common --paths visibility-compute $(args $scene) --out /tmp/$name 2>&1 | tail -1
      mkdir -p $res/$name && cp /tmp/$name/bench.csv $res/$name/
    done
  done
done
for scene in city courtyard helmet; do
  name=hardware-$scene
  /tmp/xtask-after bench $common --paths visibility $(args $scene) --out /tmp/$name 2>&1 | tail -1
  mkdir -p $res/$name && cp /tmp/$name/bench.csv $res/$name/
done
for raster in hardware compute; do
  /tmp/xtask-after render --path visibility --vis-raster $raster --msaa 4 --scene city:20000 \
    --size 1920x1080 --lights 4096 --out $res/city-$raster.png 2>&1 | tail -1
done
tar czf $OUT/results.tgz -C $res .
