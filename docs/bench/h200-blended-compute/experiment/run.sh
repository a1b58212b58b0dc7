# The experiment of part 12 (BENCHMARKS.md): `blendlist` (the first design, whose one blended
# pipeline's fragment stage output a fragment's record or shaded it itself) against
# `nofallback` (the same build with that fragment stage discarding a fragment without a
# record instead of shading it: wrong where the records run out, built only to measure what
# the shading branch costs the stage). Courtyard, MSAA 1 and 4, alternated twice.
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
for b in blendlist nofallback; do xz -dc target-device/xtask-$b.xz > /tmp/xtask-$b && chmod +x /tmp/xtask-$b; done
common="--sizes 1920x1080 --tiles 16 --lights 4096 --frames 30 --warmup 8 --cell-budget 2 --scalarize off --paths visibility-compute"
res=/tmp/res; mkdir -p $res
/tmp/xtask-blendlist bench $common --msaa 4 --out /tmp/warm 2>&1 | tail -1
for round in 1 2; do for b in blendlist nofallback; do
  /tmp/xtask-$b bench $common --msaa 1,4 --out /tmp/$b-courtyard-$round 2>&1 | tail -1
  mkdir -p $res/$b-courtyard-$round && cp /tmp/$b-courtyard-$round/bench.csv $res/$b-courtyard-$round/
done; done
tar czf $OUT/results.tgz -C $res .
