#!/usr/bin/env bash
# Device run: the visibility shading kernels read each sample's ID and depth once (10b752d,
# built as 24c7449, the same tree before its commit message was amended)
# against before (6009364), alternated twice in one call: the courtyard at MSAA 1, 4 and 8,
# DamagedHelmet and the city of 20,000 instances at MSAA 4, on the visibility path; 1080p,
# 4,096 lights. Then, from an experimental build (`after` plus `experiment.patch`, not
# committed), the raster pass's depth clear timed as a pass of its own, and the compute
# rasteriser timed beside the hardware raster on DamagedHelmet.
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
for b in before after exp; do
  xz -dc target-device/xtask-$b.xz > /tmp/xtask-$b && chmod +x /tmp/xtask-$b
done
/tmp/xtask-after info 2>&1 | head -5
common="--sizes 1920x1080 --tiles 16 --lights 4096 --scalarize off --frames 30 --warmup 8 --cell-budget 2 --paths visibility"
args() {
  case $1 in
    courtyard) echo "--msaa 1,4,8" ;;
    helmet) echo "--msaa 4 --no-demo-scene --scene target-device/DamagedHelmet.glb" ;;
    city) echo "--msaa 4 --no-demo-scene --scene city:20000" ;;
  esac
}
res=/tmp/res; mkdir -p $res
run() { # binary, scene, name, extra...
  local b=$1 scene=$2 name=$3; shift 3
  /tmp/xtask-$b bench $common $(args $scene) "$@" --out /tmp/$name 2>&1 | tail -1
  mkdir -p $res/$name && cp /tmp/$name/bench.csv $res/$name/
}
for round in 1 2; do
  for b in before after; do
    for scene in courtyard helmet city; do run $b $scene $b-$scene-$round; done
  done
done
for scene in courtyard helmet city; do
  EXP_DEPTH_CLEAR_PASS=1 run exp $scene exp-depth-clear-$scene
done
run exp helmet exp-compute-raster-helmet --compute-raster 64
tar czf $OUT/results.tgz -C $res .
