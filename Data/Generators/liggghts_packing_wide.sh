#!/bin/bash
# A LIGGGHTS packing whose radii span a factor 10 (0.5, 1.5 and 5 mm, mixed by number
# 50 / 30 / 20 %): liggghts_packing.sh with LIGGGHTS_RADII set, and so its time step a
# quarter of the default one (four times the steps for the same 0.4 s of settling),
# inserted at solid fraction 0.2 (at 0.35, 46,329 of 80,000 found a place). 2 of 80,000
# small spheres left the box while the bed formed (through which face was not found), so up
# to 0.1 % may be lost.
#
# Usage: liggghts_packing_wide.sh OUTPUT.vtk [N]   (N default 80000)
set -euo pipefail
n=${2:-80000}
LIGGGHTS_RADII="0.0005 0.0015 0.005" LIGGGHTS_FILL=0.2 LIGGGHTS_MAY_LOSE=$(( n / 1000 )) exec bash "$(cd "$(dirname "$0")" && pwd)/liggghts_packing.sh" "$@"
