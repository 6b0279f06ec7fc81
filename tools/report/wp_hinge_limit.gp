# Draws wp_hinge_limit.svg and wp_hinge_limit.png from the CSV files beside it: gnuplot wp_hinge_limit.gp
set datafile separator ','
set terminal svg size 900,560 dynamic font 'sans,12'
set output 'wp_hinge_limit.svg'
max(a, b) = a > b ? a : b
floor_error = 1e-12
set title 'hinge_limit: 1 m arm on a hinge limited to -30..45 degrees, started at 20 rad/s toward +45 (no force input), 3 s (quick: 1 s)' noenhanced
set xlabel 'cost: wall-clock ms per simulated second'
set ylabel 'error: max overshoot past a limit (degrees)'
set logscale xy
set format y '10^{%L}'
set key outside right noenhanced
set grid
set label 1 'dt in {1/30 .. 1/240} x iterations in {1, 2, 4, 8, 16, 32}; errors below 1e-12 drawn at 1e-12' at graph 0, graph -0.13 font ',9'
set bmargin 6
plot 'wp_hinge_limit.csv' using (strcol(1) eq 'standard' ? $4 : NaN):(max($5, floor_error)) with points pt 5 ps 1.2 title 'standard', \
     'wp_hinge_limit.csv' using (strcol(1) eq 'standard+shock' ? $4 : NaN):(max($5, floor_error)) with points pt 6 ps 1.2 title 'standard+shock', \
     'wp_hinge_limit.csv' using (strcol(1) eq 'guendelman' ? $4 : NaN):(max($5, floor_error)) with points pt 7 ps 1.2 title 'guendelman', \
     'wp_hinge_limit.csv' using (strcol(1) eq 'guendelman+shock' ? $4 : NaN):(max($5, floor_error)) with points pt 8 ps 1.2 title 'guendelman+shock', \
     'wp_hinge_limit.csv' using (strcol(1) eq 'bullet' ? $4 : NaN):(max($5, floor_error)) with points pt 9 ps 1.2 title 'bullet', \
     'wp_hinge_limit_front.csv' using 1:(max($2, floor_error)) with lines lw 2 lc 'black' title 'Pareto front', \
     'wp_hinge_limit_front.csv' using 1:(max($2, floor_error)):3 with labels left offset 0.6,0.3 font ',7' notitle
set terminal pngcairo size 900,560 font 'sans,10'
set output 'wp_hinge_limit.png'
replot
