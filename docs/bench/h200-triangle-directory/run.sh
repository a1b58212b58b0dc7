#!/usr/bin/env bash
# Device run: the shading kernel finds a triangle ID's draw through the triangle directory (a
# record a block of 256 IDs naming the draw where the block starts, so the binary search runs
# over the draws of one block) against a binary search over every draw: `directory` (this
# change) against `rounds` (the build of docs/bench/h200-shade-rounds, the one before it),
# alternated twice in one call, the compute rasteriser's frame: the courtyard at MSAA 1, 4 and
# 8, DamagedHelmet at MSAA 4, the city of 20,000 instances at MSAA 1 and 4; 1080p, 4,096 lights.
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
for b in rounds directory; do
  xz -dc target-device/xtask-$b.xz > /tmp/xtask-$b && chmod +x /tmp/xtask-$b
done
/tmp/xtask-directory info 2>&1 | head -5
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
/tmp/xtask-directory bench $common --msaa 4 --out /tmp/warm 2>&1 | tail -1
for round in 1 2; do
  for b in rounds directory; do
    for scene in courtyard helmet city; do
      name=$b-$scene-$round
      /tmp/xtask-$b bench $common $(args $scene) --out /tmp/$name 2>&1 | tail -1
      mkdir -p $res/$name && cp /tmp/$name/bench.csv $res/$name/
    done
  done
done
tar czf $OUT/results.tgz -C $res .
