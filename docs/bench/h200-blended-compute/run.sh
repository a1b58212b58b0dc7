#!/usr/bin/env bash
# Device run: the blended surfaces over the compute rasteriser's frame lit in compute (a
# listing pass appends each fragment in front of the opaque surface to its pixel's list, a
# kernel lights every listed fragment, the forward pass outputs the listed colours and the
# hardware blends them, the forward pass's pipeline picked on the GPU) against lit in the
# forward pass's fragment stage: `blended` (this change) against `base` (1d56634, the build of
# docs/bench/h200-triangle-directory),
# alternated twice in one call, the compute rasteriser's frame: the courtyard at MSAA 1, 4 and
# 8, DamagedHelmet at MSAA 4 (nothing blended), the city of 20,000 instances at MSAA 1 and 4;
# 1080p, 4,096 lights.
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
xz -dc target-device/xtask-1d56634.xz > /tmp/xtask-base && chmod +x /tmp/xtask-base
xz -dc target-device/xtask-blended.xz > /tmp/xtask-blended && chmod +x /tmp/xtask-blended
/tmp/xtask-blended info 2>&1 | head -5
common="--sizes 1920x1080 --tiles 16 --lights 4096 --frames 30 --warmup 8 --cell-budget 2 --scalarize off --paths visibility-compute"
args() {
  case $1 in
    courtyard) echo "--msaa 1,4,8" ;;
    helmet) echo "--msaa 4 --no-demo-scene --scene target-device/DamagedHelmet.glb" ;;
    city) echo "--msaa 1,4 --no-demo-scene --scene city:20000" ;;
  esac
}
res=/tmp/res; mkdir -p $res
# A throw-away cell first: the first configuration of a call runs with the clocks still low.
/tmp/xtask-blended bench $common --msaa 4 --out /tmp/warm 2>&1 | tail -1
for round in 1 2; do
  for b in base blended; do
    for scene in courtyard helmet city; do
      name=$b-$scene-$round
      /tmp/xtask-$b bench $common $(args $scene) --out /tmp/$name 2>&1 | tail -1
      mkdir -p $res/$name && cp /tmp/$name/bench.csv $res/$name/
    done
  done
done
tar czf $OUT/results.tgz -C $res .
