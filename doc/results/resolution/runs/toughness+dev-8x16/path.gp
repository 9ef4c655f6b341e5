# gnuplot script: the equilibrium path of history.csv
set terminal pngcairo size 900,600 noenhanced
set output 'path.png'
set datafile separator ','
set key top right
set grid
set title 'Equilibrium path: resolution-toughness+dev-8x16'
set xlabel 'increment'
set ylabel 'boundary stress / sigma_y, load factor'
plot 'history.csv' using "step":"stress_over_sigma_y" with linespoints pt 7 ps 0.4 title 'boundary stress / sigma_y', \
     'history.csv' using "step":"load_factor" with lines dt 2 title 'load factor'
