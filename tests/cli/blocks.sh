#!/usr/bin/env bash
# The block raycaster and blackbody optics from the command line (paper 004): every integrator and
# reconstruction, the density scales, bench integrators, and bad options exiting 2.
source "$(dirname "$0")/common.bash"
cd "$WORK"
"$VS" demo cosmo --cells 30000 --steps 1 -o cos -q
out=$("$VS" render cos --optics blackbody --size 64x48 -o auto.png)
echo "$out" | grep -q 'blackbody optics' || fail "blackbody render does not say its optics: $out"
"$VS" render cos --optics blackbody --density-scale linear --size 64x48 -o linear.png >/dev/null
"$VS" render cos --optics blackbody --density-scale log --reconstruction nearest --size 64x48 -o log.pfm >/dev/null
"$VS" render cos --integrator blocks --field density --log --size 64x48 -o tf.png >/dev/null
for f in auto.png linear.png tf.png; do [ "$(head -c 4 $f | tail -c 3)" = PNG ] || fail "$f is not a PNG"; done
cmp -s auto.png linear.png && fail "--density-scale linear renders the same image as the log default"
"$VS" render --demo cosmo --cells 20000 --optics blackbody --size 48x48 -o demo.png | grep -q 'blackbody' \
  || fail "render --demo cosmo --optics blackbody"
"$VS" bench integrators cos --size 48 --repeat 1 >bench.txt
for row in 'abr (tent)' 'blocks nearest' 'blocks trilinear'; do grep -q "$row" bench.txt || fail "bench integrators has no $row row: $(cat bench.txt)"; done
expect_bad_input "bad density scale" render cos --optics blackbody --density-scale cubic -o x.png
expect_bad_input "no temperature field" render cos --optics blackbody --temperature-field nope -o x.png
expect_bad_input "negative absorption" render cos --optics blackbody --absorption -1 -o x.png
expect_bad_input "bad reconstruction" render cos --integrator blocks --reconstruction cubic -o x.png
expect_bad_input "bad bench size" bench integrators cos --size 4x4
echo "blocks: ok"
