#!/usr/bin/env bash
# Re-make every image the README shows, with the commands the README names under each.
# Run from the repository root with brushwork installed (after install.sh: .venv/bin/brushwork).
set -euo pipefail
cd "$(dirname "$0")/.."
bw="${BRUSHWORK:-.venv/bin/brushwork}"
py="${PYTHON:-.venv/bin/python}"
# a fresh work folder: batch and font resume from what a folder already holds
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
"$bw" render 永和九年 -o docs/yonghe.png
"$bw" gallery -o docs/gallery.png --views docs/brush_view.png
"$bw" batch --chars "$(cat docs/sheet_chars.txt)" --size 256 --out "$work/sheet" \
  --sheet docs/sheet.png --no-progress
# 3-D outlines: the meshes of $BRUSHWORK_MESHES (default the shared test meshes) in two styles
"$py" -m brushwork.outline3d.sheet --meshes "${BRUSHWORK_MESHES:-../shared/data/meshes}" \
  --styles baimiao,xieyi --size 400 -o docs/outlines.png
# a line set in a brushwork font by headless Chromium (needs chromium and chromium-driver)
fonts="$work/font"
mkdir -p "$fonts"
"$bw" font --chars 永和九年岁在癸丑暮春 -o "$fonts/line.woff2" --no-progress
"$py" -m brushwork.font.browser "$fonts/line.woff2" 永和九年岁在癸丑暮春 docs/font_line.png --px 96
# the page of `brushwork paint`, as its test in headless Chromium paints it (needs the paint extra and chromium)
BRUSHWORK_SCREENSHOT=docs/paint.png "$py" -m pytest -q tests/test_paint.py -k paints_with_a_pen
