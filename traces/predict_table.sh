#!/bin/sh
# predict_table.sh: replay the recorded traces in ../shared/data/gaze with and
# without prediction and print one table line per source and predictor.
#
#   traces/predict_table.sh [FRAME_MS] [TRACKER_MS] [DISPLAY_MS]   (from the repo root, after make)
#
# Frame times come from the built-in constant source of `pp5 replay` unless
# COST is set: COST=machine replays every frame on the emulated Pixel-Planes 5
# (slow: ~0.1 s of host time per frame), and then MAX_FRAMES=N caps the frames
# per recording and ONLY="name1|name2" picks sources by name.  Machine
# settings go through the frame source's options, e.g. a work division:
#   COST=machine:set=division=NAME MAX_FRAMES=40 traces/predict_table.sh
# The table of the closing note of issue 16 is
#   COST=machine MAX_FRAMES=40 traces/predict_table.sh
# PREDICTORS="none landing" picks predictors (default: all five).
# Defaults: 66.667 ms frames (the paper's 15 frames/s), tracker 33 ms,
# display 17 ms, i.e. the replay defaults.  Each source's recordings are
# replayed one by one and their frames pooled: mean and 95th percentile of the
# error at display time (over frames where it is measurable), the share of
# display time with the true gaze inside the 6 deg radius, and the mean frame
# time.
set -eu
G=${PP5_SHARED_DATA:-../shared/data}/gaze
FRAME=${1:-66.667}
TRK=${2:-33}
DISP=${3:-17}
PP5=${PP5_BIN:-./pp5}
COST=${COST:-constant:$FRAME}
LIMIT=${MAX_FRAMES:+--max-frames $MAX_FRAMES}
ONLY=${ONLY:-.}
PREDICTORS=${PREDICTORS:-none linear alphabeta kalman landing}
[ -d "$G" ] || { echo "predict_table.sh: $G is absent (no recorded data here)" >&2; exit 1; }
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT

FRAMES="all frames"
[ -n "${MAX_FRAMES:-}" ] && FRAMES="the first $MAX_FRAMES frames of each recording"
echo "# $("$PP5" version 2>/dev/null | head -n 1); cost $COST; tracker $TRK ms, display $DISP ms;" \
     "$FRAMES"
printf '%-34s %7s %-14s %9s %9s %8s %9s\n' source seconds predict mean_deg p95_deg inside frame_ms
row() {   # name, file list
    name=$1; shift
    echo "$name" | grep -E -q "$ONLY" || return 0
    secs=$(for f in "$@"; do zcat "$f" | sed -n 's/^# duration_s: \([0-9.]*\).*/\1/p'; done |
           awk '{s += $1} END {printf "%.0f", s}')
    i=0
    for f in "$@"; do
        i=$((i + 1))
        "$PP5" trace import "$f" --format shared --out "$TMP/t$i.trace" > /dev/null
    done
    for pred in $PREDICTORS; do
        : > "$TMP/all.csv"
        k=0
        while [ "$k" -lt "$i" ]; do
            k=$((k + 1))
            "$PP5" replay "$TMP/t$k.trace" --cost "$COST" $LIMIT --tracker-latency-ms "$TRK" \
                --display-latency-ms "$DISP" --predict "$pred" --timing-only \
                --csv "$TMP/f.csv" > /dev/null 2>&1
            tail -n +2 "$TMP/f.csv" >> "$TMP/all.csv"
        done
        awk -F, '$13 != "nan" {print $13}' "$TMP/all.csv" | sort -g > "$TMP/err.txt"
        n=$(wc -l < "$TMP/err.txt")
        p95=$(awk -v n="$n" 'NR == int(n * 0.95 + 0.999999) {print; exit}' "$TMP/err.txt")
        mean=$(awk '{s += $1} END {if (NR) printf "%.2f", s / NR}' "$TMP/err.txt")
        inside=$(awk -F, '{a += $14; b += $15} END {if (b > 0) printf "%.1f%%", 100 * a / b}' \
                 "$TMP/all.csv")
        frame=$(awk -F, '{s += $16} END {if (NR) printf "%.1f", s / NR}' "$TMP/all.csv")
        printf '%-34s %7s %-14s %9s %9.2f %8s %9s\n' "$name" "$secs" "$pred" "$mean" "$p95" \
               "$inside" "$frame"
    done
}
row "eyelink_sr_samples reading 500Hz" "$G"/eyelink_sr_samples/trace/*Remote500.tsv.gz
row "eyelink_sr_samples saccade tmpl" "$G"/eyelink_sr_samples/trace/mono[0-9]*.tsv.gz \
    "$G"/eyelink_sr_samples/trace/bino[0-9]*.tsv.gz
row "eyelink_sr_samples fixation tmpl" "$G"/eyelink_sr_samples/trace/*Remote250.tsv.gz
row "gazecom video 250Hz" "$G"/gazecom/trace/*.tsv.gz
row "lund2013 dots (pursuit) 500Hz" "$G"/lund2013/trace/dots/*.tsv.gz
row "lund2013 img 500Hz" "$G"/lund2013/trace/img/*.tsv.gz
row "lund2013 video 500Hz" "$G"/lund2013/trace/video/*.tsv.gz
row "mcsorley2006 saccades 250Hz" "$G"/mcsorley2006/trace/*.tsv.gz
row "sptool_eyelink 1000Hz" "$G"/sptool_eyelink/trace/*.tsv.gz
row "i2mc_tx300 300Hz" "$G"/i2mc_tx300/trace/*.tsv.gz
