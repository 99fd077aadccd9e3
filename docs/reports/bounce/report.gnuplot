set terminal pngcairo noenhanced size 1100,700
set output 'docs/reports/bounce/report.png'
set logscale xy
set grid
set key outside right
set format x '%.0e'
set format y '%.0e'
set xlabel 'wall time per simulated second [s]'
set ylabel 'error [m]'
set title 'error against run time: bounce.yaml'
plot 'docs/reports/bounce/report.dat' index 0 with linespoints title 'bullet bullet_si dt', 'docs/reports/bounce/report.dat' index 1 with linespoints title 'bullet bullet_si iterations', 'docs/reports/bounce/report.dat' index 2 with linespoints title 'bullet bullet_si substeps', 'docs/reports/bounce/report.dat' index 3 with linespoints title 'bullet bullet_si_nosplit dt', 'docs/reports/bounce/report.dat' index 4 with linespoints title 'bullet bullet_si_nosplit iterations', 'docs/reports/bounce/report.dat' index 5 with linespoints title 'bullet bullet_si_nosplit substeps', 'docs/reports/bounce/report.dat' index 6 with linespoints title 'tumble impulse dt', 'docs/reports/bounce/report.dat' index 7 with linespoints title 'tumble impulse iterations', 'docs/reports/bounce/report.dat' index 8 with linespoints title 'tumble impulse substeps', 'docs/reports/bounce/report.dat' index 9 with linespoints title 'tumble penalty dt', 'docs/reports/bounce/report.dat' index 10 with linespoints title 'tumble penalty iterations', 'docs/reports/bounce/report.dat' index 11 with linespoints title 'tumble penalty substeps'
