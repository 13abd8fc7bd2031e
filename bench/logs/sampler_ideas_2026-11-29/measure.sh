#!/bin/bash
# Measurements of three sampler ideas (prototypes, not kept). BASE: code of 7f72138 (built at 26a6b2b,
# the same sources); PYR: base + pyramid_closed_form.diff; PROTO: base + opacity_adaptive_prototype.diff
# + iso_records_prototype.diff (off unless ISO_RECORDS / ADAPT are set).
set -u
BASE=/tmp/v_new PYR=/tmp/v_pyr PROTO=/tmp/v_proto OUT=$1
H=$(cat /tmp/haze_args); B=$(cat /tmp/blobs_args)
T=/tmp/vtk2/tets_1e6.vs M=/tmp/vtk2/mixed_5e5.vs
C="/usr/bin/python3 /work/main/bench/png_compare.py"
H128=${H/512x512/128x128}
cg() { valgrind --tool=callgrind --callgrind-out-file=/dev/null "$@" 2>&1 | grep -E "I +refs"; }
for v in $BASE $PYR $PROTO; do $v render $M $H --size 64x64 -o /tmp/si/warm.png >/dev/null 2>&1; $v render $T $H --size 64x64 -o /tmp/si/warm.png >/dev/null 2>&1; done
{
echo "## 1. pyramid closed form: mixed haze, callgrind 128x128 (base, then closed form)"
cg $BASE render $M $H128 -o /tmp/si/cg_b.png
cg $PYR render $M $H128 -o /tmp/si/cg_p.png
echo "## images 512x512, closed form vs base (haze, blobs)"
$BASE render $M $H -o /tmp/si/mh_b.png >/dev/null 2>&1; $PYR render $M $H -o /tmp/si/mh_p.png >/dev/null 2>&1
$BASE render $M $B -o /tmp/si/mb_b.png >/dev/null 2>&1; $PYR render $M $B -o /tmp/si/mb_p.png >/dev/null 2>&1
$C /tmp/si/mh_p.png /tmp/si/mh_b.png; $C /tmp/si/mb_p.png /tmp/si/mb_b.png
echo "## paired-timer: A = closed form, B = base, mixed haze 512x512"
paired-timer -n 10 --warmup 1 --timeout 400 --vs "$BASE render $M $H -o /tmp/si/fb_b.png" -- $PYR render $M $H -o /tmp/si/fb_a.png 2>&1
echo
echo "## 2. element maps precomputed (ISO_RECORDS=1) against the same binary without, mixed haze"
cg $PROTO render $M $H128 -o /tmp/si/x0.png
ISO_RECORDS=1 cg $PROTO render $M $H128 -o /tmp/si/x1.png
for i in 1 2 3 4 5; do
  echo "off: $($PROTO render $M $H -o /tmp/si/i0.png 2>&1 | grep -o 'render 512.*CPU time)')"
  echo "on:  $(ISO_RECORDS=1 $PROTO render $M $H -o /tmp/si/i1.png 2>&1 | grep -o 'render 512.*CPU time)')"
done
cmp /tmp/si/i0.png /tmp/si/i1.png && echo "same PNG bytes"
echo
echo "## 3. opacity-adaptive steps (ADAPT=max factor), image against rate 8 (converged) and VTK"
for mesh in T M; do
  eval f=\$$mesh
  $BASE render $f $H --rate 8 -o /tmp/si/${mesh}_r8.png 2>&1 | grep -o 'render 512.*samples,'
  for ad in 0 2 4; do
    for i in 1 2 3; do echo "$mesh haze ADAPT=$ad: $(ADAPT=$ad $PROTO render $f $H -o /tmp/si/${mesh}_a$ad.png 2>&1 | grep -o 'render 512.*samples,')"; done
    echo "  vs rate 8: $($C /tmp/si/${mesh}_a$ad.png /tmp/si/${mesh}_r8.png)"
  done
done
echo "  tets vs VTK: ADAPT=0 $($C /tmp/si/T_a0.png /tmp/vtk2/tets_1e6_haze_vtk.png)"
echo "  tets vs VTK: ADAPT=2 $($C /tmp/si/T_a2.png /tmp/vtk2/tets_1e6_haze_vtk.png)"
} > $OUT/measurements.txt 2>&1
