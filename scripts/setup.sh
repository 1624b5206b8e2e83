#!/usr/bin/env bash
# One-command setup on Debian 12: installs the Debian packages (ROS 1 from Debian, Ceres,
# OpenCV, Eigen, Xvfb...), a Python venv with evo + matplotlib that also sees Debian's ROS Python, builds the catkin workspace in
# Release, then generates the embedded synthetic dataset and its vocabulary.
# Idempotent: every step is skipped when its inputs have not changed, so a second run is quick.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
help_on_request "$@"
cd "$ROOT"

# ---- 1. Debian packages --------------------------------------------------------------------
mapfile -t PKGS < <(sed -e 's/#.*//' scripts/debian-packages.txt | tr ' ' '\n' | sed '/^$/d')
missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null || die "missing Debian packages: ${missing[*]} (run as root or install them)"
    SUDO=sudo
  fi
  say "installing ${#missing[@]} Debian packages: ${missing[*]}"
  $SUDO apt-get update -q || die "apt-get update failed"
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}" \
    || die "apt-get install failed for: ${missing[*]}"
else
  say "Debian packages: all ${#PKGS[@]} present"
fi

# ---- 2. Python venv for PyPI tools (evo, matplotlib) --------------------------------------
# --system-site-packages: the venv python also sees Debian's rospy, rostest, rosbag and the
# workspace's messages, so rospy tests and tools run in it with evo's API (scripts/bench/ate.py).
# Debian modules compiled against Debian's numpy (cv2) stay on /usr/bin/python3.
VENV_FLAGS="--system-site-packages"
venv_stamp="$STAMPS/venv.$( (cat scripts/requirements-venv.txt; echo "$VENV_FLAGS") | sha256sum | cut -c1-16)"
if [ ! -f "$venv_stamp" ] || [ ! -x .venv/bin/evo_ape ]; then
  say "creating .venv ($VENV_FLAGS) with $(tr '\n' ' ' < scripts/requirements-venv.txt)"
  /usr/bin/python3 -m venv --clear $VENV_FLAGS .venv
  .venv/bin/pip install -q --upgrade pip
  .venv/bin/pip install -q -r scripts/requirements-venv.txt || die "pip install into .venv failed"
  .venv/bin/python3 -c "import evo, scipy, psutil, rospy, rosbag" || die ".venv cannot import evo, scipy, psutil and rospy together"
  rm -f "$STAMPS"/venv.*; touch "$venv_stamp"
else
  say "Python venv: up to date"
fi

# ---- 3. Build (catkin_make, Release, -j2; incremental) ------------------------------------
say "building the catkin workspace (.ws, Release)"
bash scripts/build.sh > "$STAMPS/build.log" 2>&1 || { tail -40 "$STAMPS/build.log" >&2; die "build failed (full log: .stamps/build.log)"; }

# ---- 4. Embedded default dataset + vocabulary ---------------------------------------------
bash scripts/make_dataset.sh
