#!/usr/bin/env bash
# Device run: the depth buffer attached read-only by the passes that only test against it (the
# forward pass after a pre-pass, the G-buffer pass) against Load+Store (the overlay commit's
# binary), alternated twice in one call: courtyard at MSAA 1, 4 and 8, DamagedHelmet (carried in
# target-device/) and the city of 20,000 instances at MSAA 4; TBDR per-sample, visibility and
# clustered forward; 1080p, 4,096 lights.
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
versions="after-b after-c"
for v in $versions; do xz -dc target-device/xtask-$v.xz > /tmp/xtask-$v && chmod +x /tmp/xtask-$v; done
common="--sizes 1920x1080 --tiles 16 --lights 4096 --paths clustered,tbdr-per-sample,visibility --scalarize off --frames 30 --warmup 8 --cell-budget 2"
res=/tmp/res; mkdir -p $res
for round in 1 2; do
  for v in $versions; do
    for scene in courtyard helmet city; do
      case $scene in
        courtyard) extra="--msaa 1,4,8" ;;
        helmet) extra="--msaa 4 --no-demo-scene --scene target-device/DamagedHelmet.glb" ;;
        city) extra="--msaa 4 --no-demo-scene --scene city:20000" ;;
      esac
      /tmp/xtask-$v bench $common $extra --out /tmp/$v-$scene-$round 2>&1 | tail -1
      mkdir -p $res/$v-$scene-$round
      cp /tmp/$v-$scene-$round/bench.csv $res/$v-$scene-$round/ 2>/dev/null
    done
  done
done
tar czf $OUT/results.tgz -C $res .
