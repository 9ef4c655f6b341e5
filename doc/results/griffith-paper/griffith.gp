# gnuplot script: sigma_failure/sigma_y against sqrt(delta/c)
set terminal pngcairo size 800,600 noenhanced
set output 'griffith.png'
set datafile separator ','
set key top left
set xlabel 'sqrt(delta / c)'
set ylabel 'sigma_failure / sigma_yield'
set title 'Griffith check: paper-griffith (slope 57.219687, intercept -0.28803607, R^2 0.99471836)'
set xrange [0:*]
set yrange [0:*]
plot 'griffith.csv' every ::1 using (strcol(4) eq "yes" ? $2 : 1/0):3 with points pt 7 ps 1.5 title 'fractured', \
     'griffith.csv' every ::1 using (strcol(4) eq "no" ? $2 : 1/0):3 with points pt 6 ps 1.5 title 'no fracture (peak load)', \
     'griffith.csv' every ::1 using (strcol(4) eq "stalled" ? $2 : 1/0):3 with points pt 4 ps 1.5 title 'no fracture: solve stalled (last settled load)', \
     -0.2880360692 + 57.21968726*x title 'least-squares fit' lw 2, \
     17.84124116*x title 'nominal Griffith sqrt(2/(pi eps_y)) x' dt 2
