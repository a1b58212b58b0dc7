#!/usr/bin/env bash
# Device run: what the deferred paths draw over their image with MSAA (blended surfaces,
# particles), three ways, alternated twice in one call:
#   before: the image expanded into every sample of a multisampled target, drawn over, resolved;
#   after-a: drawn into a transparent multisampled overlay, resolved by the render passes, laid
#            over the image by a compute kernel;
#   after-b: the same overlay resolved by that kernel instead (what was committed).
# The courtyard at MSAA 1, 4 and 8 and the city of 20,000 instances at MSAA 4, TBDR per-sample
# and visibility, 1080p, 4,096 lights.
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
versions="before after-a after-b"
for v in $versions; do xz -dc target-device/xtask-$v.xz > /tmp/xtask-$v && chmod +x /tmp/xtask-$v; done
/tmp/xtask-after-b info 2>&1 | head -5
common="--sizes 1920x1080 --tiles 16 --lights 4096 --paths tbdr-per-sample,visibility --scalarize off --frames 30 --warmup 8 --cell-budget 2"
res=/tmp/res; mkdir -p $res
for round in 1 2; do
  for v in $versions; do
    for scene in courtyard city; do
      case $scene in
        courtyard) extra="--msaa 1,4,8" ;;
        city) extra="--msaa 4 --no-demo-scene --scene city:20000" ;;
      esac
      /tmp/xtask-$v bench $common $extra --out /tmp/$v-$scene-$round 2>&1 | tail -1
      mkdir -p $res/$v-$scene-$round
      cp /tmp/$v-$scene-$round/bench.csv /tmp/$v-$scene-$round/bench.md $res/$v-$scene-$round/ 2>/dev/null
    done
  done
done
for v in before after-b; do
  /tmp/xtask-$v render --path visibility --msaa 4 --size 1920x1080 --lights 4096 \
    --out $res/courtyard-visibility-$v.png 2>&1 | tail -1
done
# The device returns a few files a call: one archive.
tar czf $OUT/results.tgz -C $res .
