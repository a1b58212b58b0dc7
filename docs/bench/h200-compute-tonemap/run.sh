#!/usr/bin/env bash
# Device run: the tonemap as a compute kernel and a copy into the target (the default) against
# the full-screen fragment pass (`--fragment-tonemap`), one binary, alternated twice in one call.
# The courtyard at MSAA 1, 4 and 8 on clustered forward, TBDR per-sample and visibility; the
# city of 20,000 instances and DamagedHelmet at MSAA 4 on visibility; 1080p, 4,096 lights.
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
xz -dc target-device/xtask.xz > /tmp/xtask && chmod +x /tmp/xtask
/tmp/xtask info 2>&1 | head -5
common="--sizes 1920x1080 --tiles 16 --lights 4096 --scalarize off --frames 30 --warmup 8 --cell-budget 2"
res=/tmp/res; mkdir -p $res
for round in 1 2; do
  for mode in compute fragment; do
    flag=""; [ $mode = fragment ] && flag="--fragment-tonemap"
    for scene in courtyard city helmet; do
      case $scene in
        courtyard) extra="--msaa 1,4,8 --paths clustered,tbdr-per-sample,visibility" ;;
        city) extra="--msaa 4 --paths visibility --no-demo-scene --scene city:20000" ;;
        helmet) extra="--msaa 4 --paths visibility --no-demo-scene --scene target-device/DamagedHelmet.glb" ;;
      esac
      /tmp/xtask bench $common $extra $flag --out /tmp/$mode-$scene-$round 2>&1 | tail -1
      mkdir -p $res/$mode-$scene-$round
      cp /tmp/$mode-$scene-$round/bench.csv /tmp/$mode-$scene-$round/bench.md $res/$mode-$scene-$round/ 2>/dev/null
    done
  done
done
/tmp/xtask render --path visibility --msaa 4 --size 1920x1080 --lights 4096 \
  --out $res/courtyard-visibility-compute-tonemap.png 2>&1 | tail -1
# The device returns a few files a call: one archive.
tar czf $OUT/results.tgz -C $res .
