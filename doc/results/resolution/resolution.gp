# resolution.gp: sigma_failure/sigma_y of the disk at delta = c/1000
# against the particle count, one line per reading of Eq. 118
# (material.break_rule; dashed: with material.yield_rule: deviatoric),
# from resolution.csv (tests/long/resolution_study.sh writes both; run
# in the folder that holds resolution.csv:
# gnuplot resolution.gp), and reference.csv: the elongation rule's 39,200
# and 80,000-particle runs of session 8 (doc/performance.md), the same
# case. Stars: the 10 x 20 disk refined at the tips only (tips.csv), at
# their particle counts. Filled points: the crack ran; open points: the run reached
# path.max_load 2.0 (general yield) without fracture, its peak shown as a
# lower bound of sigma_f.
set datafile separator ","
set terminal pngcairo noenhanced size 860,580 font ",11"
set output "resolution.png"
set title "Disk, delta = c/1000: failure stress against resolution"
set xlabel "particles"
set ylabel "sigma_failure / sigma_y"
set logscale x
set xrange [1200:120000]
set yrange [0:2.2]
set key bottom right
set grid
rows(r) = sprintf("< grep -h '^%s,' resolution.csv reference.csv 2>/dev/null | sort -t, -k4,4n", r)
frac(v) = strcol(8) eq "yes" ? v : 1/0
nofrac(v) = strcol(8) ne "yes" ? v : 1/0
tips(r) = sprintf("< grep -h '^%s,' tips.csv 2>/dev/null | sort -t, -k6,6n", r)
plot rows("elongation") using 4:6 with lines lc rgb "#1f77b4" notitle, \
     rows("elongation") using 4:(frac($6)) with points pt 7 ps 1.4 lc rgb "#1f77b4" \
        title "elongation (Eq. 118: eps_p r0 > delta)", \
     rows("elongation") using 4:(nofrac($6)) with points pt 6 ps 1.4 lc rgb "#1f77b4" \
        title "elongation, no fracture by max_load (general yield)", \
     rows("strain") using 4:6 with lines lc rgb "#d62728" notitle, \
     rows("strain") using 4:(frac($6)) with points pt 5 ps 1.4 lc rgb "#d62728" \
        title "strain (eps_p > delta / L, L = 3.441 mm)", \
     rows("toughness") using 4:6 with lines lc rgb "#2ca02c" notitle, \
     rows("toughness") using 4:(frac($6)) with points pt 9 ps 1.6 lc rgb "#2ca02c" \
        title "toughness (eps_p r0 > delta sqrt(r0 / L))", \
     rows("elongation+dev") using 4:6 with lines dt 2 lc rgb "#9467bd" notitle, \
     rows("elongation+dev") using 4:(frac($6)) with points pt 13 ps 1.5 lc rgb "#9467bd" \
        title "elongation, deviatoric yield reading", \
     rows("toughness+dev") using 4:6 with lines dt 2 lc rgb "#8c564b" notitle, \
     rows("toughness+dev") using 4:(frac($6)) with points pt 11 ps 1.5 lc rgb "#8c564b" \
        title "toughness, deviatoric yield reading", \
     tips("elongation") using 6:8 with points pt 3 ps 2 lc rgb "#1f77b4" \
        title "refined at the tips only (10 x 20 disk, k = 2, 3; tips.csv)", \
     tips("toughness") using 6:8 with points pt 3 ps 2 lc rgb "#2ca02c" notitle, \
     tips("elongation+dev") using 6:8 with points pt 3 ps 2 lc rgb "#9467bd" notitle
