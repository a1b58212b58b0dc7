#!/usr/bin/env bash
# Experiment (not committed code): what clearing the G-buffer costs TBDR per-sample and the
# deferred path; courtyard MSAA 1/4/8, DamagedHelmet MSAA 4.
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
xz -dc target-device/xtask-exp.xz > /tmp/xtask && chmod +x /tmp/xtask
common="--sizes 1920x1080 --tiles 16 --lights 4096 --scalarize off --frames 30 --warmup 8 --cell-budget 2 --paths tbdr-per-sample,deferred"
res=/tmp/res; mkdir -p $res
for round in 1 2; do
  for mode in asis gbuf; do
    env=""; [ $mode = gbuf ] && env="EXP_GBUFFER_LOAD=1"
    env $env /tmp/xtask bench $common --msaa 1,4,8 --out /tmp/$mode-court-$round 2>&1 | tail -1
    env $env /tmp/xtask bench $common --msaa 4 --no-demo-scene --scene target-device/DamagedHelmet.glb --out /tmp/$mode-helmet-$round 2>&1 | tail -1
    for s in court helmet; do mkdir -p $res/$mode-$s-$round; cp /tmp/$mode-$s-$round/bench.csv $res/$mode-$s-$round/; done
  done
done
tar czf $OUT/results.tgz -C $res .
