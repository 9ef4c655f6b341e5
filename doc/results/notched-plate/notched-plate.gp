# notched-plate.gp: the load-displacement curves and the damage of the
# notched plate (data/cases/notched-plate-{pmb,state,fibre,threebody}.yaml)
# from the runs in np-*/. Reaction x dx: the force on Peridigm's
# layer of thickness dx = 0.05/60 m. Run: gnuplot notched-plate.gp
set datafile separator ','
set terminal pngcairo size 1500,480 font ',10'
set output 'notched-plate.png'
set multiplot layout 1,3
dx = 0.05 / 60
set title 'Notched plate 60 x 60: top-grip reaction'
set xlabel 'top-grip displacement u_y (mm)'
set ylabel 'reaction x dx (N)'
set key top left
set grid
set xtics 0.004
plot 'np-pmb/history.csv' using ($13 * 1e3):($12 * dx) skip 1 with linespoints pt 7 ps 0.6 title 'bond (PMB, s_0 = 1e-3)', \
     'np-state/history.csv' using ($13 * 1e3):($12 * dx) skip 1 with linespoints pt 5 ps 0.6 title 'state ({/Symbol n} = 0.3, s_0 = 1e-3)', \
     'np-fibre/history.csv' using ($13 * 1e3):($12 * dx) skip 1 with linespoints pt 9 ps 0.6 title 'fibre ({/Symbol e}_y = 1e-3, {/Symbol d} = {/Symbol e}_y dx)', \
     'np-threebody/history.csv' using ($13 * 1e3):($12 * dx) skip 1 with linespoints pt 11 ps 0.6 title 'three-body ({/Symbol n} = 0.25, G_c = 129.6 J/m^2)', \
     '-' using 1:2 with points pt 6 ps 1.5 lc rgb 'black' title 'Peridigm, elastic (868.485 N)'
0.015,868.485
e
set title 'bond (PMB): damage at the end of the run'
set xlabel 'x (mm)'
set ylabel 'y (mm)'
set size ratio -1
set cbrange [0:0.6]
set cblabel 'damage'
unset key
unset grid
plot 'np-pmb/particles.csv' using ($2 * 1e3):($3 * 1e3):6 skip 1 with points pt 5 ps 0.45 lc palette
set title 'three-body: damage at the end of the run'
plot 'np-threebody/particles.csv' using ($2 * 1e3):($3 * 1e3):6 skip 1 with points pt 5 ps 0.45 lc palette
unset multiplot
