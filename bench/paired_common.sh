# Sourced by the paired drivers (umesh_paired.sh, mesh_play_paired.sh, whole_paired.sh).
# mesh_view SIZE OPACITY: sets VIEW to the view and transfer function of bench/umesh_vs_vtk.sh at
# SIZE with the opacity points OPACITY (haze: 0.02:0.004,0.15:0.004,0.5:0.03,1.1:0.12; blobs:
# 0.02:0,0.15:0,0.5:0.03,1.1:0.12).
mesh_view() {
  VIEW=(--field density --range 0.02,1.1 --unit-distance 0.01 --camera-pos 2.3,1.6,2.9 --camera-at 0.5,0.5,0.5
    --camera-up 0,1,0 --fov 35 --background 0.06,0.06,0.08 --tf viridis --opacity "$2" --size "$1")
}
# The header line of a paired run.
paired_header() {
  echo "# $(date -u +%FT%TZ) $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg)"
  echo "# base $1, new $2, dataset $3, $4 rounds"
}
# stats: reads numbers, one per line, and prints their median [min..max] with three decimals.
stats() { sort -g | awk '{ v[NR] = $1 } END {
  m = (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2
  printf "%.3f [%.3f..%.3f]", m, v[1], v[NR] }'; }
# round_ratios RUNS KEY COLUMN: from RUNS' lines "round binary key ...", the per-round ratio
# base/new of COLUMN on the lines whose key is KEY, one per line (for stats).
round_ratios() { awk -v k="$2" -v c="$3" '$3 == k { v[$1 " " $2] = $c } END {
  for (r in v) { split(r, p, " "); if (p[2] == "base") print v[r] / v[p[1] " new"] } }' "$1"; }
