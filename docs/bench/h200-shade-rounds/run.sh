#!/usr/bin/env bash
# Device run, three release binaries of the compute rasteriser's visibility path:
# - `before`: 98dce4d, the tonemap copied into the sRGB target;
# - `target`: the sRGB target stored as Rgba8Unorm, written by the tonemap kernel without a copy;
# - `rounds`: that, and the shading kernel shading each pixel's k-th distinct ID in round k;
# - `glass-flat` (an experiment, not committed): `rounds` with the blended fragment's shading
#   replaced by a constant colour, to see what the glass costs beyond its raster.
# `target` and `rounds` alternated twice; `before` and `glass-flat` once. The courtyard at MSAA
# 1, 4 and 8, DamagedHelmet at MSAA 4, the city of 20,000 instances at MSAA 1 and 4; 1080p,
# 4,096 lights. Then the courtyard's frame at MSAA 4 from `rounds`, as an image.
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
for b in before target rounds glass-flat; do
  xz -dc target-device/xtask-$b.xz > /tmp/xtask-$b && chmod +x /tmp/xtask-$b
done
/tmp/xtask-rounds info 2>&1 | head -5
common="--sizes 1920x1080 --tiles 16 --lights 4096 --frames 30 --warmup 8 --cell-budget 2 --scalarize off --paths visibility-compute"
args() {
  case $1 in
    courtyard) echo "--msaa 1,4,8" ;;
    helmet) echo "--msaa 4 --no-demo-scene --scene target-device/DamagedHelmet.glb" ;;
    city) echo "--msaa 1,4 --no-demo-scene --scene city:20000" ;;
  esac
}
res=/tmp/res; mkdir -p $res
run() { # binary scene round
  name=$1-$2-$3
  /tmp/xtask-$1 bench $common $(args $2) --out /tmp/$name 2>&1 | tail -1
  mkdir -p $res/$name && cp /tmp/$name/bench.csv $res/$name/
}
# A throw-away cell first: the first configuration of a call runs with the clocks still low.
/tmp/xtask-rounds bench $common --msaa 4 --out /tmp/warm 2>&1 | tail -1
for scene in courtyard helmet city; do run before $scene 1; done
for round in 1 2; do
  for b in target rounds; do
    for scene in courtyard helmet city; do run $b $scene $round; done
  done
done
run glass-flat courtyard 1
/tmp/xtask-rounds render --path visibility --msaa 4 --size 1920x1080 --lights 4096 \
  --out $res/courtyard-rounds.png 2>&1 | tail -1
tar czf $OUT/results.tgz -C $res .
