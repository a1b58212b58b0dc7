#!/usr/bin/env bash
# Device run: the visibility path with the hardware raster and with the compute raster
# (`visibility-compute`: compute kernels, then the full-screen resolve into the depth and
# visibility buffers, masked draws on the hardware), whole frames in the same run, on the
# courtyard and the city of 20,000 instances at MSAA 1, 4 and 8; and one frame of each
# rendered to PNG.
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
xz -dc target-device/xtask-after.xz > /tmp/xtask && chmod +x /tmp/xtask
/tmp/xtask info 2>&1 | head -14
common="--sizes 1920x1080 --tiles 16 --msaa 1,4,8 --lights 4096 --paths visibility,visibility-compute --scalarize off --frames 30 --warmup 8 --cell-budget 2"
run() {
  name=$1; shift
  /tmp/xtask bench $common "$@" --out /tmp/$name 2>&1 | tail -4
  mkdir -p $OUT/$name
  cp /tmp/$name/bench.csv /tmp/$name/bench.md $OUT/$name/ 2>/dev/null
}
run courtyard
run city --no-demo-scene --scene city:20000
for r in hardware compute; do
  /tmp/xtask render --path visibility --vis-raster $r --msaa 4 --size 1920x1080 --lights 4096 \
    --out $OUT/courtyard-$r.png 2>&1 | tail -3
done
