#!/usr/bin/env bash
# Builds the catkin workspace (.ws/) from the packages at the top of the repo, in Release, -j2.
# Usage: scripts/build.sh [extra catkin_make args]
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
export PATH=/usr/bin:/bin:/usr/sbin:/sbin:$PATH   # Debian's python3, never pyenv's
case "${1:-}" in -h|--help) sed -n '2,3s/^# \{0,1\}//p' "$0"; exit 0 ;; esac
WS="$ROOT/.ws"
mkdir -p "$WS/src"
declare -A PKGS=([edge_slam_msgs]=edge_slam_msgs [edge_slam_common]=edge_slam_common
                 [edge_slam_mobile]=edge_slam_mobile [edge_slam_edge]=edge_slam_edge
                 [edge_slam_tests]=test)
for name in "${!PKGS[@]}"; do
  ln -sfn "$ROOT/${PKGS[$name]}" "$WS/src/$name"
done
[ -e "$WS/src/CMakeLists.txt" ] || ln -s /usr/share/catkin/cmake/toplevel.cmake "$WS/src/CMakeLists.txt"
cd "$WS"
# shellcheck disable=SC1091
source /opt/ros/*/setup.bash 2>/dev/null || true
catkin_make -DCMAKE_BUILD_TYPE=Release -DPYTHON_EXECUTABLE=/usr/bin/python3 \
  -DCATKIN_ENABLE_TESTING=ON -j"${BUILD_JOBS:-2}" "$@"
