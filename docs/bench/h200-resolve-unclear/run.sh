#!/usr/bin/env bash
# Device run: the compute rasteriser's depth resolve writing every sample (1.0 where no
# triangle) over a loaded depth target, instead of clearing the target and discarding the
# empty samples. `mid` (50389bc) against `after` (this change), alternated twice in one call,
# both visibility paths: the courtyard at MSAA 1, 4 and 8 and the city of 20,000 instances at
# MSAA 4; 1080p, 4,096 lights.
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
for b in mid after; do
  xz -dc target-device/xtask-$b.xz > /tmp/xtask-$b && chmod +x /tmp/xtask-$b
done
common="--sizes 1920x1080 --tiles 16 --lights 4096 --scalarize off --frames 30 --warmup 8 --cell-budget 2 --paths visibility,visibility-compute"
res=/tmp/res; mkdir -p $res
for round in 1 2; do
  for b in mid after; do
    for scene in courtyard city; do
      case $scene in
        courtyard) extra="--msaa 1,4,8" ;;
        city) extra="--msaa 4 --no-demo-scene --scene city:20000" ;;
      esac
      name=$b-$scene-$round
      /tmp/xtask-$b bench $common $extra --out /tmp/$name 2>&1 | tail -1
      mkdir -p $res/$name && cp /tmp/$name/bench.csv $res/$name/
    done
  done
done
/tmp/xtask-after render --path visibility --vis-raster compute --msaa 4 --size 1920x1080 \
  --lights 4096 --out $res/courtyard-compute.png 2>&1 | tail -1
tar czf $OUT/results.tgz -C $res .
