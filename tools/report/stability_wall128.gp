# Draws stability_wall128.svg and stability_wall128.png from the CSV files beside it: gnuplot stability_wall128.gp
set datafile separator ','
set terminal svg size 900,560 dynamic font 'sans,12'
set output 'stability_wall128.svg'
max(a, b) = a > b ? a : b
set title 'wall128: running-bond wall, 128 at the base (8,256 bricks) (60 Hz, 10 iterations)' noenhanced
set xlabel 'simulated time (s)'
set ylabel 'largest drift of any body from its start (m)'
set logscale y
set format y '10^{%L}'
set key left top noenhanced
set grid
set label 1 'drift below 1 um is drawn at 1 um' at graph 0.98, graph 0.04 right font ',9'
plot 'series_wall128.csv' using (strcol(1) eq 'standard+shock' ? $2 : NaN):(max($3, 1e-6)) with lines lw 2 title 'standard+shock', \
     'series_wall128.csv' using (strcol(1) eq 'bullet' ? $2 : NaN):(max($3, 1e-6)) with lines lw 2 title 'bullet'
set terminal pngcairo size 900,560 font 'sans,10'
set output 'stability_wall128.png'
replot
