#!/usr/bin/env bash
# Experiment (not committed code): what the visibility raster pass's clears cost (IDs loaded,
# depth loaded, both), and the overlay clear skipped on top; courtyard, MSAA 1/4/8.
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
xz -dc target-device/xtask-exp.xz > /tmp/xtask && chmod +x /tmp/xtask
common="--sizes 1920x1080 --tiles 16 --lights 4096 --scalarize off --frames 30 --warmup 8 --cell-budget 2 --msaa 1,4,8 --paths visibility"
res=/tmp/res; mkdir -p $res
for round in 1 2; do
  for mode in asis ids depth idsdepth; do
    case $mode in
      asis) env="" ;;
      ids) env="EXP_IDS_LOAD=1" ;;
      depth) env="EXP_DEPTH_LOAD=1" ;;
      idsdepth) env="EXP_IDS_LOAD=1 EXP_DEPTH_LOAD=1" ;;
    esac
    env $env /tmp/xtask bench $common --out /tmp/$mode-$round 2>&1 | tail -1
    for scene in city; do
      env $env /tmp/xtask bench $common --no-demo-scene --scene city:20000 --out /tmp/$mode-city-$round 2>&1 | tail -1
    done
    mkdir -p $res/$mode-$round $res/$mode-city-$round; cp /tmp/$mode-$round/bench.csv $res/$mode-$round/; cp /tmp/$mode-city-$round/bench.csv $res/$mode-city-$round/
  done
done
tar czf $OUT/results.tgz -C $res .
