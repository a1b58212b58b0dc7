#!/usr/bin/env bash
# Device run: the visibility path before this session's changes (the last session's binary) and
# after (one kernel per material program, the pixel sums, GpuMaterial.program), alternated, on
# the courtyard and the city of 20,000 instances, beside TBDR per-sample.
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
for v in before after; do xz -dc target-device/xtask-$v.xz > /tmp/xtask-$v && chmod +x /tmp/xtask-$v; done
/tmp/xtask-after info 2>&1 | head -5
common="--sizes 1920x1080 --tiles 16 --msaa 1,4 --lights 4096 --paths tbdr-per-sample,visibility --scalarize off --frames 30 --warmup 8 --cell-budget 2 --scene city:20000"
for round in 1 2; do
  for v in before after; do
    /tmp/xtask-$v bench $common --out /tmp/$v-$round 2>&1 | tail -12
    mkdir -p $OUT/$v-$round
    cp /tmp/$v-$round/bench.csv /tmp/$v-$round/bench.md $OUT/$v-$round/ 2>/dev/null
  done
done
