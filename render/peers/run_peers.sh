#!/bin/sh
# run_peers.sh: the optional peer comparisons of `pp5 bench --peers`.
#   sh render/peers/run_peers.sh CTHEAD_RAW_GZ IMAGE_SIDE OURS_FULL_MS OURS_GAZE_MS \
#      [OURS_MIP_MS WINDOW_LO WINDOW_HI]
# Installs VTK (python3-vtk9), Xvfb and VolPack (libvolpack1-dev) with apt-get
# when run as root, otherwise prints the command; builds volpack_peer.c; runs
# both peers on CThead at the same image size and prints ms/frame and the
# ratios against pp5's native renderer; with the MIP arguments also VTK in
# MIP blend mode over the same window.  Never fails the benchmark run.
set -u
data=$1 side=$2 ours_full=$3 ours_gaze=$4
ours_mip=${5:-} win_lo=${6:-} win_hi=${7:-}
here=$(dirname "$0")
pkgs="python3-vtk9 xvfb xauth libvolpack1-dev"
missing=""
for p in $pkgs; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "ok installed" || missing="$missing $p"
done
if [ -n "$missing" ]; then
    if [ "$(id -u)" = 0 ]; then
        echo "   peers: installing$missing"
        (apt-get update -q && DEBIAN_FRONTEND=noninteractive apt-get install -y -q \
            --no-install-recommends $missing) >/dev/null 2>&1 ||
            { echo "   peers: apt-get failed; skipped"; exit 0; }
    else
        echo "   peers: missing packages; run: sudo apt-get install -y$missing"
        exit 0
    fi
fi
tmp=$(mktemp -d) || exit 0
trap 'rm -rf "$tmp"' EXIT
gzip -dc "$data" > "$tmp/cthead.raw" || { echo "   peers: cannot read $data"; exit 0; }
vp_ms=""
if cc -O2 -o "$tmp/volpack_peer" "$here/volpack_peer.c" -lvolpack -lm 2>"$tmp/cc.log"; then
    vp_ms=$("$tmp/volpack_peer" "$tmp/cthead.raw" 256 256 113 "$side" 15 |
            awk '/volpack_ms_per_frame/ {print $2}')
else
    echo "   peers: volpack_peer did not compile:"; sed 's/^/     /' "$tmp/cc.log"
fi
# Debian's VTK bindings belong to the system interpreter.
py=/usr/bin/python3
vtk_ms=$(xvfb-run -a "$py" "$here/vtk_peer.py" "$tmp/cthead.raw" 256 256 113 "$side" 9 2 |
         awk '/vtk_ms_per_frame/ {print $2}')
echo "   peers on CThead ${side}x${side}, shaded composite, value ramp 350..640 -> 0.8 (ct-skin-ramp), parallel:"
[ -n "$vtk_ms" ] && echo "     VTK vtkFixedPointVolumeRayCastMapper (2 threads, Xvfb): ${vtk_ms} ms/frame" ||
    echo "     VTK: did not run"
[ -n "$vp_ms" ] && echo "     VolPack shear-warp (1 thread, classified volume): ${vp_ms} ms/frame" ||
    echo "     VolPack: did not run"
echo "     pp5 native full resolution: ${ours_full} ms/frame; gaze-directed: ${ours_gaze} ms/frame"
# ratio_line LABEL PEER_MS OURS_MS GOAL: "LABEL: 2.00x faster (goal: GOAL)".
ratio_line() {
    awk -v l="$1" -v v="$2" -v f="$3" -v g="$4" 'BEGIN {
        printf "     %s: %.2fx %s (goal: %s)\n", l, v / f,
               (v / f >= 1 ? "faster" : "(slower: ratio < 1)"), g }'
}
[ -n "$vtk_ms" ] && ratio_line "full resolution vs VTK" "$vtk_ms" "$ours_full" ">= 5x faster"
[ -n "$vp_ms" ] && ratio_line "gaze-directed vs VolPack" "$vp_ms" "$ours_gaze" "no slower"
mip_ms=""
if [ -n "$ours_mip" ]; then
    mip_ms=$(xvfb-run -a "$py" "$here/vtk_peer.py" "$tmp/cthead.raw" 256 256 113 "$side" 9 2 \
             --mip "$win_lo,$win_hi" | awk '/vtk_ms_per_frame/ {print $2}')
    echo "   peers on CThead ${side}x${side}, MIP, grey window ${win_lo}..${win_hi}, parallel:"
    [ -n "$mip_ms" ] && echo "     VTK vtkFixedPointVolumeRayCastMapper MIP (2 threads, Xvfb): ${mip_ms} ms/frame" ||
        echo "     VTK MIP: did not run"
    echo "     pp5 native MIP full resolution: ${ours_mip} ms/frame"
    [ -n "$mip_ms" ] && ratio_line "full-resolution MIP vs VTK MIP" "$mip_ms" "$ours_mip" \
        ">= 5x faster"
fi
# Every comparison of this run side by side, each ratio with its goal.
# row LABEL OURS_MS PEER_MS GOAL_RATIO GOAL_TEXT (an empty PEER_MS: did not run).
row() {
    if [ -z "$3" ]; then
        printf "     %-36s %9s %9s %8s   %-22s %s\n" "$1" "$2" "-" "-" "$5" "peer did not run"
        return
    fi
    awk -v l="$1" -v o="$2" -v p="$3" -v g="$4" -v t="$5" 'BEGIN {
        r = p / o; v = (g == "" ? "(no goal)" : (r >= g ? "met" : "missed"))
        printf "     %-36s %9.1f %9.1f %7.2fx   %-22s %s\n", l, o, p, r, t, v }'
}
echo "   side by side (CThead ${side}x${side}, this run; ratio = peer ms / pp5 ms):"
printf "     %-36s %9s %9s %8s   %-22s %s\n" "comparison" "pp5 ms" "peer ms" "ratio" "goal" "verdict"
row "full resolution vs VTK composite" "$ours_full" "$vtk_ms" 5 ">= 5x faster"
row "gaze-directed vs VTK composite" "$ours_gaze" "$vtk_ms" "" "-"
row "gaze-directed vs VolPack" "$ours_gaze" "$vp_ms" 1 ">= 1x (no slower)"
row "full resolution vs VolPack" "$ours_full" "$vp_ms" "" "-"
[ -n "$ours_mip" ] && row "full-resolution MIP vs VTK MIP" "$ours_mip" "$mip_ms" 5 ">= 5x faster"
echo "     not compared here: meshoptimizer and CGAL (the mesh module's own benchmarks), ParaView"
echo "     (Debian's 5.11 bundles its own VTK and installs beside python3-vtk9, 152 packages; not run)"
exit 0
