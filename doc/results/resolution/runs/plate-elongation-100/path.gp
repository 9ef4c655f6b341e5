# gnuplot script: the equilibrium path of history.csv
set terminal pngcairo size 900,600 noenhanced
set output 'path.png'
set datafile separator ','
set key top right
set grid
set title 'Equilibrium path: plate-elongation-100'
set xlabel 'displacement (m)'
set ylabel 'reaction (N/m in 2D, N in 3D)'
plot 'history.csv' using "displacement_m":"reaction" with linespoints pt 7 ps 0.4 title 'reaction (one point per converged increment)'
