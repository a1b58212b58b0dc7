#!/usr/bin/env bash
# Device run: the committed code (G-buffer loaded, compute tonemap), twice in one call:
# TBDR per-sample and visibility on the courtyard at MSAA 1/4/8 and DamagedHelmet at MSAA 4;
# 1080p, 4,096 lights.
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
xz -dc target-device/xtask.xz > /tmp/xtask && chmod +x /tmp/xtask
common="--sizes 1920x1080 --tiles 16 --lights 4096 --scalarize off --frames 30 --warmup 8 --cell-budget 2 --paths tbdr-per-sample,visibility"
res=/tmp/res; mkdir -p $res
for round in 1 2; do
  /tmp/xtask bench $common --msaa 1,4,8 --out /tmp/court-$round 2>&1 | tail -1
  /tmp/xtask bench $common --msaa 4 --no-demo-scene --scene target-device/DamagedHelmet.glb --out /tmp/helmet-$round 2>&1 | tail -1
  for s in court helmet; do mkdir -p $res/$s-$round; cp /tmp/$s-$round/bench.csv $res/$s-$round/; done
done
tar czf $OUT/results.tgz -C $res .
