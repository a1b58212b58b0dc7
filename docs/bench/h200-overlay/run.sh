#!/usr/bin/env bash
# Device run: the deferred paths before (the deferred image expanded into every sample of a
# multisampled target for the blended surfaces and particles, then resolved again) and after
# (those drawn into a transparent overlay, resolved, and laid over the image by the `overlay`
# pass), alternated twice, on the courtyard at MSAA 1, 4 and 8 and the city of 20,000 instances
# at MSAA 4, TBDR per-sample and visibility.
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
for v in before after; do xz -dc target-device/xtask-$v.xz > /tmp/xtask-$v && chmod +x /tmp/xtask-$v; done
/tmp/xtask-after info 2>&1 | head -5
common="--sizes 1920x1080 --tiles 16 --lights 4096 --paths tbdr-per-sample,visibility --scalarize off --frames 30 --warmup 8 --cell-budget 2"
for round in 1 2; do
  for v in before after; do
    for scene in courtyard city; do
      case $scene in
        courtyard) extra="--msaa 1,4,8" ;;
        city) extra="--msaa 4 --no-demo-scene --scene city:20000" ;;
      esac
      /tmp/xtask-$v bench $common $extra --out /tmp/$v-$scene-$round 2>&1 | tail -3
      mkdir -p $OUT/$v-$scene-$round
      cp /tmp/$v-$scene-$round/bench.csv /tmp/$v-$scene-$round/bench.md $OUT/$v-$scene-$round/ 2>/dev/null
    done
  done
done
/tmp/xtask-after render --path visibility --msaa 4 --size 1920x1080 --lights 4096 \
  --out $OUT/courtyard-visibility-after.png 2>&1 | tail -2
/tmp/xtask-before render --path visibility --msaa 4 --size 1920x1080 --lights 4096 \
  --out $OUT/courtyard-visibility-before.png 2>&1 | tail -2
