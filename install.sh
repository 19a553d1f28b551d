#!/usr/bin/env bash
# Install what brushwork needs on a Debian/Ubuntu machine (apt: Eigen, EGL/GL headers and Mesa's
# software renderer, a C++ compiler; pip: the package with its test extra), then run the main job.
# Set BRUSHWORK_SKIP_DEMO=1 to install only.
set -euo pipefail
cd "$(dirname "$0")"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
pkgs="libeigen3-dev libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri g++ cmake python3-pip"
missing=""
for p in $pkgs; do dpkg -s "$p" >/dev/null 2>&1 || missing="$missing $p"; done
if [ -n "$missing" ]; then
  echo "installing with apt:$missing" >&2
  $SUDO apt-get update -qq
  $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $missing
fi
python3 -m pip install -q ".[test]"
if [ "${BRUSHWORK_SKIP_DEMO:-0}" != 1 ]; then
  python3 -m brushwork gallery -o gallery.png
fi
