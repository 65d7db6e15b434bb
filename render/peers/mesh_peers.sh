#!/bin/sh
# mesh_peers.sh: builds the mesh peers of `pp5 bench mesh --peers`.
#   sh render/peers/mesh_peers.sh OUTDIR
# Installs meshoptimizer (libmeshoptimizer-dev), CGAL (libcgal-dev, with
# libeigen3-dev, which CGAL's Garland-Heckbert policies need) and g++ with
# apt-get when run as root, otherwise prints the command; compiles
# meshopt_peer.c and cgal_peer.cpp into OUTDIR.  Prints "built NAME" for each
# peer that compiled; never exits non-zero (the benchmark must not fail).
set -u
out=$1
here=$(dirname "$0")
pkgs="libmeshoptimizer-dev libcgal-dev libeigen3-dev g++"
missing=""
for p in $pkgs; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "ok installed" || missing="$missing $p"
done
if [ -n "$missing" ]; then
    if [ "$(id -u)" = 0 ]; then
        echo "   peers: installing$missing" >&2
        (apt-get update -q && DEBIAN_FRONTEND=noninteractive apt-get install -y -q \
            --no-install-recommends $missing) >/dev/null 2>&1 ||
            { echo "   peers: apt-get failed; skipped" >&2; exit 0; }
    else
        echo "   peers: missing packages; run: sudo apt-get install -y$missing" >&2
        exit 0
    fi
fi
if cc -O2 -o "$out/meshopt_peer" "$here/meshopt_peer.c" -lmeshoptimizer 2>"$out/meshopt_cc.log"
then
    echo "built meshopt_peer"
else
    echo "   peers: meshopt_peer did not compile:" >&2; sed 's/^/     /' "$out/meshopt_cc.log" >&2
fi
# CGAL is header-only here; one translation unit takes about a minute to compile.
if g++ -std=c++17 -O2 -DNDEBUG -I/usr/include/eigen3 -o "$out/cgal_peer" "$here/cgal_peer.cpp" \
    -lgmp -lmpfr 2>"$out/cgal_cc.log"
then
    echo "built cgal_peer"
else
    echo "   peers: cgal_peer did not compile:" >&2; sed 's/^/     /' "$out/cgal_cc.log" | head -20 >&2
fi
exit 0
