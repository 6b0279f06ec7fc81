# Draws wp_heavy_on_light.svg and wp_heavy_on_light.png from the CSV files beside it: gnuplot wp_heavy_on_light.gp
set datafile separator ','
set terminal svg size 900,560 dynamic font 'sans,12'
set output 'wp_heavy_on_light.svg'
max(a, b) = a > b ? a : b
floor_error = 1e-12
set title 'heavy_on_light: 1,000 kg cube dropped 1 m on a 1 kg cube' noenhanced
set xlabel 'cost: wall-clock ms per simulated second'
set ylabel 'error: max penetration (m)'
set logscale xy
set format y '10^{%L}'
set key outside right noenhanced
set grid
set label 1 'dt in {1/30 .. 1/240} x iterations in {1, 2, 4, 8, 16, 32}; errors below 1e-12 drawn at 1e-12' at graph 0, graph -0.13 font ',9'
set bmargin 6
plot 'wp_heavy_on_light.csv' using (strcol(1) eq 'standard' ? $4 : NaN):(max($5, floor_error)) with points pt 5 ps 1.2 title 'standard', \
     'wp_heavy_on_light.csv' using (strcol(1) eq 'standard+shock' ? $4 : NaN):(max($5, floor_error)) with points pt 6 ps 1.2 title 'standard+shock', \
     'wp_heavy_on_light.csv' using (strcol(1) eq 'guendelman' ? $4 : NaN):(max($5, floor_error)) with points pt 7 ps 1.2 title 'guendelman', \
     'wp_heavy_on_light.csv' using (strcol(1) eq 'guendelman+shock' ? $4 : NaN):(max($5, floor_error)) with points pt 8 ps 1.2 title 'guendelman+shock', \
     'wp_heavy_on_light.csv' using (strcol(1) eq 'bullet' ? $4 : NaN):(max($5, floor_error)) with points pt 9 ps 1.2 title 'bullet', \
     'wp_heavy_on_light_front.csv' using 1:(max($2, floor_error)) with lines lw 2 lc 'black' title 'Pareto front', \
     'wp_heavy_on_light_front.csv' using 1:(max($2, floor_error)):3 with labels left offset 0.6,0.3 font ',7' notitle
set terminal pngcairo size 900,560 font 'sans,10'
set output 'wp_heavy_on_light.png'
replot
