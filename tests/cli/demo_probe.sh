#!/usr/bin/env bash
# probe through the ABRs equals the brute-force sum over all cells at 10^4 random points, on both demos.
source "$(dirname "$0")/common.bash"
cd "$WORK"
for demo in jet cosmo; do
  "$VS" demo $demo --cells 100000 --steps 2 -o $demo -q
  random_points $demo 10000 7 >pts.txt
  for field in $("$VS" info $demo --json | awk '/"name":/ { gsub(/[",]/, "", $2); print $2 }'); do
    "$VS" probe $demo --field "$field" --step 1 --points pts.txt >abr.txt
    "$VS" probe $demo --field "$field" --step 1 --points pts.txt --brute-force >ref.txt
    echo -n "$demo $field: "
    compare_probes abr.txt ref.txt || fail "$demo $field: ABR probe differs from brute force"
  done
done
