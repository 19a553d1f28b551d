#!/usr/bin/env bash
# Install what brushwork needs on a Debian/Ubuntu machine (apt: Eigen, Clipper, EGL/GL headers and Mesa's
# software renderer, a C++ compiler, CMake, the AR PL UKai reference font for contact sheets, and
# python3-venv where Python's venv lacks pip), make a virtual environment .venv beside this script
# and install the package into it with its test and schema extras, KanjiVG's strokes, trimesh (outline), the font and paint
# extras (a system Python that is externally managed, PEP 668, is never pip-installed into), showing
# the compiler's progress; a second run compiles only what changed. Then it runs the main job:
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
# the build runs in .venv itself, not in a fresh isolated environment: an isolated build brings
# its own CMake, Ninja and pybind11 under a new temporary path each time, which makes CMake
# reconfigure and recompile everything; in .venv the build folder (build/{wheel_tag},
# pyproject.toml) stays valid and a second run compiles only what changed
.venv/bin/python -c "import scikit_build_core, pybind11" 2>/dev/null ||
  .venv/bin/python -m pip install -q "scikit-build-core>=0.8" "pybind11>=2.11"
log=build/install.log
mkdir -p build
echo "building brushwork (the C++ core: a minute or two the first time; the log is $log)" >&2
set +e
.venv/bin/python -m pip install -v --no-build-isolation \
  ".[test,schema,kanjivg,outline,font,paint${BRUSHWORK_EXTRAS:+,$BRUSHWORK_EXTRAS}]" 2>&1 | tee "$log" |
  grep --line-buffered -E '^ *\[ *[0-9]+(/[0-9]+|%)\]|^Successfully installed' | sed -u 's/^ */  /' >&2
status=${PIPESTATUS[0]}
set -e
if [ "$status" -ne 0 ]; then
  tail -n 30 "$log" >&2
  echo "install.sh: the build failed (the whole log is $log)" >&2
  exit "$status"
fi
if [ "${BRUSHWORK_SKIP_DEMO:-0}" != 1 ]; then
  .venv/bin/python -m brushwork render 永和九年 -o yonghe.png
fi
