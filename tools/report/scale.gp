# Draws scale.svg and scale.png from the CSV files beside it: gnuplot scale.gp
set datafile separator ','
set terminal svg size 900,560 dynamic font 'sans,12'
set output 'scale.svg'
set title 'bitstep ms/step against body count (60 Hz, 10 iterations)'
set xlabel 'dynamic bodies'
set ylabel 'ms per step'
set logscale xy
set key left top
set grid
plot 'scale.csv' using (strcol(1) eq 'pyramid' && strcol(2) eq 'awake' ? $3 : NaN):5 with linespoints lw 2 title 'pyramid awake', \
     'scale.csv' using (strcol(1) eq 'pyramid' && strcol(2) eq 'asleep' ? $3 : NaN):5 with linespoints lw 2 title 'pyramid asleep', \
     'scale.csv' using (strcol(1) eq 'columns' && strcol(2) eq 'awake' ? $3 : NaN):5 with linespoints lw 2 title 'columns awake', \
     'scale.csv' using (strcol(1) eq 'columns' && strcol(2) eq 'asleep' ? $3 : NaN):5 with linespoints lw 2 title 'columns asleep'
set terminal pngcairo size 900,560 font 'sans,10'
set output 'scale.png'
replot
