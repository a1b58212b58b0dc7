#!/usr/bin/env bash
# Device run: the compute rasteriser's late half dispatches its triangles indirectly, from
# occlusion culling's counters (no workgroup where the second phase drew nothing new), against
# a direct dispatch of every chunk: `after` (this change) against `before` (ac536f2). Both
# binaries, the compute rasteriser's visibility path, alternated twice in one call: the city of
# 20,000 instances at MSAA 1 and 4 (occlusion culling runs), the courtyard at MSAA 4 (it does
# not); 1080p, 4,096 lights.
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
for b in before after; do
  xz -dc target-device/xtask-$b.xz > /tmp/xtask-$b && chmod +x /tmp/xtask-$b
done
/tmp/xtask-after info 2>&1 | head -5
common="--sizes 1920x1080 --tiles 16 --lights 4096 --frames 30 --warmup 8 --cell-budget 2 --scalarize off --paths visibility-compute"
args() {
  case $1 in
    city) echo "--msaa 1,4 --no-demo-scene --scene city:20000" ;;
    courtyard) echo "--msaa 4" ;;
  esac
}
res=/tmp/res; mkdir -p $res
# A throw-away cell first: the first configuration of a call runs with the clocks still low.
/tmp/xtask-after bench $common --msaa 4 --out /tmp/warm 2>&1 | tail -1
for round in 1 2; do
  for b in before after; do
    for scene in city courtyard; do
      name=$b-$scene-$round
      /tmp/xtask-$b bench $common $(args $scene) --out /tmp/$name 2>&1 | tail -1
      mkdir -p $res/$name && cp /tmp/$name/bench.csv $res/$name/
    done
  done
done
/tmp/xtask-after render --path visibility --msaa 4 --scene city:20000 \
  --size 1920x1080 --lights 4096 --out $res/city.png 2>&1 | tail -1
tar czf $OUT/results.tgz -C $res .
