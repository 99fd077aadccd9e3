# Figures of docs/stability.md; `dir` holds the series of stability_series.py.
set terminal pngcairo size 900,420 font "DejaVu Sans,10"
set grid
set key top right

set output "docs/stability-tower.png"
set multiplot layout 1,2 title "20-box tower, dt = 1/60, 30 s"
set xlabel "time [s]"
set ylabel "top box height change [mm]"
plot dir."/tower_impulse.dat" using 1:2 with lines lw 2 title "impulse (soft step, 16 substeps, 240 Hz)", \
     dir."/tower_penalty.dat" using 1:2 with lines lw 2 title "penalty (k = 1e6 N/m, implicit)"
set ylabel "total energy - initial [J]"
plot dir."/tower_impulse.dat" using 1:3 with lines lw 2 title "impulse", \
     dir."/tower_penalty.dat" using 1:3 with lines lw 2 title "penalty"
unset multiplot

set output "docs/stability-penalty-stacks.png"
set multiplot layout 1,2 title "5-box penalty stacks at dt = 1/60: top box height change"
set ylabel "[mm]"
set key bottom right
plot dir."/stack_1e5.dat" using 1:2 with lines lw 2 title "k = 1e5 N/m", \
     dir."/stack_1e7.dat" using 1:2 with lines lw 2 title "k = 1e7 N/m", \
     dir."/stack_1e9.dat" using 1:2 with lines lw 2 title "k = 1e9 N/m"
set logscale y
set format y "10^{%L}"
set yrange [1e-5:10]
set ylabel "sag |change| [mm], log; dashed: theory 15 m g / k"
plot dir."/stack_1e5.dat" using 1:(abs($2)) with lines lw 2 title "k = 1e5 N/m", \
     dir."/stack_1e7.dat" using 1:(abs($2)) with lines lw 2 title "k = 1e7 N/m", \
     dir."/stack_1e9.dat" using 1:(abs($2)) with lines lw 2 title "k = 1e9 N/m", \
     15 * 9.81e3 / 1e5 with lines dt 2 lc 0 notitle, 15 * 9.81e3 / 1e7 with lines dt 2 lc 0 notitle, \
     15 * 9.81e3 / 1e9 with lines dt 2 lc 0 notitle
unset logscale y
set format y "%g"
set autoscale y
unset multiplot

set key top right
set output "docs/stability-bounce.png"
set multiplot layout 1,1 title "Ball dropped from 2 m, e = 0.8, dt = 1/30"
set ylabel "height of the ball's bottom [m]"
plot dir."/bounce_impulse.dat" using 1:2 with lines lw 2 title "impulse (restitution e = 0.8)", \
     dir."/bounce_penalty.dat" using 1:2 with lines lw 2 title "penalty (k = 1e6, c = 0: implicit damping only)"
unset multiplot
