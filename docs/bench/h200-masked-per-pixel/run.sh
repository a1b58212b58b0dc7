#!/usr/bin/env bash
# Device run: under the compute rasteriser the alpha-masked draws' fragment stage runs once a
# pixel (the alpha test at the centre, then each covered sample's depth on the triangle's
# plane) instead of once a sample: `after` (this change) against `before` (88e6b37, the culled
# compute rasteriser). Both binaries, the compute rasteriser's visibility path, alternated twice
# in one call: the city of 20,000 instances at MSAA 1 and 4, the courtyard at MSAA 4 and 8,
# DamagedHelmet at MSAA 4; 1080p, 4,096 lights. Then the city's and the courtyard's frames of
# the new binary as images, its default raster (auto).
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
    courtyard) echo "--msaa 4,8" ;;
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
/tmp/xtask-after render --path visibility --msaa 4 --scene city:20000 \
  --size 1920x1080 --lights 4096 --out $res/city-auto.png 2>&1 | tail -1
/tmp/xtask-after render --path visibility --msaa 4 \
  --size 1920x1080 --lights 4096 --out $res/courtyard-auto.png 2>&1 | tail -1
tar czf $OUT/results.tgz -C $res .
