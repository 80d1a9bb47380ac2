# The plots of `make results` (scripts/results.sh runs this inside docs/results/ on the .dat
# files scripts/results_tables.py writes).
set terminal pngcairo size 900,520 font "sans,11"
set grid ytics
set key top left

set output "fig6_fetches.png"
set title "Figure 6: cell fetches per frame (256x256, memory 1/8 and 1/27)"
set style data histograms
set style histogram clustered gap 1
set style fill solid 0.85 border -1
set ylabel "cell fetches"
set xtics rotate by -20
set key top center
plot "fig6.dat" using 2:xtic(1) title "Max Work", "" using 3 title "Cell Tree (paper's rule)", \
     "" using 4 title "Cell Tree (rollout)", "" using 6 title "optimum, or best schedule found", "" using 5 title "proven bound"
set key top left

set output "anim_fetches.png"
set title "brain\\_mirrors camera path: frame i follows frame i-1's Cell Tree"
set style data linespoints
set xtics norotate
set xlabel "frame"
plot "anim.dat" using 1:2 title "Max Work, 1/8" lw 2, "" using 1:3 title "Cell Tree, 1/8" lw 2, \
     "" using 1:4 title "lower bound, 1/8" dt 2, \
     "" using 1:5 title "Max Work, 1/27" lw 2, "" using 1:6 title "Cell Tree, 1/27" lw 2, \
     "" using 1:7 title "lower bound, 1/27" dt 2

set output "fig7_tree_vs_rays.png"
set title "Figure 7: Cell Tree nodes against rays (every frame of every run)"
set style data points
set xlabel "rays in the frame"
set ylabel "Cell Tree nodes"
set logscale xy
plot "fig7.dat" using 1:2 title "frames" pt 7 ps 1.2, x/100 title "rays / 100" dt 2

set output "fig10_tree_sizes.png"
set title "Figure 10: brain\\_mirrors, rays and Cell Tree nodes against image size"
set style data linespoints
set xlabel "image size (pixels a side)"
set ylabel "count (log)"
unset logscale x
set logscale y
set xtics ("100x100" 100, "256x256" 256, "512x512" 512)
plot "fig10.dat" using 1:2 title "rays, 1/8" lw 2, "" using 1:3 title "nodes, 1/8" lw 2, \
     "" using 1:4 title "rays, 1/27" lw 2, "" using 1:5 title "nodes, 1/27" lw 2
