set terminal pngcairo size 720,460 font ',10'
set key outside right
set grid
set output 'bench/charts/pareto.png'
set title 'Speed against accuracy: presymplectic families (graded, perturbed, tower)'
set logscale x
set xlabel 'mean time per instance [s]'
set ylabel 'fraction of wrong discrete answers'
set yrange [-0.05:1.05]
plot 'bench/results/plot/pareto_reference.dat' using 1:2 with points pt 4 ps 2.5 lw 2 title "reference (words, fmpq)", 'bench/results/plot/pareto_certified.dat' using 1:2 with points pt 5 ps 2.5 lw 2 title "certified (words, fmpq)", 'bench/results/plot/pareto_bf100.dat' using 1:2 with points pt 6 ps 2.5 lw 2 title "bin\\_float\\_100 + tol", 'bench/results/plot/pareto_bf50.dat' using 1:2 with points pt 7 ps 2.5 lw 2 title "bin\\_float\\_50 + tol", 'bench/results/plot/pareto_naive.dat' using 1:2 with points pt 8 ps 2.5 lw 2 title "naive double + tol", 'bench/results/plot/pareto_fast.dat' using 1:2 with points pt 9 ps 2.5 lw 2 title "fast (SVD)", 'bench/results/plot/pareto_sympy.dat' using 1:2 with points pt 10 ps 2.5 lw 2 title "sympy (exact)", 'bench/results/plot/pareto_numpy.dat' using 1:2 with points pt 11 ps 2.5 lw 2 title "numpy (SVD)", 'bench/results/plot/pareto_scipy.dat' using 1:2 with points pt 12 ps 2.5 lw 2 title "scipy (pivoted QR)"
set output 'bench/charts/wrong_vs_condition.png'
set title 'Wrong answers against condition (graded tower, planted answer)'
set logscale x
set xlabel 'condition number of the data'
set ylabel 'fraction wrong'
set yrange [-0.05:1.05]
plot 'bench/results/plot/graded_reference.dat' using 1:2 with linespoints lw 2 pt 1 title "reference (words, fmpq)", 'bench/results/plot/graded_certified.dat' using 1:2 with linespoints lw 2 pt 2 title "certified (words, fmpq)", 'bench/results/plot/graded_bf100.dat' using 1:2 with linespoints lw 2 pt 3 title "bin\\_float\\_100 + tol", 'bench/results/plot/graded_bf50.dat' using 1:2 with linespoints lw 2 pt 4 title "bin\\_float\\_50 + tol", 'bench/results/plot/graded_naive.dat' using 1:2 with linespoints lw 2 pt 5 title "naive double + tol", 'bench/results/plot/graded_fast.dat' using 1:2 with linespoints lw 2 pt 6 title "fast (SVD)", 'bench/results/plot/graded_sympy.dat' using 1:2 with linespoints lw 2 pt 7 title "sympy (exact)", 'bench/results/plot/graded_numpy.dat' using 1:2 with linespoints lw 2 pt 8 title "numpy (SVD)", 'bench/results/plot/graded_scipy.dat' using 1:2 with linespoints lw 2 pt 9 title "scipy (pivoted QR)"
set output 'bench/charts/time_vs_size.png'
set title 'Time against size (graded tower, condition 10^2)'
set logscale xy
set xlabel 'N'
set ylabel 'mean time per instance [s]'
set format y '10^{%L}'
set autoscale y
plot 'bench/results/plot/size_reference.dat' using 1:2 with linespoints lw 2 pt 1 title "reference (words, fmpq)  N^{2.5}", 'bench/results/plot/size_certified.dat' using 1:2 with linespoints lw 2 pt 2 title "certified (words, fmpq)  N^{2.5}", 'bench/results/plot/size_bf100.dat' using 1:2 with linespoints lw 2 pt 3 title "bin\\_float\\_100 + tol  N^{2.8}", 'bench/results/plot/size_bf50.dat' using 1:2 with linespoints lw 2 pt 4 title "bin\\_float\\_50 + tol  N^{2.7}", 'bench/results/plot/size_naive.dat' using 1:2 with linespoints lw 2 pt 5 title "naive double + tol  N^{2.4}", 'bench/results/plot/size_fast.dat' using 1:2 with linespoints lw 2 pt 6 title "fast (SVD)  N^{2.6}", 'bench/results/plot/size_sympy.dat' using 1:2 with linespoints lw 2 pt 7 title "sympy (exact)  N^{3.4}", 'bench/results/plot/size_numpy.dat' using 1:2 with linespoints lw 2 pt 8 title "numpy (SVD)  N^{2.3}", 'bench/results/plot/size_scipy.dat' using 1:2 with linespoints lw 2 pt 9 title "scipy (pivoted QR)  N^{1.9}"
set output 'bench/charts/trajectory.png'
set title '4-port (CEF Fig. 6.1): trajectory error against run time'
set logscale xy
set xlabel 'run time [s] (whole process)'
set ylabel 'max relative error of i_L vs analytic'
set format y '10^{%L}'
set format x '%g'
plot 'bench/results/plot/traj_dcad.dat' using 1:2 with linespoints pt 7 lw 2 title 'dcad simulate (exact flow)', '' using 1:2:3 with labels offset 0,-1 font ',7' notitle, \
     'bench/results/plot/traj_ngspice.dat' using 1:2 with linespoints pt 5 lw 2 title 'ngspice', '' using 1:2:3 with labels offset 0,1 font ',7' notitle
set output 'bench/charts/rlc_trajectory.png'
set title 'RLC decks (series RLC, RL step): error against the closed form and run time'
set logscale xy
set xlabel 'run time [s] (whole process, best of 3)'
set ylabel 'max relative error of i_L'
set format y '10^{%L}'
set format x '%g'
plot 'bench/results/plot/rlc_rlc-series_dcad.dat' using 1:2 with linespoints pt 7 lw 2 title 'dcad, series RLC',      'bench/results/plot/rlc_rlc-series_ngspice.dat' using 1:2 with linespoints pt 5 lw 2 title 'ngspice, series RLC', '' using 1:2:3 with labels offset 0,1 font ',7' notitle,      'bench/results/plot/rlc_rl-step_dcad.dat' using 1:2 with linespoints pt 9 lw 2 title 'dcad, RL step',      'bench/results/plot/rlc_rl-step_ngspice.dat' using 1:2 with linespoints pt 11 lw 2 title 'ngspice, RL step', '' using 1:2:3 with labels offset 0,-1 font ',7' notitle
set output 'bench/charts/fast_cad_vs_qr.png'
set title 'Fast CAD against one pivoted QR, one SVD (NxN)'
set logscale xy
set xlabel 'N'
set ylabel 'time [s]'
set format y '10^{%L}'
set format x '%g'
plot 'bench/results/plot/kernel_FastCad.dat' using 1:2 with linespoints lw 2 pt 5 title "FastCad  N^{2.90}", 'bench/results/plot/kernel_ColPivQR.dat' using 1:2 with linespoints lw 2 pt 6 title "ColPivQR  N^{3.16}", 'bench/results/plot/kernel_JacobiSingularValues.dat' using 1:2 with linespoints lw 2 pt 7 title "JacobiSingularValues  N^{3.33}"
