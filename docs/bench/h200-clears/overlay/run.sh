#!/usr/bin/env bash
# Experiment (not committed code): what the visibility path's blended-surface pass costs at
# MSAA 4/8 on the courtyard: as is; the overlay loaded instead of cleared; no blended draws.
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
xz -dc target-device/xtask-exp.xz > /tmp/xtask && chmod +x /tmp/xtask
common="--sizes 1920x1080 --tiles 16 --lights 4096 --scalarize off --frames 30 --warmup 8 --cell-budget 2 --msaa 1,4,8 --paths visibility,tbdr-per-sample"
res=/tmp/res; mkdir -p $res
for round in 1 2; do
  for mode in asis load nodraws both; do
    case $mode in
      asis) env="" ;;
      load) env="EXP_OVERLAY_LOAD=1" ;;
      nodraws) env="EXP_NO_DRAWS=1" ;;
      both) env="EXP_OVERLAY_LOAD=1 EXP_NO_DRAWS=1" ;;
    esac
    env $env /tmp/xtask bench $common --out /tmp/$mode-$round 2>&1 | tail -1
    mkdir -p $res/$mode-$round; cp /tmp/$mode-$round/bench.csv $res/$mode-$round/
  done
done
tar czf $OUT/results.tgz -C $res .
