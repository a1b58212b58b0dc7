#!/usr/bin/env bash
# Device run: the whole table of issue 39 for this session's final build (`rounds` of
# docs/bench/h200-shade-rounds: the tonemap writing the sRGB target without a copy, the shading
# kernel by rounds), both visibility rasters in one call, twice: the courtyard at MSAA 1, 4 and
# 8, DamagedHelmet at MSAA 4, the city of 20,000 instances at MSAA 1 and 4; 1080p, 4,096 lights.
# Then the compute rasteriser's frame on the courtyard and the city at MSAA 4 with each light
# culling dispatch timed on its own (`--cull-dispatch-times`), to see what bounds light culling.
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
xz -dc target-device/xtask-rounds.xz > /tmp/xtask && chmod +x /tmp/xtask
/tmp/xtask info 2>&1 | head -5
common="--sizes 1920x1080 --tiles 16 --lights 4096 --frames 30 --warmup 8 --cell-budget 2 --scalarize off"
args() {
  case $1 in
    courtyard) echo "--msaa 1,4,8" ;;
    helmet) echo "--msaa 4 --no-demo-scene --scene target-device/DamagedHelmet.glb" ;;
    city) echo "--msaa 1,4 --no-demo-scene --scene city:20000" ;;
  esac
}
res=/tmp/res; mkdir -p $res
# A throw-away cell first: the first configuration of a call runs with the clocks still low.
/tmp/xtask bench $common --paths visibility-compute --msaa 4 --out /tmp/warm 2>&1 | tail -1
for round in 1 2; do
  for scene in courtyard helmet city; do
    name=$scene-$round
    /tmp/xtask bench $common --paths visibility,visibility-compute $(args $scene) \
      --out /tmp/$name 2>&1 | tail -1
    mkdir -p $res/$name && cp /tmp/$name/bench.csv $res/$name/
  done
done
for scene in courtyard city; do
  extra="--msaa 4"; [ $scene = city ] && extra="--msaa 4 --no-demo-scene --scene city:20000"
  /tmp/xtask bench $common --paths visibility-compute $extra --cull-dispatch-times \
    --out /tmp/cull-$scene 2>&1 | tail -1
  mkdir -p $res/cull-$scene && cp /tmp/cull-$scene/bench.csv $res/cull-$scene/
done
tar czf $OUT/results.tgz -C $res .
