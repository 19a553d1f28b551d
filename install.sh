#!/usr/bin/env bash
# Install what brushwork needs on a Debian/Ubuntu machine (apt: Eigen, EGL/GL headers and Mesa's
# software renderer, a C++ compiler, the AR PL UKai reference font for contact sheets; pip: the
# package with its test extra and KanjiVG's strokes), then run the main job: 永和九年 written by the
# brush into yonghe.png.
# Set BRUSHWORK_SKIP_DEMO=1 to install only.
set -euo pipefail
cd "$(dirname "$0")"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
pkgs="libeigen3-dev libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri g++ cmake python3-pip fonts-arphic-ukai"
missing=""
for p in $pkgs; do dpkg -s "$p" >/dev/null 2>&1 || missing="$missing $p"; done
if [ -n "$missing" ]; then
  echo "installing with apt:$missing" >&2
  $SUDO apt-get update -qq
  $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $missing
fi
python3 -m pip install -q ".[test,kanjivg]"
if [ "${BRUSHWORK_SKIP_DEMO:-0}" != 1 ]; then
  python3 -m brushwork render 永和九年 -o yonghe.png
fi
