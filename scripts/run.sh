#!/usr/bin/env bash
# The main job: install what is needed, build, and run the studio on the bundled sample.
# Without a display it runs the command-line pipeline on the same sample instead.
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER_LAUNCHER=ccache
cmake --build build

sample=resources/sample/cmu_01_01_excerpt.bvh
if [ -n "${DISPLAY:-}${WAYLAND_DISPLAY:-}" ]; then
  exec build/bin/motionlod-studio --sample
fi

echo "== no display: the command-line pipeline on $sample"
build/bin/motionlod --version
build/bin/motionlod info "$sample" --unit-scale cmu
build/bin/motionlod simplify "$sample" --unit-scale cmu --threshold 5,50,100,300
