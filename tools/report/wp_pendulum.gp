# Draws wp_pendulum.svg and wp_pendulum.png from the CSV files beside it: gnuplot wp_pendulum.gp
set datafile separator ','
set terminal svg size 900,560 dynamic font 'sans,12'
set output 'wp_pendulum.svg'
max(a, b) = a > b ? a : b
floor_error = 1e-12
set title 'pendulum: 1 kg ball on a point joint 1 m below an anchor, from 5 degrees, 10 s (quick: 6 s)' noenhanced
set xlabel 'cost: wall-clock ms per simulated second'
set ylabel 'error: relative error of the period'
set logscale xy
set format y '10^{%L}'
set key outside right noenhanced
set grid
set label 1 'dt in {1/30 .. 1/240} x iterations in {1, 2, 4, 8, 16, 32}; errors below 1e-12 drawn at 1e-12' at graph 0, graph -0.13 font ',9'
set bmargin 6
plot 'wp_pendulum.csv' using (strcol(1) eq 'standard' ? $4 : NaN):(max($5, floor_error)) with points pt 5 ps 1.2 title 'standard', \
     'wp_pendulum.csv' using (strcol(1) eq 'standard+shock' ? $4 : NaN):(max($5, floor_error)) with points pt 6 ps 1.2 title 'standard+shock', \
     'wp_pendulum.csv' using (strcol(1) eq 'guendelman' ? $4 : NaN):(max($5, floor_error)) with points pt 7 ps 1.2 title 'guendelman', \
     'wp_pendulum.csv' using (strcol(1) eq 'guendelman+shock' ? $4 : NaN):(max($5, floor_error)) with points pt 8 ps 1.2 title 'guendelman+shock', \
     'wp_pendulum.csv' using (strcol(1) eq 'bullet' ? $4 : NaN):(max($5, floor_error)) with points pt 9 ps 1.2 title 'bullet', \
     'wp_pendulum_front.csv' using 1:(max($2, floor_error)) with lines lw 2 lc 'black' title 'Pareto front', \
     'wp_pendulum_front.csv' using 1:(max($2, floor_error)):3 with labels left offset 0.6,0.3 font ',7' notitle
set terminal pngcairo size 900,560 font 'sans,10'
set output 'wp_pendulum.png'
replot
