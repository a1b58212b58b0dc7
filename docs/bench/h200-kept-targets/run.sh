#!/usr/bin/env bash
# Device run: the visibility path's ID target loaded instead of cleared, and the overlay of
# blended surfaces and particles kept between frames and erased by its drawers instead of
# cleared. Two binaries, `before` (a6c855f) and `after` (this change), alternated twice in one
# call. The courtyard at MSAA 1, 4 and 8 on TBDR per-sample and visibility; DamagedHelmet and
# the city of 20,000 instances at MSAA 4; 1080p, 4,096 lights.
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
for b in before after; do
  xz -dc target-device/xtask-$b.xz > /tmp/xtask-$b && chmod +x /tmp/xtask-$b
done
/tmp/xtask-after info 2>&1 | head -5
common="--sizes 1920x1080 --tiles 16 --lights 4096 --scalarize off --frames 30 --warmup 8 --cell-budget 2"
res=/tmp/res; mkdir -p $res
for round in 1 2; do
  for b in before after; do
    for scene in courtyard helmet city; do
      case $scene in
        courtyard) extra="--msaa 1,4,8 --paths tbdr-per-sample,visibility" ;;
        helmet) extra="--msaa 4 --paths tbdr-per-sample,visibility --no-demo-scene --scene target-device/DamagedHelmet.glb" ;;
        city) extra="--msaa 4 --paths visibility --no-demo-scene --scene city:20000" ;;
      esac
      /tmp/xtask-$b bench $common $extra --out /tmp/$b-$scene-$round 2>&1 | tail -1
      mkdir -p $res/$b-$scene-$round
      cp /tmp/$b-$scene-$round/bench.csv $res/$b-$scene-$round/
    done
  done
done
/tmp/xtask-after render --path visibility --msaa 4 --size 1920x1080 --lights 4096 \
  --out $res/courtyard-visibility.png 2>&1 | tail -1
tar czf $OUT/results.tgz -C $res .
