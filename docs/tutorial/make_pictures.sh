#!/usr/bin/env bash
# Re-makes every picture of docs/tutorial.md with the pipeline itself: varsph sample / run on the tutorial
# scene, postprocess.py, the state scripts and the ParaView GUI started by `varsph paraview` (under Xvfb).
# About 10 minutes on 2 idle cores (two 1 s runs of 3100 particles). Runs go to runs/tutorial/.
set -euo pipefail
cd "$(dirname "$0")/../.."
V=./build/release/bin/varsph
T=docs/tutorial
R=runs/tutorial
X=(xvfb-run -a -s "-noreset -screen 0 1280x1024x24")
mkdir -p "$R"
$V sample $T/dam_break_mesh_2d.json -o $R/sample --overwrite
$V run $T/dam_break_mesh_2d.json -o $R/verlet --overwrite --quiet
$V run $T/dam_break_mesh_2d.json -o $R/symplectic --set integrator.type=symplectic_euler --set time.end=0.8 \
  --overwrite --quiet
"${X[@]}" pvpython paraview/states/free_surface.py $R/sample --screenshot $T/sample.png --size 1000,560
"${X[@]}" pvpython paraview/postprocess.py $R/verlet --compare $R/symplectic --times 0.2,0.4,0.6
"${X[@]}" pvpython paraview/states/free_surface.py $R/verlet --time 0.4 --surface --screenshot $T/free_surface.png \
  --size 1000,560
pvpython $T/gui_window.py $V $R/verlet --state pressure -o $T/gui_window.png
for f in probes_pressure.png front_dimensionless.png momentum_Q.png deviation.png pressure_smoothed_t0.4.png \
         deviation_t0.8.png; do    # the pictures docs/tutorial.md shows
  cp $R/verlet/post/$f $T/$f
done
cat $R/verlet/post/scene_diff.txt   # quoted in docs/tutorial.md
# part 2: your own mesh in 3D (about 30 s)
$V sample $T/torus_3d.json -o $R/torus_sample --overwrite     # per-body counts and boxes quoted in docs/tutorial.md
$V run $T/torus_3d.json -o $R/torus --overwrite --quiet --threads 1
"${X[@]}" pvpython paraview/states/free_surface.py $R/torus_sample --screenshot $T/torus_sample.png --size 1000,600
"${X[@]}" pvpython paraview/states/pressure.py $R/torus --time 0.3 --screenshot $T/torus_pressure_t0.3.png \
  --size 1000,600
echo "pictures in $T/"
