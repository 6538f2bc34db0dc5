#!/usr/bin/env bash
# gate_dam_break beside the same column released at once: the case as built in, and a copy without
# its [[wall]] (the gate). Writes the surge front and the pressure at the far wall's foot of both to
# OUT/gate_vs_instant.png (with gnuplot: apt-get install gnuplot-nox) and prints the front's times and
# the first impact.
#
#   scripts/gate_vs_instant.sh [OUT [RUN OPTIONS]]   (default OUT: out/gate_vs_instant; SLUICE=path/to/sluice)
#   e.g. scripts/gate_vs_instant.sh out/gvi --threads 1
set -euo pipefail
cd "$(dirname "$0")/.."
sluice=${SLUICE:-build/release/sluice}
out=${1:-out/gate_vs_instant}
[ $# -gt 0 ] && shift
mkdir -p "$out"
"$sluice" init --from gate_dam_break --force "$out/gate.toml" >/dev/null
# The instant release: the same file without the gate's [[wall]] and its [wall.translation] table.
awk '/^\[\[wall\]\]/ {skip = 1} /^\[\[probe\]\]/ {skip = 0} !skip' "$out/gate.toml" |
  sed 's/^name = "gate_dam_break"/name = "instant_dam_break"/' >"$out/instant.toml"
for run in gate instant; do
  rm -rf "${out:?}/$run"
  "$sluice" run "$out/$run.toml" -o "$out/$run" -q "$@" >/dev/null
done

# The front: the time it first passes each of 0.3, 0.4, ... 0.8 m (its particle's centre + dx/2).
echo "front (m)   gate (s)   instant (s)"
for x in 0.3 0.4 0.5 0.6 0.7; do
  line="$x"
  for run in gate instant; do
    t=$(awk -F, -v x="$x" 'NR > 1 && $2 + 0.0025 >= x {print $1; exit}' "$out/$run/probes/front.csv")
    line="$line   $(printf "%.3f" "${t:-nan}")"
  done
  echo "$line"
done
# The first impact on the far wall: the largest pressure before 0.5 s, and when.
for run in gate instant; do
  awk -F, -v run="$run" 'NR > 1 && $1 < 0.5 && $2 > p {p = $2; t = $1}
    END {printf "%s: largest far-wall pressure before 0.5 s %.0f Pa at t = %.4f s\n", run, p, t}' \
    "$out/$run/probes/wall_pressure.csv"
done

if command -v gnuplot >/dev/null; then
  gnuplot <<GNUPLOT
set terminal pngcairo size 1200,420 font "sans,11"
set output "$out/gate_vs_instant.png"
set datafile separator ","
set multiplot layout 1,2
set key bottom right
set xlabel "t (s)"
set ylabel "front (m)"
set xrange [0:0.35]
set yrange [0.15:0.82]
set title "The surge front along the floor"
plot "$out/gate/probes/front.csv" every ::1 using 1:(\$2 + 0.0025) with lines lw 2 title "gate lifted (Sun et al. 2019)", \
     "$out/instant/probes/front.csv" every ::1 using 1:(\$2 + 0.0025) with lines lw 2 dt 2 title "released at once"
set ylabel "p (kPa)"
set key top right
set xrange [0.25:0.6]
set yrange [*:*]
set title "Pressure at the far wall's foot, 1 cm above the floor"
plot "$out/gate/probes/wall_pressure.csv" every ::1 using 1:(\$2 / 1000) with lines lw 1.5 title "gate lifted", \
     "$out/instant/probes/wall_pressure.csv" every ::1 using 1:(\$2 / 1000) with lines lw 1.5 dt 2 title "released at once"
unset multiplot
GNUPLOT
  echo "figure: $out/gate_vs_instant.png"
fi
