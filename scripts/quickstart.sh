#!/usr/bin/env bash
# Installs the dependencies, builds, runs the default scene (the seed paper's 2D dam break) and
# renders pictures and tables with pvpython into runs/dam_break_2d_paper/post/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh varsph   # the command alone; tests and benchmarks build in scripts/test.sh
run=runs/dam_break_2d_paper
./build/release/bin/varsph run pipelines/dam_break_2d_paper.json -o "$run" --overwrite
if [ -f paraview/postprocess.py ]; then
  xvfb-run -a -s -noreset pvpython paraview/postprocess.py "$run"
fi
echo
echo "Pictures and tables are in $run/post/. Open the run in ParaView (plugin loaded, a state shown):"
echo "  ./build/release/bin/varsph paraview $run [--state free_surface|pressure]"
