#!/usr/bin/env bash
# make demo: skilld with the simulated A1 and the shipped skill library, driven by skillctl the way
# a user would drive a real robot, with no reset anywhere: list the skills, stand, navigate around
# the obstacles of configs/maps/demo.yaml (writing a picture of the planned and the walked path to
# $PICTURE), run the fastest skill forward, backward, left, right, turning left and turning right
# back to back, track a velocity with the skill selector, then stop the server cleanly. Every
# motion starts only from a stand the server has verified.
# Everything stays on this machine (Cyclone on loopback, a partition of its own).
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${BIN_DIR:-build/bin}
library=${LIBRARY:-models/a1_flsd.safetensors}
export CYCLONEDDS_URI=${CYCLONEDDS_URI:-file://$PWD/configs/cyclonedds_loopback.xml}
domain=${DOMAIN:-42}
partition="demo-$$"
ctl=("$bin/skillctl" --domain "$domain" --partition "$partition" --timeout 10)

[ -f "$library" ] || { echo "demo: no skill library at $library (export one with: flsd export RUN -o $library)"; exit 2; }

"$bin/skilld" --backend sim --library "$library" --domain "$domain" --partition "$partition" &
server=$!
trap 'kill -INT $server 2>/dev/null; wait $server' EXIT

echo "== skills in $library"
"${ctl[@]}" list | tee /tmp/flsd_demo_skills.$$
echo "== stand"
"${ctl[@]}" stand
# Among the skills that never fell in the library's evaluations (the longest survival listed;
# skilld refuses the others), the one that goes fastest forward, backward, left and right, and
# turns fastest left and right: columns 2, 3 and 4 of the list are the mean vx, vy and yaw rate.
picks=$(awk 'NR > 1 { if ($7 > longest) longest = $7; row[NR] = $0 }
             END { for (i in row) { split(row[i], f); if (f[7] != longest) continue
                     if (fw == "" || f[2] > fwv) { fw = f[1]; fwv = f[2] }
                     if (bw == "" || f[2] < bwv) { bw = f[1]; bwv = f[2] }
                     if (lw == "" || f[3] > lwv) { lw = f[1]; lwv = f[3] }
                     if (rw == "" || f[3] < rwv) { rw = f[1]; rwv = f[3] }
                     if (lt == "" || f[4] > ltv) { lt = f[1]; ltv = f[4] }
                     if (rt == "" || f[4] < rtv) { rt = f[1]; rtv = f[4] } }
                   print fw, bw, lw, rw, lt, rt }' /tmp/flsd_demo_skills.$$)
rm -f /tmp/flsd_demo_skills.$$
status=0
picture=${PICTURE:-build/demo_navigation.svg}
echo "== navigate to (5, 0) around the obstacles of configs/maps/demo.yaml"
"${ctl[@]}" --quiet goto 5 0 --map configs/maps/demo.yaml --duration 150 --picture "$picture" || status=$?
for k in $picks; do
  # Back to back, as on a real robot: the server stands the robot up between skills and starts
  # the next one only from a verified stand (lying down and standing up again if it must).
  echo "== skill $k for 4 s"
  "${ctl[@]}" --quiet skill "$k" --duration 4 || status=$?
done
echo "== track 0.4 m/s forward for 4 s (the selector chooses the skills)"
"${ctl[@]}" --quiet vel 0.4 0 0 --duration 4 || status=$?
echo "== status"
"${ctl[@]}" status
exit $status
