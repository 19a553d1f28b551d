#!/usr/bin/env bash
# Install what brushwork needs on a Debian/Ubuntu machine (apt: Eigen, Clipper, EGL/GL headers and Mesa's
# software renderer, a C++ compiler, CMake, the AR PL UKai reference font for contact sheets, and
# python3-venv where Python's venv lacks pip), make a virtual environment .venv beside this script
# and install the package into it with its test extra, KanjiVG's strokes, trimesh (outline), the font and paint extras (a system Python
# that is externally managed, PEP 668, is never pip-installed into), then run the main job:
# 永和九年 written by the brush into yonghe.png.
# Set BRUSHWORK_SKIP_DEMO=1 to install only, BRUSHWORK_EXTRAS to add extras (e.g. ray); PYTHON names the interpreter the venv is made from
# (default python3).
set -euo pipefail
cd "$(dirname "$0")"
PYTHON="${PYTHON:-python3}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
pkgs="libeigen3-dev libpolyclipping-dev libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri g++ cmake fonts-arphic-ukai"
# Debian's Python makes a venv with pip only when python3-venv (ensurepip) is installed
"$PYTHON" -c "import ensurepip, venv" >/dev/null 2>&1 || pkgs="$pkgs python3-venv"
missing=""
for p in $pkgs; do dpkg -s "$p" >/dev/null 2>&1 || missing="$missing $p"; done
if [ -n "$missing" ]; then
  echo "installing with apt:$missing" >&2
  $SUDO apt-get update -qq
  $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $missing
fi
if [ ! -x .venv/bin/python ] || ! .venv/bin/python -m pip --version >/dev/null 2>&1; then
  "$PYTHON" -m venv --clear .venv
fi
.venv/bin/python -m pip install -q ".[test,kanjivg,outline,font,paint${BRUSHWORK_EXTRAS:+,$BRUSHWORK_EXTRAS}]"
if [ "${BRUSHWORK_SKIP_DEMO:-0}" != 1 ]; then
  .venv/bin/python -m brushwork render 永和九年 -o yonghe.png
fi
